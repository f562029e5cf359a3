#pragma once
/// Colour bars: the key to a ColorScale, with nice ticks, tick labels and a title with units
/// (e.g. "Σ|F_ij| [N]"), vertical (labels to the right, title reading upwards beside them) or
/// horizontal (labels and title below). With levels it shows the discrete bands of a filled
/// contour map and ticks at the levels.
#include <string>
#include <vector>

#include "granular/render/canvas.hpp"
#include "granular/render/colormap.hpp"
#include "granular/render/style.hpp"

namespace granular::render {

enum class Orientation { Vertical, Horizontal };

struct ColorBarSpec {
  std::string title;  ///< with units; empty = none
  Orientation orientation = Orientation::Vertical;
  /// Two or more ascending values: discrete bands between them, band k coloured
  /// bandColor(scale.map, k, bands) like contour maps, ticks at the levels. Empty: continuous.
  std::vector<double> levels;
  double thickness = 16.0;  ///< bar thickness [px at scale 1]
  FigureStyle style;
};

/// Room across the bar that the bar, its frame, ticks, labels and title need [px], for a bar
/// `length` px long.
double colorBarExtent(const ColorScale& scale, const ColorBarSpec& spec, double length);
/// Room along the bar that labels need beyond each end [px] (half a label).
double colorBarOverhang(const ColorScale& scale, const ColorBarSpec& spec, double length);

/// Draws the bar filling `bar` exactly, with its frame just outside and ticks, labels and title
/// beyond: to the right of a vertical bar, below a horizontal one. A power of ten factored out of
/// the labels is written beyond the bar's max end.
void drawColorBarAt(Canvas& canvas, Rect bar, const ColorScale& scale, const ColorBarSpec& spec);
/// Fits the bar with its labels and title into `area`; returns the bar's rectangle.
Rect drawColorBar(Canvas& canvas, Rect area, const ColorScale& scale, const ColorBarSpec& spec);

}  // namespace granular::render
