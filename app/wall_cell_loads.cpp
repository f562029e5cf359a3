/// wall_cell_loads.hpp.
#include "wall_cell_loads.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "granular/wall_mesh.hpp"

namespace granular::app {

FrustumBasis frustumBasis(const Wall& wall) {
  const Vec3 e1 = (std::abs(wall.normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY())
                      .cross(wall.normal)
                      .normalized();
  return {e1, wall.normal.cross(e1)};
}

std::size_t wallCellCount(const Wall& wall) {
  switch (wall.shape) {
    case WallShape::Mesh:
      return wall.mesh->world.triangle.size();
    case WallShape::Frustum:
      return kFrustumFacets;
    case WallShape::Rectangle:
    case WallShape::Plane:
      break;
  }
  return 1;
}

namespace {

/// The facet of a frustum under `point`: by its angle about the axis.
std::size_t frustumFacet(const Wall& wall, const FrustumBasis& basis, const Vec3& point) {
  const Vec3 r = point - wall.point;
  double angle = std::atan2(r.dot(basis.e2), r.dot(basis.e1));
  if (angle < 0.0) angle += 2.0 * std::numbers::pi;
  const auto facet = std::size_t(angle / (2.0 * std::numbers::pi) * kFrustumFacets);
  return std::min<std::size_t>(facet, kFrustumFacets - 1);  // angle 2π by rounding
}

}  // namespace

std::vector<std::vector<Vec3>> wallCellForces(const Simulation& sim) {
  const std::vector<Wall>& walls = sim.walls();
  std::vector<std::vector<Vec3>> force(walls.size());
  std::vector<FrustumBasis> basis(walls.size());
  for (std::size_t w = 0; w < walls.size(); ++w) {
    force[w].assign(wallCellCount(walls[w]), Vec3::Zero());
    if (walls[w].shape == WallShape::Frustum) basis[w] = frustumBasis(walls[w]);
  }
  // A mesh's contacts are sorted onto triangles together, through the mesh's bins.
  std::vector<std::vector<Vec3>> meshPoint(walls.size()), meshForce(walls.size());
  sim.forEachContact([&](const ContactView& c) {
    if (!c.isWall()) return;
    const std::size_t w = c.wall();
    const Vec3 onWall = -c.force;
    switch (walls[w].shape) {
      case WallShape::Mesh:
        meshPoint[w].push_back(c.point);
        meshForce[w].push_back(onWall);
        return;
      case WallShape::Frustum:
        force[w][frustumFacet(walls[w], basis[w], c.point)] += onWall;
        return;
      case WallShape::Rectangle:
      case WallShape::Plane:
        force[w][0] += onWall;
        return;
    }
  });
  const std::vector<double>& radius = sim.particles().radius;
  // A contact point lies within its particle's radius of the surface.
  const double reach = radius.empty() ? 0.0 : 2.0 * *std::max_element(radius.begin(), radius.end());
  for (std::size_t w = 0; w < walls.size(); ++w) {
    if (meshPoint[w].empty()) continue;
    const std::vector<std::uint32_t> triangle =
        nearestTriangles(*walls[w].mesh, meshPoint[w], reach);
    for (std::size_t k = 0; k < triangle.size(); ++k) {
      if (triangle[k] != kNoTriangle) force[w][triangle[k]] += meshForce[w][k];
    }
  }
  return force;
}

}  // namespace granular::app
