/// Pixel statistics (inspect.hpp).
#include "granular/render/inspect.hpp"

#include <algorithm>
#include <cstdlib>

namespace granular::render {

namespace {

PixelRegion clampRegion(const Image& image, PixelRegion r) {
  r.x0 = std::clamp(r.x0, 0, image.width);
  r.x1 = std::clamp(r.x1, r.x0, image.width);
  r.y0 = std::clamp(r.y0, 0, image.height);
  r.y1 = std::clamp(r.y1, r.y0, image.height);
  return r;
}

int channelDistance(const std::uint8_t* p, Rgba c) {
  return std::max({std::abs(p[0] - c.r), std::abs(p[1] - c.g), std::abs(p[2] - c.b)});
}

}  // namespace

InkBox inkBounds(const Image& image, Rgba background, int tolerance) {
  return inkBounds(image, background, tolerance, {0, 0, image.width, image.height});
}

InkBox inkBounds(const Image& image, Rgba background, int tolerance, PixelRegion region) {
  region = clampRegion(image, region);
  InkBox box;
  box.x0 = image.width;
  box.y0 = image.height;
  for (int y = region.y0; y < region.y1; ++y) {
    const std::uint8_t* row = image.pixels.data() + std::size_t(y) * image.width * 4;
    for (int x = region.x0; x < region.x1; ++x) {
      if (channelDistance(row + std::size_t(x) * 4, background) <= tolerance) continue;
      ++box.inkPixels;
      box.x0 = std::min(box.x0, x), box.x1 = std::max(box.x1, x);
      box.y0 = std::min(box.y0, y), box.y1 = std::max(box.y1, y);
    }
  }
  if (box.inkPixels == 0) box = InkBox{};
  return box;
}

long countColorPixels(const Image& image, Rgba color, int tolerance) {
  return countColorPixels(image, color, tolerance, {0, 0, image.width, image.height});
}

long countColorPixels(const Image& image, Rgba color, int tolerance, PixelRegion region) {
  region = clampRegion(image, region);
  long n = 0;
  for (int y = region.y0; y < region.y1; ++y) {
    const std::uint8_t* row = image.pixels.data() + std::size_t(y) * image.width * 4;
    for (int x = region.x0; x < region.x1; ++x) {
      if (channelDistance(row + std::size_t(x) * 4, color) <= tolerance) ++n;
    }
  }
  return n;
}

}  // namespace granular::render
