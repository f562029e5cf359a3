#pragma once
/// The cells of space a mesh's triangles pass near, so that a particle looks at the few
/// triangles around it, not at all of them (docs/physics.md §2.20).
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "granular/triangle_mesh.hpp"
#include "mesh_contact.hpp"

namespace granular {

struct TriangleGrid {
  Vec3 origin = Vec3::Zero();
  double cell = 1.0;  ///< cell edge [m]
  int dims[3] = {0, 0, 0};
  double reach = 0;      ///< every triangle within this of a point is among its cell's [m]
  double cellAsked = 0;  ///< the cell edge binTriangles was asked for (`cell` is at least it) [m]
  std::vector<std::uint32_t> cellStart;  ///< cells + 1 entries
  std::vector<std::uint32_t> triangles;

  bool empty() const { return cellStart.empty(); }
  /// The triangles that may lie within `reach` of x (none outside the grid).
  std::span<const std::uint32_t> near(const Vec3& x) const;
};

/// Bins each triangle into every cell its box, grown by `reach`, overlaps; cells of edge
/// `cell` (at least reach, and at most 64 along the mesh's longest side is not forced).
TriangleGrid binTriangles(const TriangleMesh& mesh, double reach, double cell);

/// A neighbour list's grid of a mesh: every triangle within the largest radius plus `margin`
/// (the skin and the model's reach) of a point listed in its cell, cells of 2 R_max + margin.
/// The list's build and a grid binned again after reading a checkpoint both use this one rule.
inline TriangleGrid listGrid(const TriangleMesh& mesh, double rMax, double margin) {
  return binTriangles(mesh, rMax + margin, 2.0 * rMax + margin);
}

/// The mesh's point nearest x among the grid's candidates, its distance and the unit normal
/// from it towards x; distance +∞ where no triangle is within the grid's reach.
struct MeshNearest {
  double distance = 0;
  Vec3 normal = Vec3::UnitZ();
  Vec3 point = Vec3::Zero();
  std::uint32_t triangle = 0;  ///< the triangle the point is on (the lowest index of a tie)
};
MeshNearest nearestOnMesh(const TriangleMesh& mesh, const MeshTopology& topology,
                          const TriangleGrid& grid, const Vec3& x);

/// Appends to `out` the grid's candidates of x that lie nearer x than `limit` (≤ the grid's
/// reach), in the cell's order: a neighbour list's triangles of a particle at a build. Those
/// whose plane is that far are passed over without the closest point.
void trianglesWithin(const TriangleMesh& mesh, const MeshTopology& topology,
                     const TriangleGrid& grid, const Vec3& x, double limit,
                     std::vector<std::uint32_t>& out);

/// Every triangle index 0..count-1 as a range (std::views::iota trips clang on libstdc++ 12).
struct AllTriangles {
  struct Iterator {
    std::size_t index;
    std::size_t operator*() const { return index; }
    Iterator& operator++() {
      ++index;
      return *this;
    }
    bool operator!=(const Iterator& other) const { return index != other.index; }
  };
  std::size_t count;
  Iterator begin() const { return {0}; }
  Iterator end() const { return {count}; }
};

/// The same among any `candidates` (triangle indices); ties go to the lowest index.
template <class Candidates>
MeshNearest nearestAmong(const TriangleMesh& mesh, const MeshTopology& topology,
                         const Candidates& candidates, const Vec3& x) {
  MeshNearest best;
  best.distance = std::numeric_limits<double>::infinity();
  std::uint32_t bestTriangle = 0;
  for (const auto candidate : candidates) {
    const auto t = static_cast<std::uint32_t>(candidate);
    const auto& v = mesh.triangle[t];
    const TriangleTouch touch =
        closestOnTriangle(mesh.vertex[v[0]], mesh.vertex[v[1]], mesh.vertex[v[2]], x);
    const Vec3 d = x - touch.point;
    const double distance = d.norm();
    if (distance < best.distance || (distance == best.distance && t < bestTriangle)) {
      best.distance = distance;
      best.point = touch.point;
      best.normal = distance > 0.0 ? Vec3(d / distance) : topology.normal[t];
      best.triangle = bestTriangle = t;
    }
  }
  return best;
}

}  // namespace granular
