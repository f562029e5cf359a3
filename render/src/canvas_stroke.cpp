/// Lines, outlines and circles by coverage (canvas.hpp).
///
/// Sections: dash patterns · public stroking calls · the coverage mask · segment and ring
/// coverage.
///
/// Every stroke writes its coverage into a mask with max(), then blends the mask once. Max keeps
/// the overlapping ends of consecutive segments from being inked twice (which would show as dark
/// beads along a translucent or anti-aliased polyline), and blending once lets a translucent line
/// keep one opacity along its length.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "granular/render/canvas.hpp"
#include "raster.hpp"

namespace granular::render {

// ---------------------------------------------------------------------------------------------
// Dash patterns

std::vector<double> dashedPattern(double width) {
  const double s = std::max(width, 1.0);
  return {3.7 * s, 1.6 * s};
}

std::vector<double> dottedPattern(double width) {
  const double s = std::max(width, 1.0);
  return {1.0 * s, 1.65 * s};
}

namespace {

/// Splits finite runs of a polyline (NaN or infinite points break it) and closes it if asked.
void finiteRuns(std::span<const Point> points, bool closed, std::vector<std::vector<Point>>& out) {
  std::vector<Point> run;
  auto flush = [&] {
    if (!run.empty()) out.push_back(std::move(run));
    run.clear();
  };
  for (Point p : points) {
    if (!(std::isfinite(p.x) && std::isfinite(p.y))) {
      flush();
      continue;
    }
    if (run.empty() || !(p == run.back())) run.push_back(p);
  }
  if (closed && run.size() > 2) run.push_back(run.front());
  flush();
}

/// Cuts a polyline into its dashes; the pattern restarts at each polyline.
void dashRuns(const std::vector<Point>& line, const std::vector<double>& pattern, double offset,
              std::vector<std::vector<Point>>& out) {
  double period = 0.0;
  for (double d : pattern) period += std::max(0.0, d);
  if (!(period > 0.0)) {
    out.push_back(line);
    return;
  }
  std::size_t k = 0;  // current pattern entry; even entries draw
  double left = std::fmod(std::fmod(offset, period) + period, period);
  while (left >= std::max(0.0, pattern[k])) {
    left -= std::max(0.0, pattern[k]);
    k = (k + 1) % pattern.size();
  }
  left = std::max(0.0, pattern[k]) - left;  // length remaining in entry k
  std::vector<Point> dash;
  if (k % 2 == 0) dash.push_back(line.front());
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Point a = line[i], b = line[i + 1];
    const double segment = length(b - a);
    double at = 0.0;
    while (segment - at > left) {
      at += left;
      const Point p = a + (b - a) * (at / segment);
      if (k % 2 == 0) {
        dash.push_back(p);
        out.push_back(std::move(dash));
        dash.clear();
      } else {
        dash.push_back(p);
      }
      k = (k + 1) % pattern.size();
      left = std::max(0.0, pattern[k]);
    }
    left -= segment - at;
    if (k % 2 == 0) dash.push_back(b);
  }
  if (k % 2 == 0 && !dash.empty()) out.push_back(std::move(dash));
}

float clamp01(double v) {
  return float(std::clamp(v, 0.0, 1.0));
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Public stroking calls

void Canvas::line(Point a, Point b, const Stroke& stroke) {
  const Point pts[2] = {a, b};
  polyline(pts, stroke);
}

void Canvas::polyline(std::span<const Point> points, const Stroke& stroke) {
  const std::vector<Point> copy(points.begin(), points.end());
  strokePaths(std::span<const std::vector<Point>>(&copy, 1), false, stroke);
}

void Canvas::polylines(std::span<const std::vector<Point>> lines, const Stroke& stroke) {
  strokePaths(lines, false, stroke);
}

void Canvas::strokePolygon(std::span<const Point> points, const Stroke& stroke) {
  const std::vector<Point> copy(points.begin(), points.end());
  strokePaths(std::span<const std::vector<Point>>(&copy, 1), true, stroke);
}

void Canvas::strokeRect(Rect r, const Stroke& stroke) {
  const Point corners[4] = {
      {r.left(), r.top()}, {r.right(), r.top()}, {r.right(), r.bottom()}, {r.left(), r.bottom()}};
  strokePolygon(corners, stroke);
}

void Canvas::strokeCircle(Point center, double radius, const Stroke& stroke) {
  if (!(stroke.width > 0.0) || stroke.color.a == 0) return;
  if (!stroke.dash.empty()) {
    // Dashed circles go through the polyline path; 0.25 px chords are invisible.
    const int n = std::clamp(int(std::ceil(2.0 * std::numbers::pi * radius / 2.0)), 12, 4096);
    std::vector<Point> pts(std::size_t(n) + 1);
    for (int i = 0; i <= n; ++i) {
      const double t = 2.0 * std::numbers::pi * i / n;
      pts[std::size_t(i)] = {center.x + radius * std::cos(t), center.y + radius * std::sin(t)};
    }
    polyline(pts, stroke);
    return;
  }
  ringIntoMask(center, radius, 0.5 * std::max(stroke.width, 1.0), false);
  flushMask(stroke.color, std::min(stroke.width, 1.0));
}

void Canvas::fillCircle(Point center, double radius, Rgba color) {
  if (!(radius > 0.0) || color.a == 0) return;
  ringIntoMask(center, radius, 0.0, true);
  flushMask(color, 1.0);
}

void Canvas::strokePaths(std::span<const std::vector<Point>> lines, bool closed,
                         const Stroke& stroke) {
  if (!(stroke.width > 0.0) || stroke.color.a == 0) return;
  std::vector<std::vector<Point>> runs;
  for (const auto& line : lines) finiteRuns(line, closed, runs);
  LineCap cap = stroke.cap;
  if (!stroke.dash.empty()) {
    std::vector<std::vector<Point>> dashes;
    for (const auto& run : runs) {
      if (run.size() >= 2) dashRuns(run, stroke.dash, stroke.dashOffset, dashes);
    }
    runs = std::move(dashes);
  } else if (closed) {
    cap = LineCap::Round;  // the closing point is a join, not an end
  }
  // Sub-pixel widths: one pixel wide, proportionally fainter (the ink per length is the same).
  strokeIntoMask(runs, 0.5 * std::max(stroke.width, 1.0), cap);
  flushMask(stroke.color, std::min(stroke.width, 1.0));
}

// ---------------------------------------------------------------------------------------------
// The coverage mask

void Canvas::markMask(int x, int y, float coverage) {
  float& m = mask_[std::size_t(y) * image_.width + x];
  if (coverage <= m) return;
  m = coverage;
  dirtyX0_[std::size_t(y)] = std::min(dirtyX0_[std::size_t(y)], x);
  dirtyX1_[std::size_t(y)] = std::max(dirtyX1_[std::size_t(y)], x + 1);
  dirtyY0_ = std::min(dirtyY0_, y);
  dirtyY1_ = std::max(dirtyY1_, y + 1);
}

void Canvas::flushMask(Rgba color, double opacity) {
  const float scale = float(opacity);
  for (int y = dirtyY0_; y < dirtyY1_; ++y) {
    int& x0 = dirtyX0_[std::size_t(y)];
    int& x1 = dirtyX1_[std::size_t(y)];
    float* m = mask_.data() + std::size_t(y) * image_.width;
    std::uint8_t* row = image_.pixels.data() + std::size_t(y) * image_.width * 4;
    for (int x = x0; x < x1; ++x) {
      if (m[x] > 0.0f) detail::blendPixel(row + std::size_t(x) * 4, color, m[x] * scale);
      m[x] = 0.0f;
    }
    x0 = image_.width;
    x1 = 0;
  }
  dirtyY0_ = image_.height;
  dirtyY1_ = 0;
}

void Canvas::ensureMask() {
  // Allocated on first use and kept: strokes then only touch the pixels they cover.
  if (mask_.size() == std::size_t(image_.width) * image_.height) return;
  mask_.assign(std::size_t(image_.width) * image_.height, 0.0f);
  dirtyX0_.assign(std::size_t(image_.height), image_.width);
  dirtyX1_.assign(std::size_t(image_.height), 0);
  dirtyY0_ = image_.height;
  dirtyY1_ = 0;
}

void Canvas::strokeIntoMask(std::span<const std::vector<Point>> pieces, double halfWidth,
                            LineCap cap) {
  ensureMask();
  const PixelBox box = clipBox();
  if (box.x1 <= box.x0 || box.y1 <= box.y0) return;
  for (const auto& piece : pieces) {
    if (piece.empty()) continue;
    if (piece.size() == 1) {
      // A zero-length dash: a dot with round caps, nothing with butt caps (as in PostScript).
      if (cap == LineCap::Round) segmentIntoMask(piece[0], piece[0], halfWidth, cap, cap, box);
      continue;
    }
    const std::size_t last = piece.size() - 2;
    for (std::size_t i = 0; i + 1 < piece.size(); ++i) {
      segmentIntoMask(piece[i], piece[i + 1], halfWidth, i == 0 ? cap : LineCap::Round,
                      i == last ? cap : LineCap::Round, box);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Segment and ring coverage

void Canvas::segmentIntoMask(Point a, Point b, double hw, LineCap capA, LineCap capB,
                             const PixelBox& box) {
  Point d = b - a;
  double len = length(d);
  if (!(len > 1e-9)) {
    if (capA == LineCap::Round || capB == LineCap::Round) {
      const double r = hw + 0.5;
      const int y0 = detail::clampToInt(std::floor(a.y - r), box.y0, box.y1);
      const int y1 = detail::clampToInt(std::ceil(a.y + r), box.y0, box.y1);
      const int x0 = detail::clampToInt(std::floor(a.x - r), box.x0, box.x1);
      const int x1 = detail::clampToInt(std::ceil(a.x + r), box.x0, box.x1);
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
          const float c = clamp01(hw + 0.5 - length(Point{x + 0.5, y + 0.5} - a));
          if (c > 0.0f) markMask(x, y, c);
        }
      }
    }
    return;
  }
  Point u = d * (1.0 / len);
  if (capA == LineCap::Square) {
    a = a - u * hw;
    len += hw;
    capA = LineCap::Butt;
  }
  if (capB == LineCap::Square) {
    b = b + u * hw;
    len += hw;
    capB = LineCap::Butt;
  }
  const double reach = hw + 0.5;  // farthest pixel centre with coverage
  const double xMin = std::min(a.x, b.x) - reach, xMax = std::max(a.x, b.x) + reach;
  const double yMin = std::min(a.y, b.y) - reach, yMax = std::max(a.y, b.y) + reach;
  const int y0 = detail::clampToInt(std::ceil(yMin - 0.5), box.y0, box.y1);
  const int y1 = detail::clampToInt(std::floor(yMax - 0.5), box.y0 - 1, box.y1 - 1);
  for (int y = y0; y <= y1; ++y) {
    const double yc = y + 0.5, ry = yc - a.y;
    double lo = xMin, hi = xMax;
    // Only the pixels of this row inside the slab |distance across| ≤ reach and the band
    // −reach ≤ distance along ≤ len + reach: a long diagonal touches a few pixels per row.
    if (std::abs(u.y) > 1e-12) {
      const double c1 = (u.x * ry - reach) / u.y, c2 = (u.x * ry + reach) / u.y;
      lo = std::max(lo, a.x + std::min(c1, c2));
      hi = std::min(hi, a.x + std::max(c1, c2));
    }
    if (std::abs(u.x) > 1e-12) {
      const double c1 = (-reach - u.y * ry) / u.x, c2 = (len + reach - u.y * ry) / u.x;
      lo = std::max(lo, a.x + std::min(c1, c2));
      hi = std::min(hi, a.x + std::max(c1, c2));
    }
    const int x0 = detail::clampToInt(std::ceil(lo - 0.5), box.x0, box.x1);
    const int x1 = detail::clampToInt(std::floor(hi - 0.5), box.x0 - 1, box.x1 - 1);
    for (int x = x0; x <= x1; ++x) {
      const Point rel{x + 0.5 - a.x, ry};
      const double t = dot(rel, u);
      double c;
      if (t < 0.0 && capA == LineCap::Round) {
        c = hw + 0.5 - length(rel);
      } else if (t > len && capB == LineCap::Round) {
        c = hw + 0.5 - length(rel - u * len);
      } else {
        c = std::min(1.0, hw + 0.5 - std::abs(cross(u, rel)));
        // Butt ends: a one-pixel box filter along the line, like across it.
        if (capA == LineCap::Butt) c *= std::clamp(t + 0.5, 0.0, 1.0);
        if (capB == LineCap::Butt) c *= std::clamp(len - t + 0.5, 0.0, 1.0);
      }
      if (c > 0.0) markMask(x, y, clamp01(c));
    }
  }
}

void Canvas::ringIntoMask(Point center, double radius, double hw, bool filled) {
  ensureMask();
  const PixelBox box = clipBox();
  const double reach = (filled ? radius : radius + hw) + 0.5;
  const int y0 = detail::clampToInt(std::floor(center.y - reach), box.y0, box.y1);
  const int y1 = detail::clampToInt(std::ceil(center.y + reach), box.y0, box.y1);
  const int x0 = detail::clampToInt(std::floor(center.x - reach), box.x0, box.x1);
  const int x1 = detail::clampToInt(std::ceil(center.x + reach), box.x0, box.x1);
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const double d = length(Point{x + 0.5, y + 0.5} - center);
      const double c = filled ? radius + 0.5 - d : hw + 0.5 - std::abs(d - radius);
      if (c > 0.0) markMask(x, y, clamp01(c));
    }
  }
}

}  // namespace granular::render
