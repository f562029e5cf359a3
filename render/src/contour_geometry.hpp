#pragma once
/// Internal: contour geometry on a regular grid (contour.hpp). Each cell is split into four
/// triangles around its centre, whose value is the mean of the corners; on a triangle the field is
/// linear, so level sets are straight segments and the saddle ambiguity of plain marching squares
/// does not arise. Crossing points are interpolated from a vertex pair in one fixed order, so the
/// filled bands and the isolines share bit-identical vertices and neighbouring pieces meet
/// without gaps.
#include <vector>

#include "granular/render/geometry.hpp"

namespace granular::render::detail {

/// A scalar field sampled on nx × ny nodes spanning [x0, x1] × [y0, y1] (data units, y up).
struct GridField {
  int nx = 0, ny = 0;
  const std::vector<std::vector<double>>* values = nullptr;  ///< values[j][i]
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;

  double value(int i, int j) const { return (*values)[std::size_t(j)][std::size_t(i)]; }
  Point node(int i, int j) const {
    return {x0 + (x1 - x0) * i / (nx - 1), y0 + (y1 - y0) * j / (ny - 1)};
  }
};

/// Counter-clockwise polygons (data units) covering {f ≥ level} over the cells whose corners all
/// have values; with level = −∞, all of those cells. Runs of cells entirely inside a row merge
/// into one rectangle.
std::vector<std::vector<Point>> superlevelPolygons(const GridField& field, double level);

/// The level set {f = level} as polylines (data units); closed loops repeat their first point.
std::vector<std::vector<Point>> isolines(const GridField& field, double level);

}  // namespace granular::render::detail
