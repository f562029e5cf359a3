#pragma once
/// x–y line plots for journal figures: series as thin or bold, solid, dashed or dotted lines with
/// optional markers, horizontal reference lines, a framed legend placed where it hides the least
/// data, nice ticks and labelled axes (axes.hpp). drawPlot(Canvas&, Rect, …) draws one panel, so
/// several can share an image.
#include <optional>
#include <string>
#include <vector>

#include "granular/render/axes.hpp"
#include "granular/render/canvas.hpp"
#include "granular/render/colormap.hpp"
#include "granular/render/style.hpp"

namespace granular::render {

enum class Marker { None, Circle, Square, Triangle, Diamond };

struct Series {
  enum Dash { Solid, Dashed, Dotted };
  std::vector<double> x;  ///< abscissae [data units]
  std::vector<double> y;  ///< ordinates, as many as x [data units]; NaN breaks the line
  Rgba color = categorical(0);
  double width = 1.5;  ///< line width [px at scale 1]; 0 = markers only
  Dash dash = Solid;
  std::string label;  ///< legend text; empty = not in the legend
  Marker marker = Marker::None;
  double markerSize = 6.0;  ///< marker diameter [px at scale 1]
};

/// A horizontal line across the axes at a fixed value, e.g. a target or a measured reference.
struct ReferenceLine {
  double y = 0.0;     ///< [data units]
  std::string label;  ///< written above the line at its right end; empty = none
  Rgba color{80, 80, 80, 255};
  double width = 1.2;  ///< [px at scale 1]
  bool dashed = true;
};

struct AxisRange {
  double min = 0.0;  ///< [data units]
  double max = 1.0;  ///< [data units]
};

/// Auto picks, of nine spots inside the axes (corners first), the one over the fewest data.
enum class LegendPosition {
  Auto,
  UpperRight,
  UpperLeft,
  LowerLeft,
  LowerRight,
  OutsideRight,
  None
};

struct PlotSpec {
  std::string title;
  std::string xLabel;  ///< with units, e.g. "t [s]"
  std::string yLabel;  ///< with units, e.g. "σ₃₃ [kPa]"
  std::vector<Series> series;
  std::optional<AxisRange> xRange;  ///< fixed visible range; default: the data padded by 5 %
  std::optional<AxisRange> yRange;  ///< same; reference lines count as data
  /// Logarithmic axes (AxesSpec::xLog): data stay in their own units, the padding is 5 % of the
  /// range's decades, and values ≤ 0 are left out (a break in the line, as NaN).
  bool xLog = false, yLog = false;
  std::vector<ReferenceLine> references;
  LegendPosition legend = LegendPosition::Auto;
  bool grid = false;
  int width = 800;   ///< image width for drawPlot(spec) [px]
  int height = 500;  ///< image height for drawPlot(spec) [px]
  FigureStyle style;
};

/// A new image of spec.width × spec.height with the plot.
Image drawPlot(const PlotSpec& spec);
/// Draws the plot into `panel` of an existing canvas; returns its axes for further drawing.
Axes drawPlot(Canvas& canvas, Rect panel, const PlotSpec& spec);

/// Draws one marker centred at `at` with the given diameter [px].
void drawMarker(Canvas& canvas, Point at, Marker marker, double diameter, Rgba color);

}  // namespace granular::render
