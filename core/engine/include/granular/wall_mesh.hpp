#pragma once
/// A triangle-mesh wall's geometry (docs/physics.md §2.20): its triangles in the wall's frame,
/// and posed where the wall is now.
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

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

/// No triangle within reach (nearestTriangles).
inline constexpr std::uint32_t kNoTriangle = std::numeric_limits<std::uint32_t>::max();

/// For each of `points`, the index of the posed mesh's triangle nearest it (the lowest index of
/// a tie), or kNoTriangle where none lies within `reach` [m]: to sort contacts onto the
/// triangles they press on (per-triangle loads in the output). Binned: a large mesh costs
/// little per point.
std::vector<std::uint32_t> nearestTriangles(const WallMesh& mesh, std::span<const Vec3> points,
                                            double reach);

}  // namespace granular
