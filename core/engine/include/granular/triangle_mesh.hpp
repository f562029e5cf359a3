#pragma once
/// Triangle meshes as walls (docs/physics.md §2.20): the triangles, their topology (which
/// triangle lies across each edge) and the defects that make a mesh unfit to hold particles.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "granular/vec3.hpp"

namespace granular {

struct TriangleMesh {
  std::vector<Vec3> vertex;                            ///< [m]
  std::vector<std::array<std::uint32_t, 3>> triangle;  ///< vertex indices, counter-clockwise
};

/// Which triangle lies across each edge of each triangle, and the unit face normals. Edge k of
/// a triangle runs from its vertex k to vertex k + 1 (mod 3).
struct MeshTopology {
  static constexpr std::int64_t kOpen = -1;  ///< no triangle across: an open edge
  std::vector<std::array<std::int64_t, 3>> across;
  std::vector<Vec3> normal;
};

/// A defect, by triangle (its index in the mesh) and what is wrong with it.
struct MeshDefect {
  std::size_t triangle = 0;
  std::string what;
};

/// The mesh's topology, and its defects appended to `defects`: a vertex index out of range or
/// a vertex not finite, a triangle of (nearly) zero area (below 10⁻¹² of the square of its
/// longest edge), an edge shared by more than two triangles, two neighbours whose orientations
/// disagree (one normal inverted), and, where `closed` is asked, an open edge. A defective
/// triangle's edges are left open.
MeshTopology meshTopology(const TriangleMesh& mesh, bool closed, std::vector<MeshDefect>& defects);

}  // namespace granular
