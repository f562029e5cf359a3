/// Posing a mesh wall's triangles (granular/wall_mesh.hpp).
#include "granular/wall_mesh.hpp"

#include <algorithm>
#include <vector>

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

}  // namespace granular
