#pragma once
/// Pixel statistics for tests and sanity checks of figures: is there ink, where, and are the
/// expected colours present (a colour bar's ends, the series' colours, dark label text).
#include "granular/render/image.hpp"

namespace granular::render {

/// A rectangle of pixels [x0, x1) × [y0, y1).
struct PixelRegion {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

/// Where the ink is: the bounding box of the pixels that differ from the background.
struct InkBox {
  int x0 = 0, y0 = 0;    ///< first inked column and row
  int x1 = -1, y1 = -1;  ///< last inked column and row (inclusive); −1 when there is none
  long inkPixels = 0;    ///< number of inked pixels
  bool empty() const { return inkPixels == 0; }
};

/// Pixels with some RGB channel more than `tolerance` away from the background count as ink.
InkBox inkBounds(const Image& image, Rgba background, int tolerance);
InkBox inkBounds(const Image& image, Rgba background, int tolerance, PixelRegion region);

/// Pixels whose RGB channels are all within `tolerance` of `color`.
long countColorPixels(const Image& image, Rgba color, int tolerance);
long countColorPixels(const Image& image, Rgba color, int tolerance, PixelRegion region);

}  // namespace granular::render
