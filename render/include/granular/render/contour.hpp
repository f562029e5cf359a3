#pragma once
/// Contour maps of a scalar field on a regular grid: filled bands between levels, isolines with
/// inline labels (on a straight stretch, the line broken under the text), axes in data units and
/// a colour bar; over the same axes, polylines (trajectories) and arrows (direction fields).
/// With no values, only the axes and the overlays are drawn.
#include <span>
#include <string>
#include <vector>

#include "granular/render/axes.hpp"
#include "granular/render/canvas.hpp"
#include "granular/render/colormap.hpp"
#include "granular/render/plot.hpp"
#include "granular/render/style.hpp"

namespace granular::render {

/// A line in data coordinates drawn over a map, e.g. a particle trajectory.
struct PolylineOverlay {
  std::vector<Point> points;  ///< [data units]; NaN breaks the line
  Rgba color{0, 0, 0, 255};
  double width = 1.2;  ///< [px at scale 1]
  Series::Dash dash = Series::Solid;
};

/// Arrows anchored at data points, e.g. the direction of particle motion.
struct ArrowField {
  std::vector<Point> positions;  ///< anchors [data units]
  std::vector<Point> vectors;    ///< direction and magnitude per anchor [any unit]
  /// Arrow length in data units per unit of vector; 0: the longest arrow gets 0.9 of the mean
  /// spacing between anchors (sqrt(plot area / count)).
  double scale = 0.0;
  bool centered = false;  ///< arrow centred on its anchor instead of starting there
  Rgba color{0, 0, 0, 255};
  double width = 1.2;  ///< shaft width [px at scale 1]
};

struct ContourSpec {
  std::string title;
  std::string xLabel;  ///< with units, e.g. "x [mm]"
  std::string yLabel;
  std::string colorBarTitle;  ///< with units, e.g. "Σ|F_ij| [N]"
  /// values[j][i] at x = xMin + i·(xMax − xMin)/(nx − 1), y = yMin + j·(yMax − yMin)/(ny − 1):
  /// row j = 0 is the bottom (y grows upwards). NaN marks missing data (left blank).
  std::vector<std::vector<double>> values;
  double xMin = 0.0, xMax = 1.0;  ///< first and last column [data units]
  double yMin = 0.0, yMax = 1.0;  ///< first and last row [data units]
  /// Band boundaries, ascending. Empty: nice values (1-2-5 steps) covering the data, about
  /// levelCount bands. Values outside take the colour of the nearest band.
  std::vector<double> levels;
  int levelCount = 8;
  ColorMap map = viridis;
  bool filled = true;
  bool isolines = true;  ///< at the levels strictly inside the data range
  bool labelIsolines = true;
  /// Isolines and their labels; a label switches to white or black where this colour would not
  /// stand out from the bands under it.
  Rgba isolineColor{0, 0, 0, 255};
  double isolineWidth = 0.8;  ///< [px at scale 1]
  bool colorBar = true;
  bool equalAspect = true;  ///< same length per data unit on x and y
  std::vector<PolylineOverlay> polylines;
  std::vector<ArrowField> arrows;
  int width = 800;  ///< image size for drawContour(spec) [px]
  int height = 600;
  FigureStyle style;
};

/// The levels a spec's map uses (its own, or the automatic ones).
std::vector<double> contourLevels(const ContourSpec& spec);

/// A new image of spec.width × spec.height with the map.
Image drawContour(const ContourSpec& spec);
/// Draws the map into `panel`; returns its axes for further drawing.
Axes drawContour(Canvas& canvas, Rect panel, const ContourSpec& spec);

/// Overlays on any axes, clipped to its area.
void drawPolylines(Canvas& canvas, const Axes& axes, std::span<const PolylineOverlay> lines,
                   const FigureStyle& style);
void drawArrows(Canvas& canvas, const Axes& axes, const ArrowField& field,
                const FigureStyle& style);

}  // namespace granular::render
