/// Canvas basics, fills, text and image blits (canvas.hpp); lines are in canvas_stroke.cpp.
///
/// Sections: construction and clipping · fills · text · images.
#include "granular/render/canvas.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "raster.hpp"

namespace granular::render {

// ---------------------------------------------------------------------------------------------
// Construction and clipping

Canvas::Canvas(int width, int height, Rgba background) : image_(width, height, background) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("Canvas: size must be positive");
}

Canvas::Canvas(Image image) : image_(std::move(image)) {}

Image Canvas::takeImage() {
  Image out = std::move(image_);
  image_ = Image();
  clips_.clear();
  return out;
}

void Canvas::pushClip(Rect r) {
  const PixelBox current = clipBox();
  PixelBox b;
  // A pixel is inside when its centre is: centre i + 0.5 ≥ left ⇔ i ≥ left − 0.5.
  b.x0 = detail::clampToInt(std::ceil(r.left() - 0.5), current.x0, current.x1);
  b.y0 = detail::clampToInt(std::ceil(r.top() - 0.5), current.y0, current.y1);
  b.x1 = detail::clampToInt(std::ceil(r.right() - 0.5), current.x0, current.x1);
  b.y1 = detail::clampToInt(std::ceil(r.bottom() - 0.5), current.y0, current.y1);
  b.x1 = std::max(b.x1, b.x0);
  b.y1 = std::max(b.y1, b.y0);
  clips_.push_back(b);
}

void Canvas::popClip() {
  if (!clips_.empty()) clips_.pop_back();
}

Rect Canvas::clip() const {
  const PixelBox b = clipBox();
  return Rect::fromEdges(b.x0, b.y0, b.x1, b.y1);
}

Canvas::PixelBox Canvas::clipBox() const {
  if (!clips_.empty()) return clips_.back();
  return {0, 0, image_.width, image_.height};
}

// ---------------------------------------------------------------------------------------------
// Fills

void Canvas::fillPath(std::span<const std::vector<Point>> contours, Rgba color, FillRule rule) {
  detail::PolygonFiller filler;
  for (const auto& c : contours) filler.addContour(c);
  const PixelBox b = clipBox();
  filler.fill(image_, b.x0, b.y0, b.x1, b.y1, color, rule);
}

void Canvas::fillPolygon(std::span<const Point> points, Rgba color, FillRule rule) {
  detail::PolygonFiller filler;
  filler.addContour(points);
  const PixelBox b = clipBox();
  filler.fill(image_, b.x0, b.y0, b.x1, b.y1, color, rule);
}

void Canvas::fillRect(Rect r, Rgba color) {
  if (r.empty()) return;
  const Point corners[4] = {
      {r.left(), r.top()}, {r.right(), r.top()}, {r.right(), r.bottom()}, {r.left(), r.bottom()}};
  fillPolygon(corners, color);
}

void Canvas::arrow(Point tail, Point tip, const ArrowStyle& style) {
  const Point d = tip - tail;
  const double len = length(d);
  if (!(len > 1e-9)) return;
  const Point u = d * (1.0 / len);
  const Point n{-u.y, u.x};
  double headLength =
      style.headLength > 0.0 ? style.headLength : std::max(4.5 * style.shaftWidth, 5.0);
  double headHalf =
      0.5 * (style.headWidth > 0.0 ? style.headWidth : std::max(3.5 * style.shaftWidth, 4.0));
  double shaftHalf = 0.5 * style.shaftWidth;
  if (len < headLength) {
    // A short arrow keeps its proportions instead of growing a head longer than itself.
    const double s = len / headLength;
    headLength *= s;
    headHalf *= s;
    shaftHalf = std::min(shaftHalf, headHalf);
  }
  const Point base = tip - u * headLength;
  const Point outline[7] = {tail + n * shaftHalf, base + n * shaftHalf, base + n * headHalf, tip,
                            base - n * headHalf,  base - n * shaftHalf, tail - n * shaftHalf};
  fillPolygon(outline, style.color);
}

// ---------------------------------------------------------------------------------------------
// Text

namespace {

struct TextFrame {
  Point along;   ///< unit vector along the baseline
  Point down;    ///< unit vector from ascender to descender
  Point origin;  ///< pen start on the baseline [px]
  TextMetrics metrics;
  double u0;  ///< pen start relative to the anchor, along the baseline [px]
  double v0;  ///< baseline relative to the anchor, downwards [px]
};

/// Angle in (−180, 180] degrees.
double normalizedAngle(double degrees) {
  double a = std::fmod(degrees, 360.0);
  if (a <= -180.0) a += 360.0;
  if (a > 180.0) a -= 360.0;
  return a;
}

TextFrame textFrame(Point anchor, const TextMetrics& m, const TextStyle& style) {
  TextFrame f;
  f.metrics = m;
  const double a = normalizedAngle(style.angle) * std::numbers::pi / 180.0;
  // Counter-clockwise as seen on screen, where y points down.
  f.along = {std::cos(a), -std::sin(a)};
  f.down = {std::sin(a), std::cos(a)};
  f.u0 = style.hAlign == HAlign::Left     ? 0.0
         : style.hAlign == HAlign::Center ? -0.5 * m.width
                                          : -m.width;
  switch (style.vAlign) {
    case VAlign::Top:
      f.v0 = m.ascent;
      break;
    case VAlign::Middle:
      f.v0 = 0.5 * m.capHeight;
      break;
    case VAlign::Baseline:
      f.v0 = 0.0;
      break;
    case VAlign::Bottom:
      f.v0 = -m.descent;
      break;
  }
  f.origin = anchor + f.along * f.u0 + f.down * f.v0;
  return f;
}

Rect frameBounds(const TextFrame& f) {
  const double us[2] = {0.0, f.metrics.width};
  const double vs[2] = {-f.metrics.ascent, f.metrics.descent};
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (double u : us) {
    for (double v : vs) {
      const Point p = f.origin + f.along * u + f.down * v;
      x0 = std::min(x0, p.x), x1 = std::max(x1, p.x);
      y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    }
  }
  return Rect::fromEdges(x0, y0, x1, y1);
}

}  // namespace

TextMetrics Canvas::measureText(std::string_view text, const TextStyle& style) const {
  return Font::get(style.weight, style.size)->measure(text);
}

Rect Canvas::textBounds(Point anchor, std::string_view text, const TextStyle& style) const {
  return frameBounds(textFrame(anchor, measureText(text, style), style));
}

Rect Canvas::text(Point anchor, std::string_view text, const TextStyle& style) {
  const auto font = Font::get(style.weight, style.size);
  const TextFrame f = textFrame(anchor, font->measure(text), style);
  const Rect bounds = frameBounds(f);
  // Text anchored far off the canvas (or at NaN) has nothing to draw.
  constexpr double kFar = 1e7;
  if (text.empty() || style.color.a == 0 || !(std::abs(f.origin.x) < kFar) ||
      !(std::abs(f.origin.y) < kFar)) {
    return bounds;
  }
  const double angle = normalizedAngle(style.angle);
  const PixelBox clip = clipBox();
  auto put = [&](int x, int y, std::uint8_t coverage) {
    if (coverage == 0 || x < clip.x0 || x >= clip.x1 || y < clip.y0 || y >= clip.y1) return;
    detail::blendPixel(image_.pixels.data() + (std::size_t(y) * image_.width + x) * 4, style.color,
                       float(coverage) * (1.0f / 255.0f));
  };

  if (angle == 0.0) {
    // The baseline snaps to a pixel row (the hinting aligned the glyphs to it); the pen keeps its
    // sub-pixel position along the row.
    const int baseline = int(std::lround(f.origin.y));
    const double column = std::floor(f.origin.x);
    const TextRaster r = font->rasterize(text, f.origin.x - column);
    const int left = int(column) - r.originX, top = baseline - r.baselineY;
    for (int y = 0; y < r.height; ++y) {
      for (int x = 0; x < r.width; ++x)
        put(left + x, top + y, r.coverage[std::size_t(y) * r.width + x]);
    }
  } else if (angle == 90.0) {
    // Reads upwards: raster column c lands in canvas row rowOfPen − (c − originX) − 1, raster
    // row r in canvas column baselineColumn + (r − baselineY).
    const int baseline = int(std::lround(f.origin.x));
    const double rowOfPen = std::ceil(f.origin.y);
    const TextRaster r = font->rasterize(text, rowOfPen - f.origin.y);
    for (int y = 0; y < r.height; ++y) {
      for (int x = 0; x < r.width; ++x) {
        put(baseline + (y - r.baselineY), int(rowOfPen) - (x - r.originX) - 1,
            r.coverage[std::size_t(y) * r.width + x]);
      }
    }
  } else if (angle == -90.0) {
    // Reads downwards: the mirror image of the case above.
    const int baseline = int(std::lround(f.origin.x));
    const double rowOfPen = std::floor(f.origin.y);
    const TextRaster r = font->rasterize(text, f.origin.y - rowOfPen);
    for (int y = 0; y < r.height; ++y) {
      for (int x = 0; x < r.width; ++x) {
        put(baseline - (y - r.baselineY) - 1, int(rowOfPen) + (x - r.originX),
            r.coverage[std::size_t(y) * r.width + x]);
      }
    }
  } else {
    auto contours = font->outline(text);
    for (auto& contour : contours) {
      for (Point& p : contour) p = f.origin + f.along * p.x + f.down * p.y;
    }
    fillPath(contours, style.color, FillRule::NonZero);
  }
  return bounds;
}

// ---------------------------------------------------------------------------------------------
// Images

void Canvas::blit(const Image& source, Point topLeft) {
  if (source.empty() || !(std::abs(topLeft.x) < 1e7) || !(std::abs(topLeft.y) < 1e7)) return;
  const int left = int(std::lround(topLeft.x)), top = int(std::lround(topLeft.y));
  const PixelBox clip = clipBox();
  const int x0 = std::max(clip.x0, left), x1 = std::min(clip.x1, left + source.width);
  const int y0 = std::max(clip.y0, top), y1 = std::min(clip.y1, top + source.height);
  for (int y = y0; y < y1; ++y) {
    const std::uint8_t* src = source.pixels.data() + (std::size_t(y - top) * source.width) * 4;
    std::uint8_t* dst = image_.pixels.data() + std::size_t(y) * image_.width * 4;
    for (int x = x0; x < x1; ++x) {
      const std::uint8_t* s = src + std::size_t(x - left) * 4;
      detail::blendPixel(dst + std::size_t(x) * 4, {s[0], s[1], s[2], s[3]}, 1.0f);
    }
  }
}

void Canvas::blit(const Image& source, Rect destination, Filter filter) {
  if (source.empty() || !(std::abs(destination.x) < 1e7) || !(std::abs(destination.y) < 1e7) ||
      !(destination.w < 1e7) || !(destination.h < 1e7)) {
    return;
  }
  const int dx0 = int(std::lround(destination.left())), dy0 = int(std::lround(destination.top()));
  const int dx1 = int(std::lround(destination.right()));
  const int dy1 = int(std::lround(destination.bottom()));
  if (dx1 <= dx0 || dy1 <= dy0) return;
  if (dx1 - dx0 == source.width && dy1 - dy0 == source.height) {
    blit(source, Point{double(dx0), double(dy0)});
    return;
  }
  const double sx = double(source.width) / (dx1 - dx0);
  const double sy = double(source.height) / (dy1 - dy0);
  const PixelBox clip = clipBox();
  // Filters average premultiplied colours, so transparent pixels do not bleed their colour.
  struct Premul {
    double r = 0, g = 0, b = 0, a = 0;
    void add(const std::uint8_t* p, double w) {
      const double pa = p[3] * w;
      r += p[0] * pa, g += p[1] * pa, b += p[2] * pa, a += pa;
    }
  };
  auto pixel = [&](int x, int y) {
    x = std::clamp(x, 0, source.width - 1);
    y = std::clamp(y, 0, source.height - 1);
    return source.pixels.data() + (std::size_t(y) * source.width + x) * 4;
  };
  for (int y = std::max(dy0, clip.y0); y < std::min(dy1, clip.y1); ++y) {
    for (int x = std::max(dx0, clip.x0); x < std::min(dx1, clip.x1); ++x) {
      Premul acc;
      const double u = (x - dx0 + 0.5) * sx, v = (y - dy0 + 0.5) * sy;  // source position
      if (filter == Filter::Nearest) {
        acc.add(pixel(int(u), int(v)), 1.0);
      } else if (filter == Filter::Bilinear) {
        const double fu = u - 0.5, fv = v - 0.5;
        const int i = int(std::floor(fu)), j = int(std::floor(fv));
        const double wu = fu - i, wv = fv - j;
        acc.add(pixel(i, j), (1 - wu) * (1 - wv));
        acc.add(pixel(i + 1, j), wu * (1 - wv));
        acc.add(pixel(i, j + 1), (1 - wu) * wv);
        acc.add(pixel(i + 1, j + 1), wu * wv);
      } else {
        // Box: every source pixel under the destination pixel, weighted by the overlap.
        const double u0 = (x - dx0) * sx, u1 = u0 + sx, v0 = (y - dy0) * sy, v1 = v0 + sy;
        const double inv = 1.0 / (sx * sy);
        for (int j = int(v0); j < std::min(source.height, int(std::ceil(v1))); ++j) {
          const double wy = std::min(v1, j + 1.0) - std::max(v0, double(j));
          for (int i = int(u0); i < std::min(source.width, int(std::ceil(u1))); ++i) {
            const double wx = std::min(u1, i + 1.0) - std::max(u0, double(i));
            acc.add(pixel(i, j), wx * wy * inv);
          }
        }
      }
      if (acc.a <= 0.0) continue;
      auto byte = [](double c) { return std::uint8_t(std::clamp(std::lround(c), 0L, 255L)); };
      const Rgba c{byte(acc.r / acc.a), byte(acc.g / acc.a), byte(acc.b / acc.a), byte(acc.a)};
      detail::blendPixel(image_.pixels.data() + (std::size_t(y) * image_.width + x) * 4, c, 1.0f);
    }
  }
}

}  // namespace granular::render
