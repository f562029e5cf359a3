/// The box cut into bricks (granular/bricks.hpp): the counts from the rank count and the box's
/// shape, ownership that leaves no point without an owner, the ghost ranks of a point, and the
/// balance of particle counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>
#include <stdexcept>

#include "granular/bricks.hpp"
#include "granular/communicator.hpp"

using namespace granular;

TEST(Bricks, CountsCutTheLeastArea) {
  // The paper's box, 0.64 × 0.64 × 1.1 m: a z cut costs 0.64² = 0.41 m², an x or y cut
  // 0.64·1.1 = 0.70 m². 2 and 3 ranks cut z; 4 cut y and z once (1.11 m²) rather than z three
  // times (1.23 m²) or x and y (1.41 m²).
  const Vec3 lo(0, 0, 0), hi(0.64, 0.64, 1.1);
  EXPECT_EQ(Bricks(1, lo, hi).counts(), (std::array<int, 3>{1, 1, 1}));
  EXPECT_EQ(Bricks(2, lo, hi).counts(), (std::array<int, 3>{1, 1, 2}));
  EXPECT_EQ(Bricks(3, lo, hi).counts(), (std::array<int, 3>{1, 1, 3}));
  EXPECT_EQ(Bricks(4, lo, hi).counts(), (std::array<int, 3>{1, 2, 2}));
  // A flat bed, 4 × 4 × 0.5 m: 4 ranks cut x and y (2·2 + 0 = 4 m² against 3·2 = 6 m² along one).
  EXPECT_EQ(Bricks(4, lo, Vec3(4, 4, 0.5)).counts(), (std::array<int, 3>{2, 2, 1}));
  // A cube: ties go to z, then y.
  EXPECT_EQ(Bricks(2, lo, Vec3(1, 1, 1)).counts(), (std::array<int, 3>{1, 1, 2}));
  EXPECT_EQ(Bricks(8, lo, Vec3(1, 1, 1)).counts(), (std::array<int, 3>{2, 2, 2}));
  // A prime count along the long axis.
  EXPECT_EQ(Bricks(7, lo, Vec3(10, 1, 1)).counts(), (std::array<int, 3>{7, 1, 1}));
  EXPECT_THROW(Bricks(0, lo, hi), std::invalid_argument);
  EXPECT_THROW(Bricks(2, lo, Vec3(1, 0, 1)), std::invalid_argument);
}

TEST(Bricks, EveryPointHasOneOwnerWhoseBrickHoldsIt) {
  const Vec3 lo(-1, 0, 0), hi(1, 2, 3);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.5, 1.5);  // inside and beyond the box
  for (int ranks : {1, 2, 3, 4, 6, 8, 12}) {
    const Bricks b(ranks, lo, hi);
    ASSERT_EQ(b.ranks(), ranks);
    std::vector<int> seen(ranks, 0);
    for (int k = 0; k < 2000; ++k) {
      const Vec3 x(lo.x() + u(rng) * 2, lo.y() + u(rng) * 2, lo.z() + u(rng) * 3);
      const int r = b.owner(x);
      ASSERT_GE(r, 0);
      ASSERT_LT(r, ranks);
      const auto [blo, bhi] = b.bounds(r);
      for (int a = 0; a < 3; ++a) {
        EXPECT_LE(blo[a], x[a]);
        EXPECT_LT(x[a], bhi[a]);
      }
      ++seen[r];
    }
    for (int r = 0; r < ranks; ++r) EXPECT_GT(seen[r], 0) << r << " of " << ranks;
  }
  // On a cut plane: the brick above.
  const Bricks two(2, Vec3(0, 0, 0), Vec3(1, 1, 2));
  EXPECT_EQ(two.owner(Vec3(0.5, 0.5, 1.0)), 1);
  EXPECT_EQ(two.owner(Vec3(0.5, 0.5, std::nextafter(1.0, 0.0))), 0);
}

TEST(Bricks, GhostRanksAreTheBricksWithinTheHalo) {
  // 2 × 2 × 1 bricks over the unit square: a point near the centre is a ghost of the three
  // other bricks, one near an edge's middle of one, one deep inside a brick of none.
  const Bricks b(4, Vec3(0, 0, 0), Vec3(2, 2, 0.1));
  ASSERT_EQ(b.counts(), (std::array<int, 3>{2, 2, 1}));
  const double halo = 0.1;
  const Vec3 centre(0.95, 0.95, 0.05);
  EXPECT_EQ(b.owner(centre), 0);
  EXPECT_EQ(b.ghostRanks(centre, halo), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(b.ghostRanks(Vec3(1.05, 0.5, 0.05), halo), (std::vector<int>{0}));
  EXPECT_TRUE(b.ghostRanks(Vec3(0.5, 0.5, 0.05), halo).empty());
  // The definition: r holds x as a ghost exactly when x lies within the halo of r's brick.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 2.0);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 x(u(rng), u(rng), 0.05);
    const std::vector<int> ghosts = b.ghostRanks(x, halo);
    for (int r = 0; r < 4; ++r) {
      const auto [lo, hi] = b.bounds(r);
      bool near = true;
      for (int a = 0; a < 3; ++a) near = near && x[a] >= lo[a] - halo && x[a] < hi[a] + halo;
      const bool listed = std::find(ghosts.begin(), ghosts.end(), r) != ghosts.end();
      EXPECT_EQ(listed, near && r != b.owner(x)) << x.transpose() << " rank " << r;
    }
  }
}

TEST(Bricks, BalanceEqualisesTheSlabsWhateverTheOrder) {
  // A bed packed at the bottom of a tall box: even cuts leave the top bricks empty; balanced
  // ones give each slab a quarter of the particles, for any order of the positions.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> p;
  for (int k = 0; k < 4000; ++k) p.emplace_back(u(rng), u(rng), 0.8 * u(rng) * u(rng));
  Bricks b(4, Vec3(0, 0, 0), Vec3(1, 1, 3));
  ASSERT_EQ(b.counts(), (std::array<int, 3>{1, 1, 4}));
  b.balance(p, 0.05);
  std::vector<int> count(4, 0);
  for (const Vec3& x : p) ++count[b.owner(x)];
  for (int r = 0; r < 4; ++r) EXPECT_NEAR(count[r], 1000, 1) << r;
  std::shuffle(p.begin(), p.end(), rng);
  Bricks again(4, Vec3(0, 0, 0), Vec3(1, 1, 3));
  again.balance(p, 0.05);
  EXPECT_EQ(again.cuts(2), b.cuts(2));
  // A minimum width the box cannot give keeps the cuts; one it can is respected.
  Bricks narrow(4, Vec3(0, 0, 0), Vec3(1, 1, 3));
  narrow.balance(p, 1.0);
  EXPECT_EQ(narrow.cuts(2), (std::vector<double>{0.75, 1.5, 2.25}));
  Bricks wide(4, Vec3(0, 0, 0), Vec3(1, 1, 3));
  wide.balance(p, 0.3);
  double below = 0;
  for (double c : wide.cuts(2)) {
    EXPECT_GE(c - below, 0.3 - 1e-12);
    below = c;
  }
  EXPECT_GE(3.0 - below, 0.3 - 1e-12);
}

TEST(Bricks, RebalancedCountsEachRanksOwnAndCutsNearTheQuantiles) {
  // The bed of the last test, cut evenly first (the top bricks empty), then rebalanced from the
  // positions (one process: every position its own): each slab near a quarter, each cut within
  // two bins' width (2 · 3 m / 4096) of balance()'s (which cuts halfway between two positions,
  // this one on a bin's edge), the same cuts for any order, and the original map unchanged.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> p;
  for (int k = 0; k < 4000; ++k) p.emplace_back(u(rng), u(rng), 0.8 * u(rng) * u(rng));
  const std::unique_ptr<Communicator> one = singleProcess();
  Bricks even(4, Vec3(0, 0, 0), Vec3(1, 1, 3));
  const auto moved = std::dynamic_pointer_cast<const Bricks>(even.rebalanced(p, *one));
  ASSERT_NE(moved, nullptr);
  EXPECT_EQ(even.cuts(2), (std::vector<double>{0.75, 1.5, 2.25}));
  std::vector<int> count(4, 0);
  for (const Vec3& x : p) ++count[moved->owner(x)];
  for (int r = 0; r < 4; ++r) EXPECT_NEAR(count[r], 1000, 40) << r;
  Bricks exact(4, Vec3(0, 0, 0), Vec3(1, 1, 3));
  exact.balance(p, 0.0);
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_NEAR(moved->cuts(2)[k], exact.cuts(2)[k], 2 * 3.0 / 4096);
  std::shuffle(p.begin(), p.end(), rng);
  const auto again = std::dynamic_pointer_cast<const Bricks>(even.rebalanced(p, *one));
  EXPECT_EQ(again->cuts(2), moved->cuts(2));
}
