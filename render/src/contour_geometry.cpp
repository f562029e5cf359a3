/// Contour geometry: superlevel polygons and isolines on a regular grid (contour_geometry.hpp).
#include "contour_geometry.hpp"

#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace granular::render::detail {

namespace {

struct Vertex {
  std::uint32_t id;  ///< nodes 0 … nx·ny − 1, then cell centres
  Point at;
  double value;
};

/// The four corner nodes and the centre of cell (i, j); false when a corner has no value.
bool cellVertices(const GridField& f, int i, int j, Vertex (&corner)[4], Vertex& centre) {
  const int ids[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};  // counter-clockwise
  double sum = 0.0;
  for (int k = 0; k < 4; ++k) {
    const int ci = ids[k][0], cj = ids[k][1];
    const double v = f.value(ci, cj);
    if (!std::isfinite(v)) return false;
    corner[k] = {std::uint32_t(cj * f.nx + ci), f.node(ci, cj), v};
    sum += v;
  }
  const Point a = corner[0].at, c = corner[2].at;
  centre = {std::uint32_t(f.nx * f.ny + j * (f.nx - 1) + i),
            {0.5 * (a.x + c.x), 0.5 * (a.y + c.y)},
            0.25 * sum};
  return true;
}

/// Where the level crosses edge (p, q), always interpolated from the lower id to the higher.
Point crossing(const Vertex& p, const Vertex& q, double level) {
  const Vertex& a = p.id < q.id ? p : q;
  const Vertex& b = p.id < q.id ? q : p;
  const double t = (level - a.value) / (b.value - a.value);
  return {a.at.x + t * (b.at.x - a.at.x), a.at.y + t * (b.at.y - a.at.y)};
}

std::uint64_t edgeKey(const Vertex& p, const Vertex& q) {
  const std::uint64_t lo = std::min(p.id, q.id), hi = std::max(p.id, q.id);
  return (lo << 32) | hi;
}

}  // namespace

std::vector<std::vector<Point>> superlevelPolygons(const GridField& f, double level) {
  std::vector<std::vector<Point>> out;
  if (f.nx < 2 || f.ny < 2) return out;
  Vertex corner[4], centre;
  for (int j = 0; j + 1 < f.ny; ++j) {
    int runStart = -1;  // first cell of the current run of cells entirely inside
    auto closeRun = [&](int end) {
      if (runStart < 0) return;
      const Point a = f.node(runStart, j), b = f.node(end, j + 1);
      out.push_back({{a.x, a.y}, {b.x, a.y}, {b.x, b.y}, {a.x, b.y}});
      runStart = -1;
    };
    for (int i = 0; i + 1 < f.nx; ++i) {
      if (!cellVertices(f, i, j, corner, centre)) {
        closeRun(i);
        continue;
      }
      int inside = 0;
      for (const Vertex& v : corner) inside += v.value >= level ? 1 : 0;
      if (inside == 4) {
        if (runStart < 0) runStart = i;
        continue;
      }
      closeRun(i);
      if (inside == 0 && centre.value < level) continue;
      // Clip each triangle to f ≥ level (Sutherland–Hodgman against one linear constraint).
      for (int k = 0; k < 4; ++k) {
        const Vertex tri[3] = {corner[k], corner[(k + 1) % 4], centre};
        std::vector<Point> poly;
        for (int e = 0; e < 3; ++e) {
          const Vertex& p = tri[e];
          const Vertex& q = tri[(e + 1) % 3];
          const bool pIn = p.value >= level, qIn = q.value >= level;
          if (pIn) poly.push_back(p.at);
          if (pIn != qIn) poly.push_back(crossing(p, q, level));
        }
        if (poly.size() >= 3) out.push_back(std::move(poly));
      }
    }
    closeRun(f.nx - 1);
  }
  return out;
}

std::vector<std::vector<Point>> isolines(const GridField& f, double level) {
  std::vector<std::vector<Point>> out;
  if (f.nx < 2 || f.ny < 2 || !std::isfinite(level)) return out;
  struct Segment {
    std::uint64_t key[2];
    Point at[2];
  };
  std::vector<Segment> segments;
  Vertex corner[4], centre;
  for (int j = 0; j + 1 < f.ny; ++j) {
    for (int i = 0; i + 1 < f.nx; ++i) {
      if (!cellVertices(f, i, j, corner, centre)) continue;
      for (int k = 0; k < 4; ++k) {
        const Vertex tri[3] = {corner[k], corner[(k + 1) % 4], centre};
        Segment s{};
        int n = 0;
        for (int e = 0; e < 3; ++e) {
          const Vertex& p = tri[e];
          const Vertex& q = tri[(e + 1) % 3];
          if ((p.value >= level) != (q.value >= level)) {
            s.key[n] = edgeKey(p, q);
            s.at[n] = crossing(p, q, level);
            ++n;
          }
        }
        if (n == 2) segments.push_back(s);
      }
    }
  }
  // Chain the segments through the edges they share: an edge is crossed once, so each crossing
  // joins at most two segments.
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> byEdge;
  byEdge.reserve(segments.size() * 2);
  for (std::size_t s = 0; s < segments.size(); ++s) {
    byEdge[segments[s].key[0]].push_back(s);
    byEdge[segments[s].key[1]].push_back(s);
  }
  std::vector<bool> used(segments.size(), false);
  auto other = [&](std::uint64_t key, std::size_t from) -> long {
    for (std::size_t s : byEdge[key]) {
      if (s != from && !used[s]) return long(s);
    }
    return -1;
  };
  auto walk = [&](std::size_t start, int startEnd) {
    // Follow from segment `start`, leaving through its end `1 − startEnd`.
    std::vector<Point> line{segments[start].at[startEnd]};
    std::size_t s = start;
    int exitEnd = 1 - startEnd;
    used[s] = true;
    for (;;) {
      line.push_back(segments[s].at[exitEnd]);
      const std::uint64_t key = segments[s].key[exitEnd];
      const long next = other(key, s);
      if (next < 0) {
        // A loop closes on its starting edge.
        if (key == segments[start].key[startEnd] && line.size() > 2) line.back() = line.front();
        break;
      }
      s = std::size_t(next);
      used[s] = true;
      exitEnd = segments[s].key[0] == key ? 1 : 0;
    }
    out.push_back(std::move(line));
  };
  // Open lines first, from an end that no other segment shares (the data's border), then loops.
  for (std::size_t s = 0; s < segments.size(); ++s) {
    if (used[s]) continue;
    for (int end = 0; end < 2; ++end) {
      if (!used[s] && byEdge[segments[s].key[end]].size() == 1) walk(s, end);
    }
  }
  for (std::size_t s = 0; s < segments.size(); ++s) {
    if (!used[s]) walk(s, 0);
  }
  return out;
}

}  // namespace granular::render::detail
