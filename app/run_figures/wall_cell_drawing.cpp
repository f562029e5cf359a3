/// wall_cell_drawing.hpp.
#include "wall_cell_drawing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

namespace granular::app {

namespace {

/// A corner rounded to a grid far finer than any cell: the cells of a wall are written each
/// with its own copies of the corners they share, and a frustum's last facet meets its first at
/// an angle of 2π computed apart from 0.
using Key = std::array<long long, 3>;

Key keyOf(const Vec3& x, double grid) {
  return {std::llround(x.x() / grid), std::llround(x.y() / grid), std::llround(x.z() / grid)};
}

/// Newell's normal of a polygon, unit (zero for a degenerate one).
Vec3 normalOf(const std::vector<Vec3>& corners) {
  Vec3 n = Vec3::Zero();
  for (std::size_t k = 0; k < corners.size(); ++k) {
    n += corners[k].cross(corners[(k + 1) % corners.size()]);
  }
  const double length = n.norm();
  return length > 0.0 ? Vec3(n / length) : Vec3::Zero();
}

void addWall(const WallCells& wall, CellDrawing& out) {
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
  for (const auto& cell : wall.cells) {
    for (const Vec3& x : cell) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  }
  if (wall.cells.empty()) return;
  const double grid = std::max(1e-12, 1e-9 * (hi - lo).norm());
  // Each edge, by its two corners in either order: the cells it bounds and its ends.
  struct Edge {
    std::vector<std::size_t> cells;
    render::Segment ends;
  };
  std::map<std::pair<Key, Key>, Edge> edges;
  std::vector<Vec3> normals;
  for (std::size_t c = 0; c < wall.cells.size(); ++c) {
    const std::vector<Vec3>& corners = wall.cells[c];
    normals.push_back(normalOf(corners));
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
      out.triangles.push_back({corners[0], corners[k], corners[k + 1]});
    }
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const Vec3 &a = corners[k], &b = corners[(k + 1) % corners.size()];
      Key ka = keyOf(a, grid), kb = keyOf(b, grid);
      if (ka == kb) continue;  // a corner of zero length, not an edge
      if (kb < ka) std::swap(ka, kb);
      Edge& e = edges[{ka, kb}];
      if (e.cells.empty()) e.ends = {a, b};
      e.cells.push_back(c);
    }
  }
  const double featureCos = std::cos(kWallFeatureAngleDeg * std::numbers::pi / 180.0);
  for (const auto& [key, e] : edges) {
    const bool open = e.cells.size() == 1;
    const bool sharp =
        e.cells.size() == 2 && normals[e.cells[0]].dot(normals[e.cells[1]]) < featureCos;
    if (open || sharp || e.cells.size() > 2) out.outlines.push_back(e.ends);
  }
}

}  // namespace

CellDrawing cellDrawing(std::span<const WallCells> walls) {
  CellDrawing out;
  for (const WallCells& wall : walls) {
    if (!wall.plane()) addWall(wall, out);
  }
  return out;
}

}  // namespace granular::app
