/// Scanline polygon filling (raster.hpp).
#include "raster.hpp"

#include <algorithm>
#include <cmath>

namespace granular::render::detail {

void PolygonFiller::addEdge(Point a, Point b) {
  if (a.y == b.y) return;  // horizontal edges cross no sub-scanline
  if (!(std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(b.x) && std::isfinite(b.y))) {
    return;
  }
  int dir = 1;
  if (a.y > b.y) {
    std::swap(a, b);
    dir = -1;
  }
  edges_.push_back({a.x, a.y, b.y, (b.x - a.x) / (b.y - a.y), dir});
}

void PolygonFiller::addContour(std::span<const Point> points) {
  if (points.size() < 3) return;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) addEdge(points[i], points[i + 1]);
  addEdge(points.back(), points.front());
}

void PolygonFiller::fill(Image& image, int x0, int y0, int x1, int y1, Rgba color, FillRule rule) {
  if (edges_.empty() || x1 <= x0 || y1 <= y0 || color.a == 0) return;
  std::sort(edges_.begin(), edges_.end(), [](const Edge& a, const Edge& b) { return a.y0 < b.y0; });
  double yMax = edges_.front().y1;
  for (const Edge& e : edges_) yMax = std::max(yMax, e.y1);
  const int rowBegin = clampToInt(std::floor(edges_.front().y0), y0, y1);
  const int rowEnd = clampToInt(std::ceil(yMax), y0, y1);
  const int width = x1 - x0;
  cover_.assign(std::size_t(width) + 2, 0.0f);
  delta_.assign(std::size_t(width) + 2, 0.0f);
  active_.clear();
  constexpr float kWeight = 1.0f / kSubScanlines;
  auto inside = [rule](int winding) {
    return rule == FillRule::NonZero ? winding != 0 : (winding & 1) != 0;
  };

  std::size_t next = 0;
  // Edges entirely above the first row drawn (clipped away) are skipped, not activated.
  while (next < edges_.size() && edges_[next].y1 <= rowBegin) ++next;
  for (int row = rowBegin; row < rowEnd; ++row) {
    while (next < edges_.size() && edges_[next].y0 < row + 1) {
      if (edges_[next].y1 > row) active_.push_back(next);
      ++next;
    }
    std::erase_if(active_, [&](std::size_t i) { return edges_[i].y1 <= row; });
    if (active_.empty()) {
      if (next == edges_.size()) break;
      continue;
    }
    int touched0 = width + 1, touched1 = -1;
    auto addSpan = [&](double xa, double xb) {
      xa = std::max(xa, double(x0)) - x0;
      xb = std::min(xb, double(x1)) - x0;
      if (!(xb > xa)) return;
      const int ia = int(xa), ib = int(xb);
      if (ia == ib) {
        cover_[ia] += float(xb - xa) * kWeight;
      } else {
        cover_[ia] += float(ia + 1 - xa) * kWeight;
        delta_[ia + 1] += kWeight;
        delta_[ib] -= kWeight;
        cover_[ib] += float(xb - ib) * kWeight;
      }
      touched0 = std::min(touched0, ia);
      touched1 = std::max(touched1, ib);
    };
    for (int s = 0; s < kSubScanlines; ++s) {
      const double ys = row + (s + 0.5) / kSubScanlines;
      crossings_.clear();
      for (std::size_t i : active_) {
        const Edge& e = edges_[i];
        if (e.y0 <= ys && ys < e.y1) crossings_.push_back({e.x0 + (ys - e.y0) * e.dxdy, e.dir});
      }
      if (crossings_.size() < 2) continue;
      std::sort(crossings_.begin(), crossings_.end(),
                [](const Crossing& a, const Crossing& b) { return a.x < b.x; });
      int winding = 0;
      double spanStart = 0.0;
      for (const Crossing& c : crossings_) {
        const bool was = inside(winding);
        winding += c.dir;
        const bool is = inside(winding);
        if (!was && is) spanStart = c.x;
        if (was && !is) addSpan(spanStart, c.x);
      }
    }
    if (touched1 < 0) continue;
    std::uint8_t* base = image.pixels.data() + (std::size_t(row) * image.width + x0) * 4;
    float running = 0.0f;
    const int last = std::min(touched1, width - 1);
    for (int x = touched0; x <= last; ++x) {
      running += delta_[x];
      const float c = std::min(1.0f, cover_[x] + running);
      if (c > 1.0f / 512.0f) blendPixel(base + std::size_t(x) * 4, color, c);
    }
    std::fill(cover_.begin() + touched0, cover_.begin() + touched1 + 2, 0.0f);
    std::fill(delta_.begin() + touched0, delta_.begin() + touched1 + 2, 0.0f);
  }
}

}  // namespace granular::render::detail
