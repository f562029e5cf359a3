/// Contour maps and overlays (contour.hpp).
///
/// Sections: levels · isoline labels · overlays · drawing.
///
/// Bands are painted as nested superlevel sets: first the whole field in the lowest band's
/// colour, then {f ≥ l₁} in the next, and so on. Each fill covers the previous one's boundary
/// completely, so anti-aliased band edges blend band into band and never let the background
/// show through as a faint seam (as abutting polygons would).
#include "granular/render/contour.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "contour_geometry.hpp"
#include "granular/render/colorbar.hpp"

namespace granular::render {

// ---------------------------------------------------------------------------------------------
// Levels

namespace {

struct ValueRange {
  double lo = INFINITY, hi = -INFINITY;
  bool any() const { return lo <= hi; }
};

ValueRange valueRange(const std::vector<std::vector<double>>& values) {
  ValueRange r;
  for (const auto& row : values) {
    for (double v : row) {
      if (std::isfinite(v)) r.lo = std::min(r.lo, v), r.hi = std::max(r.hi, v);
    }
  }
  return r;
}

/// Grid size; throws when rows differ in length.
std::pair<int, int> gridSize(const ContourSpec& spec) {
  const int ny = int(spec.values.size());
  const int nx = ny > 0 ? int(spec.values.front().size()) : 0;
  for (const auto& row : spec.values) {
    if (int(row.size()) != nx) throw std::invalid_argument("ContourSpec: rows differ in length");
  }
  return {nx, ny};
}

}  // namespace

std::vector<double> contourLevels(const ContourSpec& spec) {
  if (!spec.levels.empty()) {
    std::vector<double> levels;
    for (double l : spec.levels) {
      if (std::isfinite(l)) levels.push_back(l);
    }
    std::sort(levels.begin(), levels.end());
    levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
    return levels;
  }
  const ValueRange r = valueRange(spec.values);
  if (!r.any()) return {};
  double lo = r.lo, hi = r.hi;
  if (lo == hi) {
    const double d = lo == 0.0 ? 1.0 : 0.05 * std::abs(lo);
    lo -= d, hi += d;
  }
  const int count = std::max(2, spec.levelCount);
  const double step = niceTicks(lo, hi, std::max(2, count / 2 + 1), count + 1).step;
  // Whole steps covering the data: the first level at or below the minimum, the last at or above
  // the maximum.
  const double first = std::floor(lo / step + 1e-9) * step;
  const double last = std::ceil(hi / step - 1e-9) * step;
  return ticksWithStep(first, last, step).values;
}

// ---------------------------------------------------------------------------------------------
// Isoline labels

namespace {

/// A polyline parameterised by arc length [px].
struct Path {
  std::vector<Point> points;
  std::vector<double> at;  ///< arc length at each point

  explicit Path(std::vector<Point> p) : points(std::move(p)), at(points.size(), 0.0) {
    for (std::size_t i = 1; i < points.size(); ++i) {
      at[i] = at[i - 1] + render::length(points[i] - points[i - 1]);
    }
  }
  double length() const { return at.empty() ? 0.0 : at.back(); }
  /// Index of the segment holding arc length s.
  std::size_t segment(double s) const {
    const auto it = std::upper_bound(at.begin(), at.end(), s);
    const std::size_t i = std::size_t(std::max<std::ptrdiff_t>(1, it - at.begin()));
    return std::min(i, points.size() - 1) - 1;
  }
  Point pointAt(double s) const {
    const std::size_t i = segment(s);
    const double d = at[i + 1] - at[i];
    const double t = d > 0.0 ? std::clamp((s - at[i]) / d, 0.0, 1.0) : 0.0;
    return points[i] + (points[i + 1] - points[i]) * t;
  }
  /// The stretch between arc lengths s0 < s1.
  std::vector<Point> between(double s0, double s1) const {
    std::vector<Point> out{pointAt(s0)};
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (at[i] > s0 && at[i] < s1) out.push_back(points[i]);
    }
    out.push_back(pointAt(s1));
    return out;
  }
};

struct Label {
  Point centre;
  double angle;      ///< [degrees], counter-clockwise, upright
  double halfWidth;  ///< half the gap in the line [px]
  std::string text;
};

/// Places labels on the straightest stretches of the chains, one per stretch of about an axes
/// length, away from the frame and from other labels; returns the chains with the line broken
/// under each label.
std::vector<std::vector<Point>> placeLabels(const std::vector<std::vector<Point>>& chains,
                                            const std::string& text, double textWidth,
                                            double capHeight, double font, const Rect& area,
                                            std::vector<Label>& labels) {
  std::vector<std::vector<Point>> pieces;
  const double pad = 0.35 * font;
  const double gap = textWidth + 2.0 * pad;  // the break in the line [px]
  const double straightness = 0.3 * capHeight;
  for (const auto& chain : chains) {
    Path path(chain);
    const double total = path.length();
    std::vector<std::pair<double, double>> cuts;
    if (total >= 2.0 * gap) {
      const int parts = std::clamp(int(total / (1.2 * std::max(area.w, area.h))) + 1, 1, 3);
      for (int q = 0; q < parts; ++q) {
        const double from = total * q / parts, to = total * (q + 1) / parts;
        const double middle = 0.5 * (from + to);
        double bestScore = INFINITY, bestS = 0.0;
        Label best{};
        const double step = std::max(2.0, gap / 8.0);
        for (double s = from; s + gap <= to; s += step) {
          const Point a = path.pointAt(s), b = path.pointAt(s + gap);
          const Point chord = b - a;
          const double chordLength = length(chord);
          if (chordLength < 0.85 * gap) continue;
          const Point u = chord * (1.0 / chordLength);
          double deviation = 0.0;
          for (std::size_t i = path.segment(s) + 1; i < path.points.size() && path.at[i] < s + gap;
               ++i) {
            deviation = std::max(deviation, std::abs(cross(u, path.points[i] - a)));
          }
          if (deviation > straightness) continue;
          const Point centre = (a + b) * 0.5;
          const double reach = 0.5 * gap + capHeight;
          if (centre.x - reach < area.left() || centre.x + reach > area.right() ||
              centre.y - reach < area.top() || centre.y + reach > area.bottom()) {
            continue;
          }
          bool clear = true;
          for (const Label& other : labels) {
            if (length(other.centre - centre) < other.halfWidth + 0.5 * gap + capHeight)
              clear = false;
          }
          if (!clear) continue;
          const double score = deviation + 0.01 * std::abs(s + 0.5 * gap - middle);
          if (score < bestScore) {
            bestScore = score;
            bestS = s;
            double angle = std::atan2(-chord.y, chord.x) * 180.0 / std::numbers::pi;
            if (angle > 90.0) angle -= 180.0;
            if (angle <= -90.0) angle += 180.0;
            best = {centre, angle, 0.5 * gap, text};
          }
        }
        if (std::isfinite(bestScore)) {
          labels.push_back(best);
          cuts.push_back({bestS, bestS + gap});
        }
      }
    }
    if (cuts.empty()) {
      pieces.push_back(chain);
      continue;
    }
    // The chain minus the label gaps, in order along it.
    std::sort(cuts.begin(), cuts.end());
    double from = 0.0;
    for (const auto& [a, b] : cuts) {
      if (a > from) pieces.push_back(path.between(from, a));
      from = b;
    }
    if (total > from) pieces.push_back(path.between(from, total));
  }
  return pieces;
}

double luminance(Rgba c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

/// The isoline colour for a label when it stands out from the bands around the label's centre;
/// otherwise black or white, whichever contrasts more (black labels vanish on viridis' dark end).
Rgba readableOn(const Image& image, Point centre, double radius, Rgba preferred) {
  double sum = 0.0;
  int n = 0;
  const int r = std::max(1, int(radius));
  const int cx = int(centre.x), cy = int(centre.y);
  for (int y = std::max(0, cy - r); y <= std::min(image.height - 1, cy + r); ++y) {
    for (int x = std::max(0, cx - r); x <= std::min(image.width - 1, cx + r); ++x) {
      sum += luminance(image.at(x, y));
      ++n;
    }
  }
  if (n == 0) return preferred;
  const double background = sum / n;
  if (std::abs(luminance(preferred) - background) >= 120.0) return preferred;
  return background < 128.0 ? Rgba{255, 255, 255, preferred.a} : Rgba{0, 0, 0, preferred.a};
}

std::vector<Point> toPixels(const Axes& axes, const std::vector<Point>& data) {
  std::vector<Point> px;
  px.reserve(data.size());
  for (const Point& p : data) {
    px.push_back(std::isfinite(p.x) && std::isfinite(p.y) ? axes.toPixel(p) : Point{NAN, NAN});
  }
  return px;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Overlays

void drawPolylines(Canvas& canvas, const Axes& axes, std::span<const PolylineOverlay> lines,
                   const FigureStyle& style) {
  canvas.pushClip(axes.area());
  for (const PolylineOverlay& line : lines) {
    Stroke s;
    s.color = line.color;
    s.width = style.px(line.width);
    if (line.dash == Series::Dashed) s.dash = dashedPattern(s.width);
    if (line.dash == Series::Dotted) s.dash = dottedPattern(s.width);
    canvas.polyline(toPixels(axes, line.points), s);
  }
  canvas.popClip();
}

void drawArrows(Canvas& canvas, const Axes& axes, const ArrowField& field,
                const FigureStyle& style) {
  const std::size_t n = std::min(field.positions.size(), field.vectors.size());
  if (n == 0) return;
  double scale = field.scale;
  if (!(scale > 0.0)) {
    double longest = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double m = length(field.vectors[i]);
      if (std::isfinite(m)) longest = std::max(longest, m);
    }
    const AxesSpec& a = axes.spec();
    const double spacing = std::sqrt(std::abs((a.xMax - a.xMin) * (a.yMax - a.yMin)) / double(n));
    scale = longest > 0.0 ? 0.9 * spacing / longest : 0.0;
  }
  ArrowStyle arrow;
  arrow.color = field.color;
  arrow.shaftWidth = style.px(field.width);
  canvas.pushClip(axes.area());
  for (std::size_t i = 0; i < n; ++i) {
    const Point v = field.vectors[i] * scale;
    const Point tail = field.centered ? field.positions[i] - v * 0.5 : field.positions[i];
    const Point tip = tail + v;
    if (!(std::isfinite(tail.x) && std::isfinite(tail.y) && std::isfinite(tip.x) &&
          std::isfinite(tip.y))) {
      continue;
    }
    canvas.arrow(axes.toPixel(tail), axes.toPixel(tip), arrow);
  }
  canvas.popClip();
}

// ---------------------------------------------------------------------------------------------
// Drawing

Image drawContour(const ContourSpec& spec) {
  Canvas canvas(spec.width, spec.height, spec.style.background);
  drawContour(canvas, {0.0, 0.0, double(spec.width), double(spec.height)}, spec);
  return canvas.takeImage();
}

Axes drawContour(Canvas& canvas, Rect panel, const ContourSpec& spec) {
  const FigureStyle& st = spec.style;
  const auto [nx, ny] = gridSize(spec);
  const ValueRange range = valueRange(spec.values);
  const bool hasField = nx >= 2 && ny >= 2 && range.any();
  const std::vector<double> levels = hasField ? contourLevels(spec) : std::vector<double>{};
  const int bands = int(levels.size()) - 1;
  const ColorScale scale{levels.empty() ? 0.0 : levels.front(),
                         levels.empty() ? 1.0 : levels.back(), spec.map};
  ColorBarSpec bar;
  bar.title = spec.colorBarTitle;
  bar.levels = levels;
  bar.style = st;
  const bool showBar = spec.colorBar && spec.filled && bands >= 1;
  const double font = st.px(st.fontSize);
  const double barGap = std::round(1.2 * font);

  AxesSpec axesSpec;
  axesSpec.title = spec.title;
  axesSpec.xLabel = spec.xLabel;
  axesSpec.yLabel = spec.yLabel;
  axesSpec.xMin = spec.xMin, axesSpec.xMax = spec.xMax;
  axesSpec.yMin = spec.yMin, axesSpec.yMax = spec.yMax;
  axesSpec.equalAspect = spec.equalAspect;
  axesSpec.style = st;
  if (showBar) axesSpec.reserveRight = barGap + colorBarExtent(scale, bar, 0.8 * panel.h);
  const Axes axes(panel, axesSpec);
  const Rect& area = axes.area();

  detail::GridField field;
  field.nx = nx, field.ny = ny;
  field.values = &spec.values;
  field.x0 = spec.xMin, field.x1 = spec.xMax, field.y0 = spec.yMin, field.y1 = spec.yMax;

  canvas.pushClip(area);
  if (hasField && spec.filled && bands >= 1) {
    for (int k = 0; k < bands; ++k) {
      const double level = k == 0 ? -INFINITY : levels[std::size_t(k)];
      std::vector<std::vector<Point>> polygons = detail::superlevelPolygons(field, level);
      for (auto& poly : polygons) poly = toPixels(axes, poly);
      canvas.fillPath(polygons, bandColor(spec.map, k, bands));
    }
  }
  std::vector<Label> labels;
  TextStyle labelText;
  labelText.size = 0.85 * font;
  labelText.color = spec.isolineColor;
  labelText.hAlign = HAlign::Center;
  labelText.vAlign = VAlign::Middle;
  if (hasField && spec.isolines) {
    Stroke stroke;
    stroke.color = spec.isolineColor;
    stroke.width = st.px(spec.isolineWidth);
    const Ticks format = niceTicks(levels.front(), levels.back());
    double step = INFINITY;
    for (std::size_t i = 0; i + 1 < levels.size(); ++i)
      step = std::min(step, levels[i + 1] - levels[i]);
    const double unit = std::pow(10.0, -format.exponent);
    const TextMetrics m = canvas.measureText("", labelText);
    for (double level : levels) {
      if (!(level > range.lo && level < range.hi)) continue;
      std::vector<std::vector<Point>> chains = detail::isolines(field, level);
      for (auto& chain : chains) chain = toPixels(axes, chain);
      if (spec.labelIsolines) {
        const std::string text =
            formatTick(level * unit, (std::isfinite(step) ? step : 1.0) * unit);
        const double w = canvas.measureText(text, labelText).width;
        chains = placeLabels(chains, text, w, m.capHeight, labelText.size, area, labels);
      }
      canvas.polylines(chains, stroke);
    }
  }
  for (const Label& l : labels) {
    labelText.angle = l.angle;
    labelText.color = readableOn(canvas.image(), l.centre, l.halfWidth, spec.isolineColor);
    canvas.text(l.centre, l.text, labelText);
  }
  canvas.popClip();

  drawPolylines(canvas, axes, spec.polylines, st);
  for (const ArrowField& f : spec.arrows) drawArrows(canvas, axes, f, st);
  axes.drawFrame(canvas);
  if (showBar) {
    const double lw = axes.lineWidth();
    const double x = area.right() + lw + barGap;
    drawColorBarAt(canvas, Rect{x, area.top(), std::round(st.px(bar.thickness)), area.h}, scale,
                   bar);
  }
  return axes;
}

}  // namespace granular::render
