/// Walls as the particle view draws them (app/gui/wall_drawing.hpp): how many triangles and
/// outline segments each shape gives, and where their corners lie.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "granular/triangle_mesh.hpp"
#include "granular/wall_mesh.hpp"
#include "mesh_fixtures.hpp"
#include "wall_drawing.hpp"

namespace granular::gui {
namespace {

/// Distance from the axis through `base` along unit `axis`, and position along it [m].
struct AxialPosition {
  double radius, along;
};
AxialPosition axial(const Vec3& x, const Vec3& base, const Vec3& axis) {
  const Vec3 d = x - base;
  const double along = d.dot(axis);
  return {(d - along * axis).norm(), along};
}

Wall frustum(const Vec3& base, const Vec3& axis, double length, double radiusStart,
             double radiusEnd) {
  Wall w;
  w.shape = WallShape::Frustum;
  w.point = base;
  w.normal = axis.normalized();
  w.length = length;
  w.radiusStart = radiusStart;
  w.radiusEnd = radiusEnd;
  return w;
}

/// The unit cube [0, 1]³ as 12 triangles, counter-clockwise seen from outside.
TriangleMesh cube() {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertex.push_back(Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangle.push_back({q[0], q[1], q[2]});
    m.triangle.push_back({q[0], q[2], q[3]});
  }
  return m;
}

/// An open tube of `facets` flat sides about z: radius 1, height 1, no caps.
TriangleMesh facetedTube(int facets) {
  TriangleMesh m;
  for (int k = 0; k < facets; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / facets;
    m.vertex.push_back(Vec3(std::cos(angle), std::sin(angle), 0.0));
    m.vertex.push_back(Vec3(std::cos(angle), std::sin(angle), 1.0));
  }
  for (int k = 0; k < facets; ++k) {
    const std::uint32_t a = 2 * k, b = 2 * ((k + 1) % facets);
    m.triangle.push_back({a, b, b + 1});
    m.triangle.push_back({a, b + 1, a + 1});
  }
  return m;
}

Wall meshWall(TriangleMesh body, const Vec3& origin = Vec3::Zero()) {
  Wall w;
  w.shape = WallShape::Mesh;
  w.point = origin;
  w.mesh = poseMesh(std::make_shared<const TriangleMesh>(std::move(body)), origin, Vec3::UnitZ(),
                    Vec3::UnitX());
  return w;
}

TEST(WallDrawing, InfinitePlanesAreLeftToTheBoxEdges) {
  Wall plane;  // the default shape
  plane.normal = Vec3(0.0, 0.0, 1.0);
  const WallDrawing d = wallDrawing(std::vector<Wall>{plane, plane});
  EXPECT_TRUE(d.triangles.empty());
  EXPECT_TRUE(d.outlines.empty());
}

TEST(WallDrawing, RectangleIsTwoTrianglesInItsPlaneWithItsFourSides) {
  Wall w;
  w.shape = WallShape::Rectangle;
  w.point = Vec3(1.0, 2.0, 3.0);
  w.normal = Vec3(1.0, 1.0, 0.0).normalized();
  w.edge = Vec3(0.0, 0.0, 1.0);
  w.halfSide[0] = 0.3;
  w.halfSide[1] = 0.2;
  const Vec3 side = w.normal.cross(w.edge);
  const WallDrawing d = wallDrawing(std::vector<Wall>{w});
  ASSERT_EQ(d.triangles.size(), 2u);
  ASSERT_EQ(d.outlines.size(), 4u);
  double area = 0.0;
  for (const render::Triangle& t : d.triangles) {
    for (const Vec3& x : t) {
      const Vec3 r = x - w.point;
      EXPECT_NEAR(r.dot(w.normal), 0.0, 1e-12);
      EXPECT_NEAR(std::abs(r.dot(w.edge)), 0.3, 1e-12);
      EXPECT_NEAR(std::abs(r.dot(side)), 0.2, 1e-12);
    }
    area += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm();
  }
  EXPECT_NEAR(area, 4 * 0.3 * 0.2, 1e-12);  // the two halves cover the rectangle once
  double perimeter = 0.0;
  for (const auto& [a, b] : d.outlines) perimeter += (b - a).norm();
  EXPECT_NEAR(perimeter, 4 * (0.3 + 0.2), 1e-12);
}

TEST(WallDrawing, CylinderFacetsLieOnItAndItsRimsAreOutlined) {
  const Vec3 base(0.1, -0.2, 0.3), axis = Vec3(1.0, 0.0, 1.0).normalized();
  const WallDrawing d = wallDrawing(std::vector<Wall>{frustum(base, axis, 0.8, 0.25, 0.25)});
  ASSERT_EQ(d.triangles.size(), std::size_t(2 * kFrustumFacets));
  ASSERT_EQ(d.outlines.size(), std::size_t(2 * kFrustumFacets));  // two rims
  for (const render::Triangle& t : d.triangles) {
    for (const Vec3& x : t) {
      const AxialPosition p = axial(x, base, axis);
      EXPECT_NEAR(p.radius, 0.25, 1e-12);
      EXPECT_TRUE(std::abs(p.along) < 1e-12 || std::abs(p.along - 0.8) < 1e-12) << p.along;
    }
  }
  for (const auto& [a, b] : d.outlines) {
    // A rim's chord: both ends at one end of the axis, one facet's angle apart.
    EXPECT_NEAR(axial(a, base, axis).along, axial(b, base, axis).along, 1e-12);
    EXPECT_NEAR((b - a).norm(), 2 * 0.25 * std::sin(std::numbers::pi / kFrustumFacets), 1e-12);
  }
}

TEST(WallDrawing, ConeCornersLieAtTheirEndsRadius) {
  const Vec3 base(0.0, 0.0, 0.5), axis(0.0, 0.0, -1.0);  // a hopper narrowing downwards
  const WallDrawing d = wallDrawing(std::vector<Wall>{frustum(base, axis, 0.4, 0.3, 0.05)});
  ASSERT_EQ(d.triangles.size(), std::size_t(2 * kFrustumFacets));
  ASSERT_EQ(d.outlines.size(), std::size_t(2 * kFrustumFacets));
  int atStart = 0, atEnd = 0;
  for (const render::Triangle& t : d.triangles) {
    for (const Vec3& x : t) {
      const AxialPosition p = axial(x, base, axis);
      if (std::abs(p.along) < 1e-12) {
        EXPECT_NEAR(p.radius, 0.3, 1e-12);
        ++atStart;
      } else {
        EXPECT_NEAR(p.along, 0.4, 1e-12);
        EXPECT_NEAR(p.radius, 0.05, 1e-12);
        ++atEnd;
      }
    }
  }
  EXPECT_EQ(atStart, 3 * kFrustumFacets);  // each quad: 2 corners of each rim in each triangle
  EXPECT_EQ(atEnd, 3 * kFrustumFacets);
}

TEST(WallDrawing, DiscAndPointedConeAreOneTriangleAFacetAndOneRim) {
  const Vec3 centre(0.0, 0.0, 0.0);
  const Wall disc = frustum(centre, Vec3::UnitZ(), 0.0, 0.0, 0.06);
  const Wall pointed = frustum(centre, Vec3::UnitZ(), 0.2, 0.1, 0.0);
  for (const Wall& w : {disc, pointed}) {
    const WallDrawing d = wallDrawing(std::vector<Wall>{w});
    ASSERT_EQ(d.triangles.size(), std::size_t(kFrustumFacets));
    EXPECT_EQ(d.outlines.size(), std::size_t(kFrustumFacets));
    double area = 0.0;
    for (const render::Triangle& t : d.triangles) {
      area += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm();
    }
    if (w.length == 0.0) {  // the disc's 48-gon, inscribed in its circle
      EXPECT_NEAR(
          area,
          0.5 * kFrustumFacets * 0.06 * 0.06 * std::sin(2 * std::numbers::pi / kFrustumFacets),
          1e-12);
    }
  }
}

TEST(WallDrawing, AnnulusHasTwoRims) {
  const WallDrawing d =
      wallDrawing(std::vector<Wall>{frustum(Vec3::Zero(), Vec3::UnitZ(), 0.0, 0.05, 0.1)});
  EXPECT_EQ(d.triangles.size(), std::size_t(2 * kFrustumFacets));
  EXPECT_EQ(d.outlines.size(), std::size_t(2 * kFrustumFacets));
}

TEST(WallDrawing, CubeMeshShowsItsTwelveEdgesNotItsDiagonals) {
  const Vec3 origin(0.5, 0.0, -1.0);
  const WallDrawing d = wallDrawing(std::vector<Wall>{meshWall(cube(), origin)});
  ASSERT_EQ(d.triangles.size(), 12u);
  ASSERT_EQ(d.outlines.size(), 12u);
  for (const auto& [a, b] : d.outlines) {
    const Vec3 along = (b - a).cwiseAbs();
    EXPECT_NEAR(along.sum(), 1.0, 1e-12);  // one unit along one axis: an edge, not a diagonal
    EXPECT_NEAR(along.maxCoeff(), 1.0, 1e-12);
  }
  // Posed where the wall is.
  for (const render::Triangle& t : d.triangles) {
    for (const Vec3& x : t) {
      const Vec3 r = x - origin;
      EXPECT_TRUE(r.minCoeff() >= -1e-12 && r.maxCoeff() <= 1 + 1e-12) << x.transpose();
    }
  }
}

TEST(WallDrawing, FacetedTubeShowsItsRimsNotItsFacets) {
  constexpr int kFacets = 24;  // 15° between neighbours, under the feature angle
  const WallDrawing d = wallDrawing(std::vector<Wall>{meshWall(facetedTube(kFacets))});
  EXPECT_EQ(d.triangles.size(), std::size_t(2 * kFacets));
  ASSERT_EQ(d.outlines.size(), std::size_t(2 * kFacets));  // the open rims only
  for (const auto& [a, b] : d.outlines) EXPECT_EQ(a.z(), b.z());

  const WallDrawing coarse = wallDrawing(std::vector<Wall>{meshWall(facetedTube(6))});
  EXPECT_EQ(coarse.outlines.size(), std::size_t(2 * 6 + 6));  // 60° apart: the sides show too
}

TEST(WallDrawing, FlatGridShowsOnlyItsBorder) {
  const WallDrawing d = wallDrawing(std::vector<Wall>{meshWall(testing::flatGrid(4))});
  EXPECT_EQ(d.triangles.size(), 32u);
  EXPECT_EQ(d.outlines.size(), 16u);
}

TEST(WallDrawing, WallsAddUp) {
  Wall rectangle;
  rectangle.shape = WallShape::Rectangle;
  rectangle.halfSide[0] = rectangle.halfSide[1] = 1.0;
  const std::vector<Wall> walls = {
      Wall{}, rectangle, frustum(Vec3::Zero(), Vec3::UnitZ(), 1.0, 0.5, 0.5), meshWall(cube())};
  const WallDrawing d = wallDrawing(walls);
  EXPECT_EQ(d.triangles.size(), 2u + 2 * kFrustumFacets + 12);
  EXPECT_EQ(d.outlines.size(), 4u + 2 * kFrustumFacets + 12);
}

}  // namespace
}  // namespace granular::gui
