/// surfaceDistance (granular/wall.hpp): the force pass's own measure of a wall, for callers
/// outside the engine.
#include <cmath>
#include "granular/wall.hpp"

#include "granular/wall_mesh.hpp"
#include "wall_contact.hpp"

namespace granular {

double surfaceDistance(const Wall& w, const Vec3& x) {
  return touchOf(w, x).distance;
}

bool surfaceNearer(const Wall& w, const Vec3& x, double r) {
  if (w.shape != WallShape::Mesh) return touchOf(w, x).distance < r;
  const TriangleMesh& mesh = w.mesh->world;
  const MeshTopology& topology = w.mesh->topology;
  for (std::size_t t = 0; t < mesh.triangle.size(); ++t) {
    const auto& v = mesh.triangle[t];
    // No point of a triangle is nearer than its plane.
    if (!(std::abs((x - mesh.vertex[v[0]]).dot(topology.normal[t])) < r)) continue;
    const TriangleTouch touch =
        closestOnTriangle(mesh.vertex[v[0]], mesh.vertex[v[1]], mesh.vertex[v[2]], x);
    if ((x - touch.point).norm() < r) return true;
  }
  return false;
}

}  // namespace granular
