/// A sphere's contacts with a triangle mesh (mesh_contact.hpp).
#include "mesh_contact.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace granular {

namespace {

bool isEdge(TriangleFeature f) {
  return f >= TriangleFeature::Edge0 && f <= TriangleFeature::Edge2;
}
bool isVertex(TriangleFeature f) {
  return f >= TriangleFeature::Vertex0;
}
int edgeOf(TriangleFeature f) {
  return int(f) - int(TriangleFeature::Edge0);
}
int cornerOf(TriangleFeature f) {
  return int(f) - int(TriangleFeature::Vertex0);
}

}  // namespace

TriangleTouch closestOnTriangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& x) {
  // Voronoi regions of the corners, then the edges, else the face (the barycentric form of the
  // projection), as in Ericson, Real-Time Collision Detection (2005) §5.1.5.
  const Vec3 ab = b - a, ac = c - a, ax = x - a;
  const double d1 = ab.dot(ax), d2 = ac.dot(ax);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, TriangleFeature::Vertex0};
  const Vec3 bx = x - b;
  const double d3 = ab.dot(bx), d4 = ac.dot(bx);
  if (d3 >= 0.0 && d4 <= d3) return {b, TriangleFeature::Vertex1};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    return {a + (d1 / (d1 - d3)) * ab, TriangleFeature::Edge0};
  }
  const Vec3 cx = x - c;
  const double d5 = ab.dot(cx), d6 = ac.dot(cx);
  if (d6 >= 0.0 && d5 <= d6) return {c, TriangleFeature::Vertex2};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    return {a + (d2 / (d2 - d6)) * ac, TriangleFeature::Edge2};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    return {b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b), TriangleFeature::Edge1};
  }
  const double scale = 1.0 / (va + vb + vc);
  return {a + (vb * scale) * ab + (vc * scale) * ac, TriangleFeature::Face};
}

void meshContacts(const TriangleMesh& mesh, const MeshTopology& topology,
                  std::span<const std::uint32_t> candidates, const Vec3& x, double reach,
                  std::vector<MeshContact>& out) {
  out.clear();
  // 1. Each candidate's closest point, within reach. A face's is straight across its plane,
  // so that a sphere over a flat region is exactly above its contact point.
  // Scratch kept on this thread between calls: nothing is allocated per particle and step.
  thread_local std::vector<MeshContact> found, kept;
  found.clear();
  kept.clear();
  for (std::uint32_t t : candidates) {
    const auto& v = mesh.triangle[t];
    const Vec3& n = topology.normal[t];
    const double across = (x - mesh.vertex[v[0]]).dot(n);
    // No point of a triangle is nearer than its plane: most candidates end here.
    if (!(std::abs(across) < reach)) continue;
    const TriangleTouch touch =
        closestOnTriangle(mesh.vertex[v[0]], mesh.vertex[v[1]], mesh.vertex[v[2]], x);
    MeshContact c;
    c.triangle = t;
    c.feature = touch.feature;
    if (touch.feature == TriangleFeature::Face) {
      c.distance = std::abs(across);
      c.normal = across < 0.0 ? Vec3(-n) : n;
      c.point = x - across * n;
    } else {
      const Vec3 d = x - touch.point;
      c.distance = d.norm();
      c.normal = c.distance > 0.0 ? Vec3(d / c.distance) : topology.normal[t];
      c.point = touch.point;
    }
    if (c.distance < reach) found.push_back(c);
  }
  // 2. The local minima of the distance over the mesh: a face's closest point; an edge's when
  // the triangle across finds it too (or the edge is open), once; a corner's when every
  // triangle around it finds it. Elsewhere a neighbour holds a nearer point.
  auto findsEdge = [&](std::uint32_t t, std::uint32_t across) {
    return std::any_of(found.begin(), found.end(), [&](const MeshContact& d) {
      return d.triangle == t && isEdge(d.feature) &&
             topology.across[t][edgeOf(d.feature)] == std::int64_t(across);
    });
  };
  for (const MeshContact& c : found) {
    if (isEdge(c.feature)) {
      const std::int64_t other = topology.across[c.triangle][edgeOf(c.feature)];
      if (other != MeshTopology::kOpen &&
          (std::uint32_t(other) < c.triangle || !findsEdge(std::uint32_t(other), c.triangle))) {
        continue;
      }
    } else if (isVertex(c.feature)) {
      const std::uint32_t v = mesh.triangle[c.triangle][cornerOf(c.feature)];
      const bool local = std::all_of(found.begin(), found.end(), [&](const MeshContact& d) {
        const auto& corners = mesh.triangle[d.triangle];
        const bool around = corners[0] == v || corners[1] == v || corners[2] == v;
        return !around || (isVertex(d.feature) && corners[cornerOf(d.feature)] == v &&
                           d.triangle >= c.triangle);
      });
      if (!local) continue;
    }
    kept.push_back(c);
  }
  // A point on the border between two features may round into neither's rule: the nearest
  // point found is always a contact.
  if (kept.empty() && !found.empty()) {
    kept.push_back(*std::min_element(
        found.begin(), found.end(), [](const MeshContact& p, const MeshContact& q) {
          return p.distance != q.distance ? p.distance < q.distance : p.triangle < q.triangle;
        }));
  }
  // 3 and 4: nearest first (then by triangle, for the same result on any candidate order); a
  // contact at the point of a nearer one, or on the same surface as it, is that contact.
  std::sort(kept.begin(), kept.end(), [](const MeshContact& p, const MeshContact& q) {
    return p.distance != q.distance ? p.distance < q.distance : p.triangle < q.triangle;
  });
  const double sameSurface = std::cos(kSameSurfaceDegrees * std::numbers::pi / 180.0);
  for (const MeshContact& c : kept) {
    const bool known = std::any_of(out.begin(), out.end(), [&](const MeshContact& d) {
      const double scale = 1.0 + d.point.cwiseAbs().maxCoeff();
      return (c.point - d.point).norm() <= 1e-12 * scale || c.normal.dot(d.normal) > sameSurface;
    });
    if (!known) out.push_back(c);
  }
}

}  // namespace granular
