/// A sphere's contacts with a triangle mesh (docs/physics.md §2.20): one contact over a flat
/// region however it is cut, exactly above the sphere at every position, on the triangles'
/// edges and corners too; one contact, turning smoothly, over a convex ridge; one per side in a
/// corner; one inside a triangulated cylinder; and the defects a mesh is refused for, by triangle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "granular/triangle_mesh.hpp"
#include "mesh_contact.hpp"
#include "mesh_fixtures.hpp"
#include "triangle_grid.hpp"

using namespace granular;
using granular::testing::flatGrid;

namespace {

constexpr double kR = 0.03;  // [m]

/// Appends the quad abcd (counter-clockwise seen from its front) as two triangles.
void addQuad(TriangleMesh& m, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const auto base = std::uint32_t(m.vertex.size());
  m.vertex.insert(m.vertex.end(), {a, b, c, d});
  m.triangle.push_back({base, base + 1, base + 2});
  m.triangle.push_back({base, base + 2, base + 3});
}

/// Merges vertices at the same place, so that quads added apart share their edges.
TriangleMesh welded(const TriangleMesh& m) {
  TriangleMesh out;
  std::vector<std::uint32_t> index;
  for (const Vec3& v : m.vertex) {
    std::uint32_t k = 0;
    while (k < out.vertex.size() && (out.vertex[k] - v).norm() > 1e-12) ++k;
    if (k == out.vertex.size()) out.vertex.push_back(v);
    index.push_back(k);
  }
  for (const auto& t : m.triangle) out.triangle.push_back({index[t[0]], index[t[1]], index[t[2]]});
  return out;
}

std::vector<std::uint32_t> allTriangles(const TriangleMesh& m) {
  std::vector<std::uint32_t> all(m.triangle.size());
  for (std::size_t t = 0; t < all.size(); ++t) all[t] = std::uint32_t(t);
  return all;
}

std::vector<MeshContact> contactsOf(const TriangleMesh& m, const MeshTopology& topology,
                                    const Vec3& x) {
  std::vector<MeshContact> out;
  const std::vector<std::uint32_t> all = allTriangles(m);
  meshContacts(m, topology, all, x, kR, out);
  return out;
}

MeshTopology soundTopology(const TriangleMesh& m) {
  std::vector<MeshDefect> defects;
  MeshTopology topology = meshTopology(m, false, defects);
  EXPECT_TRUE(defects.empty()) << defects.front().triangle << ": " << defects.front().what;
  return topology;
}

}  // namespace

TEST(MeshContact, OverAFlatRegionOfTwoEightOrTwoHundredTrianglesASphereHasOneContactStraightBelow) {
  // Over the interior, on every edge and at every corner of the cut, from above and below:
  // one contact, at the height, along ±z, below the centre; 2, 8 and 200 triangles.
  const double height = kR - 1e-4;
  std::mt19937_64 draws(7);
  std::uniform_real_distribution<double> inside(0.05, 0.95);
  for (int n : {1, 2, 10}) {
    const TriangleMesh m = flatGrid(n);
    ASSERT_EQ(m.triangle.size(), std::size_t(2 * n * n));
    const MeshTopology topology = soundTopology(m);
    std::vector<Vec3> at;
    for (int j = 0; j <= 2 * n; ++j) {
      for (int i = 0; i <= 2 * n; ++i) at.push_back(Vec3(0.5 * i / n, 0.5 * j / n, 0));
    }
    for (int k = 0; k < 200; ++k) {
      const double u = inside(draws), v = inside(draws);
      at.push_back(Vec3(u, v, 0));
      at.push_back(Vec3(u, std::round(v * n) / n, 0));  // on a cut along x
      at.push_back(Vec3(u, u, 0));                      // on the squares' diagonals
    }
    for (const Vec3& p : at) {
      for (double side : {1.0, -1.0}) {
        // Pressed in by 0.3 % and by 15 % of the radius: the neighbours' edges are then within
        // reach, their normals up to 32° off.
        for (double h : {height, 0.85 * kR}) {
          const Vec3 x = p + side * h * Vec3::UnitZ();
          const std::vector<MeshContact> c = contactsOf(m, topology, x);
          ASSERT_EQ(c.size(), 1u) << n << " triangles² at " << x.transpose();
          EXPECT_NEAR(c[0].distance, h, 1e-12 * h);
          EXPECT_LT((c[0].normal - side * Vec3::UnitZ()).norm(), 1e-12) << x.transpose();
          EXPECT_LT((c[0].point - p).norm(), 1e-12);
        }
      }
    }
  }
}

TEST(MeshContact, BeyondAnOpenRimTheContactIsWithTheRim) {
  const TriangleMesh m = flatGrid(2);
  const MeshTopology topology = soundTopology(m);
  const Vec3 offset = Vec3(-0.6, 0, 0.8) * (kR - 1e-4);
  for (const Vec3& p : {Vec3(0, 0.3, 0), Vec3(0, 0.5, 0), Vec3(0, 0, 0)}) {
    const std::vector<MeshContact> c = contactsOf(m, topology, p + offset);
    ASSERT_EQ(c.size(), 1u) << p.transpose();
    EXPECT_LT((c[0].point - p).norm(), 1e-12);
    EXPECT_LT((c[0].normal - offset.normalized()).norm(), 1e-12);
  }
}

TEST(MeshContact, OverAConvexRidgeOneContactTurnsSmoothlyFromFaceToFace) {
  // A roof: two planks meeting at the ridge y = 0, sloping down 15° on either side. A sphere
  // moving across it at a fixed height has one contact all the way, its normal turning from one
  // face's to the other's through the ridge's, never by more than its path allows in a step.
  const double slope = 15.0 * std::numbers::pi / 180.0;
  const double dy = std::cos(slope), dz = -std::sin(slope);
  TriangleMesh raw;
  addQuad(raw, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, dy, dz), Vec3(0, dy, dz));
  addQuad(raw, Vec3(0, -dy, dz), Vec3(1, -dy, dz), Vec3(1, 0, 0), Vec3(0, 0, 0));
  const TriangleMesh m = welded(raw);
  const MeshTopology topology = soundTopology(m);
  for (const auto& normal : topology.normal) EXPECT_GT(normal.z(), 0.9);  // outward, up
  Vec3 last = Vec3::Zero();
  const double step = 1e-4;
  for (double y = -0.05; y <= 0.05; y += step) {
    const Vec3 x(0.5, y, kR - 1e-3 - std::abs(y) * std::tan(slope));
    const std::vector<MeshContact> c = contactsOf(m, topology, x);
    ASSERT_EQ(c.size(), 1u) << "y = " << y;
    if (!last.isZero()) {
      EXPECT_LT((c[0].normal - last).norm(), 3.0 * step / kR) << y;
    }
    last = c[0].normal;
  }
}

TEST(MeshContact, InACornerASphereTouchesEachSideOnce) {
  // A floor (z = 0) and a wall (x = 0) of two triangles each, sharing the edge along y.
  TriangleMesh raw;
  addQuad(raw, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0));
  addQuad(raw, Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 1, 1), Vec3(0, 0, 1));
  const TriangleMesh m = welded(raw);
  const MeshTopology topology = soundTopology(m);
  const double d = kR - 1e-3;
  std::vector<MeshContact> c = contactsOf(m, topology, Vec3(d, 0.5, d));
  ASSERT_EQ(c.size(), 2u);
  EXPECT_LT(std::min((c[0].normal - Vec3::UnitX()).norm(), (c[1].normal - Vec3::UnitX()).norm()),
            1e-12);
  EXPECT_LT(std::min((c[0].normal - Vec3::UnitZ()).norm(), (c[1].normal - Vec3::UnitZ()).norm()),
            1e-12);
  // Out over the floor, the wall's edge is not a second contact.
  c = contactsOf(m, topology, Vec3(0.5, 0.5, d));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_LT((c[0].normal - Vec3::UnitZ()).norm(), 1e-12);
}

TEST(MeshContact, InsideATriangulatedCylinderASphereHasOneContactAtEveryAzimuth) {
  // 36 facets of 10°: a sphere pressed 10 % of its radius into the wall touches two facets'
  // planes at once near each fold, and they are one surface, so one contact, the nearer.
  constexpr int kFacets = 36;
  const double radius = 0.2;
  TriangleMesh raw;
  auto rim = [&](int k, double z) {
    const double a = 2.0 * std::numbers::pi * k / kFacets;
    return Vec3(radius * std::cos(a), radius * std::sin(a), z);
  };
  for (int k = 0; k < kFacets; ++k)
    addQuad(raw, rim(k, 0), rim(k + 1, 0), rim(k + 1, 1), rim(k, 1));
  const TriangleMesh m = welded(raw);
  const MeshTopology topology = soundTopology(m);
  const double apothem = radius * std::cos(std::numbers::pi / kFacets);
  for (int k = 0; k <= 200; ++k) {
    const double a = 2.0 * std::numbers::pi / kFacets * (k / 100.0);
    const Vec3 out(std::cos(a), std::sin(a), 0);
    const Vec3 x = (apothem - 0.9 * kR) * out + 0.5 * Vec3::UnitZ();
    const std::vector<MeshContact> c = contactsOf(m, topology, x);
    ASSERT_EQ(c.size(), 1u) << "azimuth " << a;
    EXPECT_LT(c[0].normal.dot(-out), 1.0 + 1e-12);
    EXPECT_GT(c[0].normal.dot(-out), std::cos(std::numbers::pi / kFacets) - 1e-12);
  }
}

TEST(MeshContact, ANeighbourListsTrianglesOfAPointAreEveryTriangleWithinTheLimit) {
  // A closed box of 12 triangles and a cylinder of 36 facets: points all around them, limits
  // from well inside the grid's reach to it. The search passes over triangles whose plane is too
  // far and looks only in the point's cell; it must find what a look at every triangle finds.
  constexpr double kReach = 0.05;
  TriangleMesh box;
  const Vec3 lo(0, 0, 0), hi(0.3, 0.2, 0.1);
  auto corner = [&](int k) {
    return Vec3(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  };
  addQuad(box, corner(0), corner(2), corner(3), corner(1));
  addQuad(box, corner(4), corner(5), corner(7), corner(6));
  addQuad(box, corner(0), corner(1), corner(5), corner(4));
  addQuad(box, corner(2), corner(6), corner(7), corner(3));
  addQuad(box, corner(0), corner(4), corner(6), corner(2));
  addQuad(box, corner(1), corner(3), corner(7), corner(5));
  TriangleMesh cylinder;
  for (int k = 0; k < 36; ++k) {
    auto rim = [&](int j, double z) {
      const double a = 2.0 * std::numbers::pi * j / 36;
      return Vec3(0.1 * std::cos(a), 0.1 * std::sin(a), z);
    };
    addQuad(cylinder, rim(k, 0), rim(k + 1, 0), rim(k + 1, 0.2), rim(k, 0.2));
  }
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const TriangleMesh& raw : {box, cylinder}) {
    const TriangleMesh m = welded(raw);
    const MeshTopology topology = soundTopology(m);
    const TriangleGrid grid = binTriangles(m, kReach, 0.04);
    int near = 0, far = 0;
    std::vector<std::uint32_t> found;
    for (int k = 0; k < 20000; ++k) {
      const Vec3 x(-0.15 + 0.6 * unit(random), -0.15 + 0.5 * unit(random),
                   -0.08 + 0.36 * unit(random));
      const double limit = kReach * (0.2 + 0.8 * unit(random));
      std::vector<std::uint32_t> every;
      for (std::uint32_t t = 0; t < m.triangle.size(); ++t) {
        const auto& v = m.triangle[t];
        const Vec3 c = closestOnTriangle(m.vertex[v[0]], m.vertex[v[1]], m.vertex[v[2]], x).point;
        if ((x - c).norm() < limit) every.push_back(t);
      }
      found.clear();
      trianglesWithin(m, topology, grid, x, limit, found);
      std::sort(found.begin(), found.end());
      ASSERT_EQ(found, every) << "at (" << x.transpose() << "), limit " << limit;
      (every.empty() ? far : near) += 1;
    }
    EXPECT_GT(near, 1000);  // both answers are tried often
    EXPECT_GT(far, 1000);
  }
}

TEST(MeshContact, ADefectiveMeshIsReportedByTriangleAndWhat) {
  // A closed tetrahedron is sound; each defect names its triangle.
  TriangleMesh tetrahedron;
  tetrahedron.vertex = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  tetrahedron.triangle = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  std::vector<MeshDefect> defects;
  meshTopology(tetrahedron, true, defects);
  EXPECT_TRUE(defects.empty());
  auto defectsOf = [](const TriangleMesh& m, bool closed) {
    std::vector<MeshDefect> found;
    meshTopology(m, closed, found);
    return found;
  };
  auto says = [](const std::vector<MeshDefect>& found, std::size_t triangle, const char* what) {
    for (const MeshDefect& d : found) {
      if (d.triangle == triangle && d.what.find(what) != std::string::npos) return true;
    }
    return false;
  };
  TriangleMesh inverted = tetrahedron;
  std::swap(inverted.triangle[2][0], inverted.triangle[2][1]);
  EXPECT_TRUE(says(defectsOf(inverted, true), 2, "inverted"));
  TriangleMesh open = tetrahedron;
  open.triangle.pop_back();
  EXPECT_TRUE(says(defectsOf(open, true), 0, "open"));
  EXPECT_TRUE(defectsOf(open, false).empty());  // an open surface, where one is allowed
  TriangleMesh flat = tetrahedron;
  flat.vertex.push_back(Vec3(2, 0, 0));
  flat.triangle.push_back({0, 1, 4});
  EXPECT_TRUE(says(defectsOf(flat, false), 4, "zero area"));
  TriangleMesh fin = tetrahedron;
  fin.vertex.push_back(Vec3(1, 1, 1));
  fin.triangle.push_back({0, 4, 1});
  EXPECT_TRUE(says(defectsOf(fin, false), 4, "shared by 3 triangles"));
  TriangleMesh beyond = tetrahedron;
  beyond.triangle.push_back({0, 1, 9});
  EXPECT_TRUE(says(defectsOf(beyond, false), 4, "vertex index beyond"));
  TriangleMesh notFinite = tetrahedron;
  notFinite.vertex[3] = Vec3(0, 0, std::nan(""));
  EXPECT_TRUE(says(defectsOf(notFinite, false), 1, "not finite"));
}
