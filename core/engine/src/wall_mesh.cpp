/// Posing a mesh wall's triangles (granular/wall_mesh.hpp).
#include "granular/wall_mesh.hpp"

#include <algorithm>
#include <vector>

#include "triangle_grid.hpp"

namespace granular {

std::shared_ptr<const WallMesh> poseMesh(std::shared_ptr<const TriangleMesh> body,
                                         const Vec3& origin, const Vec3& normal, const Vec3& edge) {
  auto mesh = std::make_shared<WallMesh>();
  const Vec3 side = normal.cross(edge);
  mesh->world.triangle = body->triangle;
  mesh->world.vertex.reserve(body->vertex.size());
  for (const Vec3& v : body->vertex) {
    mesh->world.vertex.push_back(origin + v.x() * edge + v.y() * side + v.z() * normal);
    mesh->extent = std::max(mesh->extent, v.norm());
  }
  std::vector<MeshDefect> defects;  // the body was checked when it was read
  mesh->topology = meshTopology(mesh->world, false, defects);
  mesh->body = std::move(body);
  return mesh;
}

std::vector<std::uint32_t> nearestTriangles(const WallMesh& mesh, std::span<const Vec3> points,
                                            double reach) {
  std::vector<std::uint32_t> nearest(points.size(), kNoTriangle);
  if (points.empty() || mesh.world.triangle.empty() || !(reach > 0.0)) return nearest;
  const TriangleGrid grid = binTriangles(mesh.world, reach, reach);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const MeshNearest found =
        nearestAmong(mesh.world, mesh.topology, grid.near(points[k]), points[k]);
    if (found.distance <= reach) nearest[k] = found.triangle;
  }
  return nearest;
}

}  // namespace granular
