#pragma once
/// Points and rectangles in pixel coordinates: origin at the top-left corner of the image, x to
/// the right, y down, doubles so that shapes can sit between pixels (pixel (i, j) covers
/// [i, i+1) × [j, j+1), its centre is (i + 0.5, j + 0.5)).
#include <algorithm>
#include <cmath>

namespace granular::render {

/// A position or a displacement [px].
struct Point {
  double x = 0.0;  ///< [px], to the right
  double y = 0.0;  ///< [px], downwards

  friend Point operator+(Point a, Point b) { return {a.x + b.x, a.y + b.y}; }
  friend Point operator-(Point a, Point b) { return {a.x - b.x, a.y - b.y}; }
  friend Point operator*(Point a, double s) { return {a.x * s, a.y * s}; }
  friend Point operator*(double s, Point a) { return {a.x * s, a.y * s}; }
  friend bool operator==(Point, Point) = default;
};

inline double dot(Point a, Point b) {
  return a.x * b.x + a.y * b.y;
}
/// z-component of the cross product: positive when b is clockwise of a on screen (y down).
inline double cross(Point a, Point b) {
  return a.x * b.y - a.y * b.x;
}
inline double length(Point a) {
  return std::hypot(a.x, a.y);
}

/// An axis-aligned rectangle [px]; empty when w or h is not positive.
struct Rect {
  double x = 0.0;  ///< left edge [px]
  double y = 0.0;  ///< top edge [px]
  double w = 0.0;  ///< width [px]
  double h = 0.0;  ///< height [px]

  static Rect fromEdges(double left, double top, double right, double bottom) {
    return {left, top, right - left, bottom - top};
  }
  double left() const { return x; }
  double top() const { return y; }
  double right() const { return x + w; }
  double bottom() const { return y + h; }
  Point center() const { return {x + 0.5 * w, y + 0.5 * h}; }
  bool empty() const { return !(w > 0.0 && h > 0.0); }
  bool contains(Point p) const { return p.x >= x && p.x < right() && p.y >= y && p.y < bottom(); }
  /// Shrinks every side by d (grows for negative d).
  Rect inset(double d) const { return {x + d, y + d, w - 2.0 * d, h - 2.0 * d}; }
  bool intersects(const Rect& o) const {
    return x < o.right() && o.x < right() && y < o.bottom() && o.y < bottom();
  }
  Rect intersect(const Rect& o) const {
    const double l = std::max(x, o.x), t = std::max(y, o.y);
    const double r = std::min(right(), o.right()), b = std::min(bottom(), o.bottom());
    return {l, t, std::max(0.0, r - l), std::max(0.0, b - t)};
  }
  friend bool operator==(const Rect&, const Rect&) = default;
};

}  // namespace granular::render
