#pragma once
/// Cartesian axes for the 2-D figures: a layout that fits tick labels, axis labels and a title
/// inside a panel, the data → pixel mapping, and the frame (spines, outward ticks, labels).
/// Line plots (plot.hpp) and contour maps (contour.hpp) both draw on one.
#include <string>

#include "granular/render/canvas.hpp"
#include "granular/render/style.hpp"
#include "granular/render/ticks.hpp"

namespace granular::render {

struct AxesSpec {
  std::string title;              ///< above the axes; empty = none
  std::string xLabel;             ///< with units, e.g. "t [s]"; empty = none
  std::string yLabel;             ///< drawn rotated, reading upwards
  double xMin = 0.0, xMax = 1.0;  ///< visible x range [data units]; xMin > xMax flips the axis
  double yMin = 0.0, yMax = 1.0;  ///< visible y range [data units]; y grows upwards
  /// Logarithmic axes: every decade equally long, ticks at the powers of ten labelled "10⁻⁴"
  /// (logTicks); the range must then be > 0 (else one decade, 1 to 10, is shown).
  bool xLog = false, yLog = false;
  bool equalAspect = false;   ///< one data unit equally long on both axes (maps; linear axes only)
  bool grid = false;          ///< light lines at the ticks, under the data
  double reserveRight = 0.0;  ///< width kept free right of the axes (colour bar, legend) [px]
  FigureStyle style;
};

/// Ticks for an axis `length` px long labelled at `fontSize` px: niceTicks' choice (at most one
/// tick per two ems), made coarser until neighbouring labels keep one em apart (horizontal axis)
/// or 0.8 em between their cap heights (vertical axis). `logarithmic`: logTicks, labelling every
/// first, second, third, fifth, tenth … power of ten, the first whose labels keep apart.
Ticks ticksForAxis(double lo, double hi, double length, bool horizontal, double fontSize,
                   bool logarithmic = false);

class Axes {
 public:
  /// Lays out the axes in `panel` [px]: the data area shrinks until the frame, tick labels,
  /// axis labels and title fit inside the panel less the style's margin; ticks are chosen so
  /// that neighbouring labels keep at least one em apart.
  Axes(Rect panel, const AxesSpec& spec);

  const AxesSpec& spec() const { return spec_; }
  const Rect& panel() const { return panel_; }
  /// The data area [px]; its edges are whole pixels and the frame lies just outside it.
  const Rect& area() const { return area_; }
  /// The strip `reserveRight` wide at the right of the panel, beside the area, same height.
  Rect reserved() const;
  const Ticks& xTicks() const { return xTicks_; }
  const Ticks& yTicks() const { return yTicks_; }
  /// Frame and tick line width, whole pixels [px].
  int lineWidth() const { return lineWidth_; }

  /// Data → pixel; on a logarithmic axis a value ≤ 0 has no pixel (NaN).
  double xToPixel(double x) const;
  double yToPixel(double y) const;
  Point toPixel(double x, double y) const { return {xToPixel(x), yToPixel(y)}; }
  Point toPixel(Point data) const { return toPixel(data.x, data.y); }
  Point toData(Point pixel) const;

  /// Grid lines (if enabled) over the area; draw before the data.
  void drawBackground(Canvas& canvas) const;
  /// Spines, ticks, tick labels, axis labels, multipliers and title; draw after the data.
  void drawFrame(Canvas& canvas) const;

 private:
  void layout();
  /// Where a value lies along its axis, 0 at the range's min and 1 at its max (log10 on a
  /// logarithmic axis).
  double xFraction(double x) const;
  double yFraction(double y) const;

  AxesSpec spec_;
  Rect panel_;
  Rect area_;
  Ticks xTicks_, yTicks_;
  int lineWidth_ = 1;
  bool multiplierRow_ = false;  ///< the y multiplier has a row of its own above the frame
};

}  // namespace granular::render
