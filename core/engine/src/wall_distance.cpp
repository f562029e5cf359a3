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
    if (triangleWithin(mesh, topology, t, x, r)) return true;
  }
  return false;
}

}  // namespace granular
