#pragma once
/// A sphere's contacts with a triangle mesh (docs/physics.md §2.20): the closest feature of each
/// triangle near it (face, edge or vertex), reduced to one contact per touched surface. On a
/// flat or gently curved region of many triangles a sphere has one contact however the region
/// is cut; in a corner sharper than kSameSurfaceDegrees, one per side.
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "granular/triangle_mesh.hpp"

namespace granular {

/// Faces whose contacts' normals are closer than this are one surface: a sphere in the fold
/// between them (a triangulated cylinder seen from inside) has one contact, the nearer [°].
inline constexpr double kSameSurfaceDegrees = 20.0;

/// The closest point of a triangle and which of its features holds it.
enum class TriangleFeature : std::uint8_t { Face, Edge0, Edge1, Edge2, Vertex0, Vertex1, Vertex2 };

struct TriangleTouch {
  Vec3 point;
  TriangleFeature feature = TriangleFeature::Face;
};

/// The point of triangle abc closest to x, and its feature (edge k runs from vertex k to k + 1).
/// A point on an edge's line or at a corner belongs to the edge or the corner.
TriangleTouch closestOnTriangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& x);

/// Whether triangle t of `mesh` has a point nearer x than `limit`. A triangle whose plane is
/// that far is passed over without the closest point: no point of it is nearer than its plane.
inline bool triangleWithin(const TriangleMesh& mesh, const MeshTopology& topology, std::size_t t,
                           const Vec3& x, double limit) {
  const auto& v = mesh.triangle[t];
  if (!(std::abs((x - mesh.vertex[v[0]]).dot(topology.normal[t])) < limit)) return false;
  const TriangleTouch touch =
      closestOnTriangle(mesh.vertex[v[0]], mesh.vertex[v[1]], mesh.vertex[v[2]], x);
  return (x - touch.point).norm() < limit;
}

/// One contact of a sphere with a mesh.
struct MeshContact {
  double distance = 0;  ///< from the centre to the closest point [m]
  Vec3 normal;          ///< unit, from the closest point towards the centre [-]
  Vec3 point;           ///< the closest point [m]
  std::uint32_t triangle = 0;
  TriangleFeature feature = TriangleFeature::Face;
};

/// The contacts of the sphere centred at x with the mesh, among the `candidates` (triangle
/// indices; they must include every triangle closer than `reach`), for distances below
/// `reach`; nearest first. They are the local minima of the distance from x over the mesh:
/// 1. every candidate's closest point and its feature;
/// 2. a face's point is a contact; an edge's only if the triangle across finds the same edge
///    (counted once) or the edge is open; a corner's only if every triangle around it finds
///    that corner (once); otherwise a neighbour holds a nearer point. If rounding at a border
///    between features leaves none, the nearest point found is the contact;
/// 3. the same closest point found twice is one contact;
/// 4. of contacts whose normals are closer than kSameSurfaceDegrees, the nearest (a fold of a
///    gently curved surface gives two minima, one on each facet's plane).
void meshContacts(const TriangleMesh& mesh, const MeshTopology& topology,
                  std::span<const std::uint32_t> candidates, const Vec3& x, double reach,
                  std::vector<MeshContact>& out);

}  // namespace granular
