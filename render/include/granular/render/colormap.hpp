#pragma once
/// Colour maps, functions from [0, 1] to a colour, and the scale that maps data values onto one.
///
/// viridis is the default: perceptually uniform and readable in grey print and by colour-blind
/// readers. magma is a sequential alternative with a darker low end. jet is the rainbow of older
/// papers (the paper's figures use one) and is offered for comparison with them only: its bright
/// bands at cyan and yellow invent edges that are not in the data.
#include "granular/render/image.hpp"

namespace granular::render {

/// A colour map: t in [0, 1] → colour; t outside is clamped.
using ColorMap = Rgba (*)(double t);

Rgba viridis(double t);
Rgba magma(double t);
Rgba jet(double t);
Rgba grayscale(double t);

/// Distinct colours for line series (Matplotlib's "tab10" cycle); i wraps around.
Rgba categorical(int i);

/// Linear blend of two colours, all four channels; t = 0 gives a.
Rgba mix(Rgba a, Rgba b, double t);

/// The colour of band `band` of `bandCount` filled bands (contour maps, discrete colour bars):
/// the bands spread over the whole map, the first takes map(0) and the last map(1), so that
/// neighbouring bands are as distinct as the map allows.
Rgba bandColor(ColorMap map, int band, int bandCount);

/// Maps data values to colours: min → map(0), max → map(1), values outside clamped to the ends.
struct ColorScale {
  double min = 0.0;  ///< value shown with map(0) [data units]
  double max = 1.0;  ///< value shown with map(1) [data units]
  ColorMap map = viridis;

  /// Position of a value on the map, clamped to [0, 1]; 0.5 when min == max.
  double normalize(double value) const;
  /// Colour of a value; NaN gives transparent black (no data).
  Rgba operator()(double value) const;
};

}  // namespace granular::render
