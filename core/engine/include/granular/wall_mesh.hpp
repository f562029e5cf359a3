#pragma once
/// A triangle-mesh wall's geometry (docs/physics.md §2.20): its triangles in the wall's frame,
/// and posed where the wall is now.
#include <memory>
#include <string>

#include "granular/triangle_mesh.hpp"

namespace granular {

/// Contacts a particle may have with one mesh at once (a box's corner: three); beyond them the
/// nearest are kept.
inline constexpr std::size_t kMeshContacts = 3;

/// A mesh where it is: immutable, so that copies of a state share it; a moving mesh is posed
/// anew each step (poseMesh).
struct WallMesh {
  std::shared_ptr<const TriangleMesh> body;  ///< in the wall's frame [m]
  TriangleMesh world;                        ///< posed [m]
  MeshTopology topology;                     ///< of `world` (its normals posed)
  double extent = 0;                         ///< the farthest vertex from the frame's origin [m]
};

/// `body` posed in the frame with origin `origin`, z axis `normal` and x axis `edge` (unit and
/// normal to each other).
std::shared_ptr<const WallMesh> poseMesh(std::shared_ptr<const TriangleMesh> body,
                                         const Vec3& origin, const Vec3& normal, const Vec3& edge);

}  // namespace granular
