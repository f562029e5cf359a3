#pragma once
/// The look shared by the 2-D figures (line plots, contour maps, colour bars): sizes, fonts and
/// colours. Lengths are given at scale 1, which stands for 100 dpi like Matplotlib's default
/// figure, so that its defaults carry over: 10 pt text is 13.9 px there, a 0.8 pt frame is 1.1 px.
/// A figure for print at 300 dpi uses scale 3 and keeps every proportion.
#include "granular/render/image.hpp"

namespace granular::render {

struct FigureStyle {
  double scale = 1.0;           ///< multiplies every length below [-]; dpi / 100
  double fontSize = 13.9;       ///< tick labels and legend [px at scale 1] (10 pt)
  double labelFontSize = 13.9;  ///< axis labels [px at scale 1] (10 pt)
  double titleFontSize = 16.7;  ///< panel title [px at scale 1] (12 pt)
  double axisWidth = 1.0;       ///< frame and ticks [px at scale 1]; rounded to whole pixels
  double tickLength = 4.9;      ///< outward tick length [px at scale 1] (3.5 pt)
  double margin = 8.0;          ///< free border around a panel's ink [px at scale 1]
  Rgba ink{0, 0, 0, 255};       ///< frame, ticks and text
  Rgba background{255, 255, 255, 255};
  Rgba gridColor{220, 220, 220, 255};

  /// The style for a target resolution [dots per inch].
  static FigureStyle forDpi(double dpi) {
    FigureStyle s;
    s.scale = dpi / 100.0;
    return s;
  }
  /// A length given at scale 1, in pixels of this figure [px].
  double px(double lengthAtScale1) const { return lengthAtScale1 * scale; }
};

}  // namespace granular::render
