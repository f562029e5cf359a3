/// A triangle mesh's topology and defects (granular/triangle_mesh.hpp).
#include "granular/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>

namespace granular {

namespace {

/// One triangle's edge as the edge table holds it: its vertices ordered, and whether the
/// triangle runs along it from the lower vertex to the higher.
struct EdgeUse {
  std::uint32_t low, high;
  std::uint32_t triangle;
  std::uint8_t k;  ///< edge k of the triangle: its vertex k to vertex k + 1
  bool upward;     ///< the triangle runs low → high
};

/// A vertex as a message names it: (x, y, z) to 6 digits, in the mesh's units.
std::string pointText(const Vec3& v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", v.x(), v.y(), v.z());
  return text;
}

}  // namespace

MeshTopology meshTopology(const TriangleMesh& mesh, bool closed, std::vector<MeshDefect>& defects) {
  const std::size_t n = mesh.triangle.size(), reported = defects.size();
  MeshTopology topology;
  topology.across.assign(n, {MeshTopology::kOpen, MeshTopology::kOpen, MeshTopology::kOpen});
  topology.normal.assign(n, Vec3::Zero());
  std::vector<bool> sound(n, true);
  for (std::size_t t = 0; t < n; ++t) {
    const auto& v = mesh.triangle[t];
    if (std::any_of(v.begin(), v.end(), [&](std::uint32_t i) { return i >= mesh.vertex.size(); })) {
      defects.push_back({t, "a vertex index beyond the mesh's " +
                                std::to_string(mesh.vertex.size()) + " vertices"});
      sound[t] = false;
      continue;
    }
    const Vec3 &a = mesh.vertex[v[0]], &b = mesh.vertex[v[1]], &c = mesh.vertex[v[2]];
    if (!a.allFinite() || !b.allFinite() || !c.allFinite()) {
      defects.push_back({t, "a vertex is not finite"});
      sound[t] = false;
      continue;
    }
    const Vec3 cross = (b - a).cross(c - a);
    const double longest2 =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if (!(cross.norm() > 1e-12 * longest2)) {
      defects.push_back({t, "zero area (its corners lie on a line)"});
      sound[t] = false;
      continue;
    }
    topology.normal[t] = cross.normalized();
  }

  std::vector<EdgeUse> edges;
  edges.reserve(3 * n);
  for (std::size_t t = 0; t < n; ++t) {
    if (!sound[t]) continue;
    for (std::uint8_t k = 0; k < 3; ++k) {
      const std::uint32_t from = mesh.triangle[t][k], to = mesh.triangle[t][(k + 1) % 3];
      edges.push_back({std::min(from, to), std::max(from, to), std::uint32_t(t), k, from < to});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return std::tie(x.low, x.high, x.triangle, x.k) < std::tie(y.low, y.high, y.triangle, y.k);
  });
  for (std::size_t begin = 0; begin < edges.size();) {
    std::size_t end = begin + 1;
    while (end < edges.size() && edges[end].low == edges[begin].low &&
           edges[end].high == edges[begin].high) {
      ++end;
    }
    const EdgeUse& first = edges[begin];
    auto where = [&](const EdgeUse& e) {
      return "its edge from " + pointText(mesh.vertex[e.upward ? e.low : e.high]) + " to " +
             pointText(mesh.vertex[e.upward ? e.high : e.low]);
    };
    if (end - begin == 1) {
      if (closed) defects.push_back({first.triangle, where(first) + " is open (no neighbour)"});
    } else if (end - begin == 2) {
      const EdgeUse& second = edges[begin + 1];
      if (first.upward == second.upward) {
        defects.push_back({second.triangle, "its normal is inverted against triangle " +
                                                std::to_string(first.triangle) + "'s (" +
                                                where(second) + " runs the same way in both)"});
      } else {
        topology.across[first.triangle][first.k] = second.triangle;
        topology.across[second.triangle][second.k] = first.triangle;
      }
    } else {
      for (std::size_t e = begin; e < end; ++e) {
        defects.push_back({edges[e].triangle, where(edges[e]) + " is shared by " +
                                                  std::to_string(end - begin) + " triangles"});
      }
    }
    begin = end;
  }
  std::stable_sort(
      defects.begin() + std::ptrdiff_t(reported), defects.end(),
      [](const MeshDefect& x, const MeshDefect& y) { return x.triangle < y.triangle; });
  return topology;
}

}  // namespace granular
