#include "wall_drawing.hpp"

#include <cmath>
#include <numbers>

#include "granular/triangle_mesh.hpp"
#include "granular/wall_mesh.hpp"

namespace granular::gui {

namespace {

void addRectangle(const Wall& wall, WallDrawing& out) {
  const Vec3 u = wall.halfSide[0] * wall.edge;
  const Vec3 v = wall.halfSide[1] * wall.normal.cross(wall.edge);
  const Vec3 corner[4] = {wall.point - u - v, wall.point + u - v, wall.point + u + v,
                          wall.point - u + v};
  out.triangles.push_back({corner[0], corner[1], corner[2]});
  out.triangles.push_back({corner[0], corner[2], corner[3]});
  for (int k = 0; k < 4; ++k) out.outlines.emplace_back(corner[k], corner[(k + 1) % 4]);
}

void addFrustum(const Wall& wall, WallDrawing& out) {
  // The same basis about the axis as the ParaView files', so both show the same facets.
  const Vec3 e1 = (std::abs(wall.normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY())
                      .cross(wall.normal)
                      .normalized();
  const Vec3 e2 = wall.normal.cross(e1);
  const Vec3 start = wall.point, end = wall.point + wall.length * wall.normal;
  auto around = [&](int k) {
    const double angle = 2.0 * std::numbers::pi * k / kFrustumFacets;
    return Vec3(std::cos(angle) * e1 + std::sin(angle) * e2);
  };
  for (int k = 0; k < kFrustumFacets; ++k) {
    const Vec3 a = around(k), b = around(k + 1);
    const Vec3 startA = start + wall.radiusStart * a, startB = start + wall.radiusStart * b;
    const Vec3 endA = end + wall.radiusEnd * a, endB = end + wall.radiusEnd * b;
    // A rim of radius 0 is a point: the facet is one triangle there.
    if (wall.radiusStart != 0.0) out.triangles.push_back({startA, startB, endB});
    if (wall.radiusEnd != 0.0) out.triangles.push_back({startA, endB, endA});
    if (wall.radiusStart != 0.0) out.outlines.emplace_back(startA, startB);
    if (wall.radiusEnd != 0.0) out.outlines.emplace_back(endA, endB);
  }
}

void addMesh(const Wall& wall, WallDrawing& out) {
  const TriangleMesh& mesh = wall.mesh->world;
  const MeshTopology& topology = wall.mesh->topology;
  const double featureCos = std::cos(kFeatureAngleDeg * std::numbers::pi / 180.0);
  for (std::size_t t = 0; t < mesh.triangle.size(); ++t) {
    const auto& corner = mesh.triangle[t];
    out.triangles.push_back(
        {mesh.vertex[corner[0]], mesh.vertex[corner[1]], mesh.vertex[corner[2]]});
    for (int k = 0; k < 3; ++k) {
      const std::int64_t other = topology.across[t][k];
      // A shared edge is seen from both of its triangles: the one with the lower index draws it.
      const bool open = other == MeshTopology::kOpen;
      if (!open && std::size_t(other) < t) continue;
      if (open || topology.normal[t].dot(topology.normal[std::size_t(other)]) < featureCos) {
        out.outlines.emplace_back(mesh.vertex[corner[k]], mesh.vertex[corner[(k + 1) % 3]]);
      }
    }
  }
}

}  // namespace

WallDrawing wallDrawing(std::span<const Wall> walls) {
  WallDrawing out;
  for (const Wall& wall : walls) {
    if (wall.removed) continue;  // a gate opened
    switch (wall.shape) {
      case WallShape::Plane:
        break;
      case WallShape::Rectangle:
        addRectangle(wall, out);
        break;
      case WallShape::Frustum:
        addFrustum(wall, out);
        break;
      case WallShape::Mesh:
        if (wall.mesh) addMesh(wall, out);
        break;
    }
  }
  return out;
}

}  // namespace granular::gui
