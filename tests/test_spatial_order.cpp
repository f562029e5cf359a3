/// granular::spatialOrder (Morton cell order) and granular::reordered.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "granular/spatial_order.hpp"

using namespace granular;

TEST(SpatialOrder, VisitsTheCellsOfACubeInZOrder) {
  // One point in each cell of a 2 × 2 × 2 block, listed in reverse Z-order: the order must
  // list them as x fastest, then y, then z (bit 0 of the code is x, bit 1 y, bit 2 z).
  std::vector<Vec3> points;
  for (int code = 7; code >= 0; --code) {
    points.emplace_back(0.5 + (code & 1), 0.5 + ((code >> 1) & 1), 0.5 + ((code >> 2) & 1));
  }
  const std::vector<std::size_t> order = spatialOrder(points, 1.0);
  ASSERT_EQ(order.size(), 8u);
  for (std::size_t k = 0; k < 8; ++k) EXPECT_EQ(order[k], 7 - k) << "position " << k;
}

TEST(SpatialOrder, KeepsEachCellTogetherAndTiesInTheirOrder) {
  // A layer-by-layer lattice of 4 × 4 × 4 cells with 2 points each: after ordering, the two
  // points of a cell are neighbours in the list, and in their old order.
  std::vector<Vec3> points;
  for (int z = 0; z < 4; ++z) {
    for (int y = 0; y < 4; ++y) {
      for (int x = 0; x < 4; ++x) {
        points.emplace_back(x + 0.25, y + 0.25, z + 0.25);
        points.emplace_back(x + 0.75, y + 0.75, z + 0.75);
      }
    }
  }
  const std::vector<std::size_t> order = spatialOrder(points, 1.0);
  std::vector<std::size_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::size_t> identity(points.size());
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_EQ(sorted, identity);  // a permutation
  for (std::size_t k = 0; k < order.size(); k += 2) {
    EXPECT_EQ(order[k] + 1, order[k + 1]) << "cell at position " << k;
    EXPECT_EQ(order[k] % 2, 0u);
  }
  // Locality: in the lattice order, the point above (z + 1) is 32 indices away; in Z-order
  // the 8 cells of each 2 × 2 × 2 block are consecutive, and the cell above is 4 cells on.
  std::vector<std::size_t> where(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) where[order[k]] = k;
  for (int z = 0; z < 4; z += 2) {
    for (int y = 0; y < 4; ++y) {
      for (int x = 0; x < 4; ++x) {
        const std::size_t below = 2 * (x + 4 * y + 16 * z), above = below + 32;
        const std::size_t gap =
            where[above] > where[below] ? where[above] - where[below] : where[below] - where[above];
        EXPECT_EQ(gap, 8u) << x << " " << y << " " << z;
      }
    }
  }
}

TEST(SpatialOrder, FarOrNonFinitePositionsStillGetACell) {
  const std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(1e300, 0, 0), Vec3(std::nan(""), 0, 0),
                                    Vec3(0.1, 0, 0)};
  const std::vector<std::size_t> order = spatialOrder(points, 1.0);
  ASSERT_EQ(order.size(), 4u);
  EXPECT_EQ(order[0], 0u);
  EXPECT_EQ(order[1], 3u);  // same cell as point 0, after it
}

TEST(SpatialOrder, RefusesABadCellSize) {
  const std::vector<Vec3> points = {Vec3(0, 0, 0)};
  EXPECT_THROW(spatialOrder(points, 0.0), std::invalid_argument);
  EXPECT_THROW(spatialOrder(points, -1.0), std::invalid_argument);
  EXPECT_THROW(spatialOrder(points, std::nan("")), std::invalid_argument);
}

TEST(SpatialOrder, ReorderedMovesEveryArrayTogether) {
  Particles p;
  for (int i = 0; i < 5; ++i) {
    p.add(Vec3(i, 0, 0), 0.01 * (i + 1), 1000.0 + i, Vec3(0, i, 0));
    p.angularVelocity.back() = Vec3(0, 0, i);
  }
  const std::vector<std::size_t> order = {3, 0, 4, 1, 2};
  const Particles q = reordered(p, order);
  ASSERT_EQ(q.size(), 5u);
  for (std::size_t k = 0; k < 5; ++k) {
    const std::size_t i = order[k];
    EXPECT_EQ(q.position[k], p.position[i]);
    EXPECT_EQ(q.velocity[k], p.velocity[i]);
    EXPECT_EQ(q.angularVelocity[k], p.angularVelocity[i]);
    EXPECT_EQ(q.radius[k], p.radius[i]);
    EXPECT_EQ(q.mass[k], p.mass[i]);
  }
  EXPECT_THROW(reordered(p, {0, 1, 2}), std::invalid_argument);        // too short
  EXPECT_THROW(reordered(p, {0, 1, 2, 3, 3}), std::invalid_argument);  // not a permutation
  EXPECT_THROW(reordered(p, {0, 1, 2, 3, 9}), std::invalid_argument);  // out of range
}
