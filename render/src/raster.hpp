#pragma once
/// Internal: pixel blending and the scanline polygon filler behind Canvas (canvas.hpp).
#include <cstdint>
#include <span>
#include <vector>

#include "granular/render/canvas.hpp"

namespace granular::render::detail {

/// A pixel coordinate clamped to [lo, hi] before conversion, so that far-off or NaN geometry
/// (data outside the axes) cannot overflow an int; NaN gives lo.
inline int clampToInt(double v, int lo, int hi) {
  if (!(v > lo)) return lo;
  if (v > hi) return hi;
  return int(v);
}

/// Blends `c` over the pixel at `p` (RGBA bytes, non-premultiplied) with the colour's alpha
/// scaled by `coverage` ∈ [0, 1].
inline void blendPixel(std::uint8_t* p, Rgba c, float coverage) {
  const float a = coverage * (float(c.a) * (1.0f / 255.0f));
  if (a <= 0.0f) return;
  if (p[3] == 255) {  // opaque destination, the common case
    p[0] = std::uint8_t(float(p[0]) + (float(c.r) - float(p[0])) * a + 0.5f);
    p[1] = std::uint8_t(float(p[1]) + (float(c.g) - float(p[1])) * a + 0.5f);
    p[2] = std::uint8_t(float(p[2]) + (float(c.b) - float(p[2])) * a + 0.5f);
    return;
  }
  const float da = float(p[3]) * (1.0f / 255.0f);
  const float keep = da * (1.0f - a);
  const float outA = a + keep;
  if (outA <= 0.0f) return;
  const float inv = 1.0f / outA;
  p[0] = std::uint8_t((float(c.r) * a + float(p[0]) * keep) * inv + 0.5f);
  p[1] = std::uint8_t((float(c.g) * a + float(p[1]) * keep) * inv + 0.5f);
  p[2] = std::uint8_t((float(c.b) * a + float(p[2]) * keep) * inv + 0.5f);
  p[3] = std::uint8_t(outA * 255.0f + 0.5f);
}

/// Scan converts closed polygons: 16 sub-scanlines per pixel row, exact coverage along each
/// sub-scanline, so edges get 17 vertical and continuous horizontal coverage levels.
class PolygonFiller {
 public:
  static constexpr int kSubScanlines = 16;

  void clear() { edges_.clear(); }
  bool empty() const { return edges_.empty(); }
  /// A closed contour (the last point joins the first).
  void addContour(std::span<const Point> points);
  void addEdge(Point a, Point b);
  /// Fills the pixels [x0, x1) × [y0, y1) of `image` that the polygons cover.
  void fill(Image& image, int x0, int y0, int x1, int y1, Rgba color, FillRule rule);

 private:
  struct Edge {
    double x0, y0, y1, dxdy;  // y0 < y1; x at y0
    int dir;                  // +1 downward, −1 upward
  };
  struct Crossing {
    double x;
    int dir;
  };
  std::vector<Edge> edges_;
  std::vector<std::size_t> active_;
  std::vector<Crossing> crossings_;
  std::vector<float> cover_, delta_;
};

}  // namespace granular::render::detail
