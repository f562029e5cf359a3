#pragma once
/// Sanity checks of a finished figure, for tests and for the commands that draw figures: a blank
/// image, ink running off the border (clipped), a missing colour bar or missing text.
#include <string>
#include <vector>

#include "granular/render/colormap.hpp"
#include "granular/render/image.hpp"

namespace granular::render {

struct FigureExpectations {
  Rgba background{255, 255, 255, 255};
  double minInkFraction = 0.02;  ///< at least this share of the pixels is not background
  int borderMargin = 2;          ///< ink keeps this many pixels from every edge [px]
  /// If set, the colour bar's two end colours must each cover at least `minBarPixels` pixels.
  ColorMap colorBarMap = nullptr;
  long minBarPixels = 30;
  /// The bar is looked for right of this fraction of the width (the data themselves may show
  /// the end colours too).
  double colorBarFromX = 0.75;
  /// Dark (text) pixels required in the top band (title) and in the bottom-left quarter
  /// (axis and tick labels, or any label) [count].
  long minTitlePixels = 20;
  long minLabelPixels = 20;
  double titleBand = 0.08;  ///< the top band's height as a fraction of the image
};

/// What is wrong with the figure; empty when nothing is.
std::vector<std::string> figureProblems(const Image& image, const FigureExpectations& expect);

}  // namespace granular::render
