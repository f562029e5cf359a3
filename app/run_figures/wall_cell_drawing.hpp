#pragma once
/// The walls of a snapshot's ParaView file (wall_cells.hpp) as the particle view draws them:
/// translucent triangles and outline segments, the same as the window draws the walls themselves
/// (gui/wall_drawing.hpp), found here from the cells alone.
#include <span>
#include <vector>

#include "granular/render/particle_view.hpp"
#include "wall_cells.hpp"

namespace granular::app {

/// An edge between two cells of one wall is outlined when their normals differ by more than this
/// [deg]: a box's edges show, a faceted cylinder's facets do not (as in the window).
inline constexpr double kWallFeatureAngleDeg = 30.0;

struct CellDrawing {
  std::vector<render::Triangle> triangles;  ///< [m]
  std::vector<render::Segment> outlines;    ///< [m]
};

/// Every wall but an infinite plane (the box's edges show those): its cells cut into triangles,
/// and outlined where a cell's edge has no neighbour in the wall (a rectangle's sides, a
/// cylinder's rims, a mesh's open edges) or meets one at more than kWallFeatureAngleDeg.
CellDrawing cellDrawing(std::span<const WallCells> walls);

}  // namespace granular::app
