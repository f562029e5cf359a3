/// Line plots (plot.hpp).
///
/// Sections: ranges · markers · placement (where lines, reference labels and the legend go) ·
/// drawing.
#include "granular/render/plot.hpp"

#include <algorithm>
#include <cmath>

#include "plot_legend.hpp"

namespace granular::render {

// ---------------------------------------------------------------------------------------------
// Ranges

namespace {

/// The finite data range, padded by 5 % of its span on each side (Matplotlib's margins), so
/// that curves do not run along the frame.
AxisRange paddedRange(double lo, double hi) {
  if (!(lo <= hi)) return {0.0, 1.0};
  double span = hi - lo;
  if (span <= 1e-12 * std::max(std::abs(lo), std::abs(hi))) {
    const double half = lo == 0.0 ? 0.5 : 0.05 * std::abs(lo);
    return {lo - half, hi + half};
  }
  return {lo - 0.05 * span, hi + 0.05 * span};
}

/// paddedRange for a logarithmic axis: padded by 5 % of its decades on each side (half a decade
/// around a single value); one decade, 1 to 10, when nothing is > 0.
AxisRange paddedLogRange(double lo, double hi) {
  if (!(lo > 0.0 && lo <= hi)) return {1.0, 10.0};
  const double a = std::log10(lo), b = std::log10(hi);
  const double pad = b - a > 1e-12 ? 0.05 * (b - a) : 0.5;
  return {std::pow(10.0, a - pad), std::pow(10.0, b + pad)};
}

/// Whether a value has a place on an axis: finite, and > 0 on a logarithmic one.
bool onAxis(double v, bool logarithmic) {
  return std::isfinite(v) && (!logarithmic || v > 0.0);
}

struct Extent {
  double lo = INFINITY, hi = -INFINITY;
  void add(double v) {
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
};

/// Points along the drawn lines (every few pixels) and over reference labels, inside the area:
/// what a legend placed on top would hide.
void addObstacles(std::vector<Point>& out, const std::vector<Point>& line, const Rect& area) {
  constexpr double kStep = 3.0;  // [px]
  for (std::size_t i = 0; i < line.size(); ++i) {
    const Point a = line[i];
    if (!(std::isfinite(a.x) && std::isfinite(a.y))) continue;
    if (area.contains(a)) out.push_back(a);
    if (i + 1 == line.size()) break;
    const Point b = line[i + 1];
    if (!(std::isfinite(b.x) && std::isfinite(b.y))) continue;
    const int n = int(std::min(4096.0, length(b - a) / kStep));
    for (int k = 1; k < n; ++k) {
      const Point p = a + (b - a) * (double(k) / n);
      if (area.contains(p)) out.push_back(p);
    }
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Markers

void drawMarker(Canvas& canvas, Point at, Marker marker, double d, Rgba color) {
  const double r = 0.5 * d;
  switch (marker) {
    case Marker::None:
      return;
    case Marker::Circle:
      canvas.fillCircle(at, r, color);
      return;
    case Marker::Square: {
      // Same area as the circle, so mixed markers look equally heavy.
      const double h = 0.886 * r;
      canvas.fillRect({at.x - h, at.y - h, 2.0 * h, 2.0 * h}, color);
      return;
    }
    case Marker::Triangle: {
      const Point pts[3] = {{at.x, at.y - 1.15 * r},
                            {at.x + 1.0 * r, at.y + 0.58 * r},
                            {at.x - 1.0 * r, at.y + 0.58 * r}};
      canvas.fillPolygon(pts, color);
      return;
    }
    case Marker::Diamond: {
      const double h = 1.25 * r;
      const Point pts[4] = {{at.x, at.y - h}, {at.x + h, at.y}, {at.x, at.y + h}, {at.x - h, at.y}};
      canvas.fillPolygon(pts, color);
      return;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Placement

namespace {

/// Where everything of a plot lands for one axes layout, before anything is drawn: the legend's
/// placement depends on it, and the layout depends on where the legend goes.
struct Placed {
  std::vector<std::vector<Point>> lines;  ///< per series, pixels; NaN = break
  std::vector<double> referenceY;         ///< per reference line, pixel row (crisp)
  std::vector<Point> labelAnchors;        ///< per reference line
  std::vector<VAlign> labelAligns;
  std::vector<HAlign> labelHAligns;
  std::vector<Rect> labelBoxes;
  std::vector<Point> obstacles;  ///< what a legend would hide
};

TextStyle referenceTextStyle(const FigureStyle& st) {
  TextStyle t;
  t.size = 0.9 * st.px(st.fontSize);
  t.hAlign = HAlign::Right;
  return t;
}

Placed place(const Canvas& canvas, const Axes& axes, const PlotSpec& spec) {
  const FigureStyle& st = spec.style;
  const Rect& area = axes.area();
  Placed p;
  for (const Series& s : spec.series) {
    const std::size_t n = std::min(s.x.size(), s.y.size());
    std::vector<Point> line(n);
    for (std::size_t i = 0; i < n; ++i) {
      // Non-finite values (and values ≤ 0 on a logarithmic axis) map to NaN, which the canvas
      // treats as a break in the line.
      line[i] = (onAxis(s.x[i], spec.xLog) && onAxis(s.y[i], spec.yLog))
                    ? axes.toPixel(s.x[i], s.y[i])
                    : Point{NAN, NAN};
    }
    addObstacles(p.obstacles, line, area);
    p.lines.push_back(std::move(line));
  }
  const std::size_t seriesObstacles = p.obstacles.size();
  for (const ReferenceLine& r : spec.references) {
    const double w = st.px(r.width);
    double y = axes.yToPixel(r.y);
    // Crisp: odd widths on pixel centres, even widths on pixel edges.
    y = (int(std::lround(std::max(1.0, w))) % 2 == 1) ? std::floor(y) + 0.5 : std::round(y);
    p.referenceY.push_back(y);
    // The label goes at an end of its line, above or below it: of the four spots inside the
    // axes, the one over the fewest data (right end above the line first).
    TextStyle t = referenceTextStyle(st);
    const double gap = 0.3 * t.size, inset = 0.5 * t.size;
    Point bestAnchor{area.right() - inset, y - gap};
    HAlign bestH = HAlign::Right;
    VAlign bestV = VAlign::Bottom;
    long bestCount = -1;
    for (int spot = 0; spot < 4; ++spot) {
      t.hAlign = spot % 2 == 0 ? HAlign::Right : HAlign::Left;
      t.vAlign = spot < 2 ? VAlign::Bottom : VAlign::Top;
      const Point anchor{spot % 2 == 0 ? area.right() - inset : area.left() + inset,
                         spot < 2 ? y - gap : y + gap};
      const Rect box = canvas.textBounds(anchor, r.label, t);
      if (box.top() < area.top() + 2.0 || box.bottom() > area.bottom() - 2.0) continue;
      const Rect grown = box.inset(-2.0);
      long count = 0;
      for (std::size_t i = 0; i < seriesObstacles; ++i) count += grown.contains(p.obstacles[i]);
      for (const Rect& other : p.labelBoxes) count += grown.intersects(other) ? 1000 : 0;
      if (bestCount < 0 || count < bestCount) {
        bestCount = count;
        bestAnchor = anchor;
        bestH = t.hAlign;
        bestV = t.vAlign;
      }
    }
    t.hAlign = bestH;
    t.vAlign = bestV;
    p.labelHAligns.push_back(bestH);
    p.labelAligns.push_back(bestV);
    p.labelAnchors.push_back(bestAnchor);
    const Rect box = canvas.textBounds(bestAnchor, r.label, t);
    p.labelBoxes.push_back(box);
    addObstacles(p.obstacles, {{area.left(), y}, {area.right(), y}}, area);
    if (!r.label.empty()) {
      for (double gx = box.left(); gx <= box.right(); gx += 3.0) {
        for (double gy = box.top(); gy <= box.bottom(); gy += 3.0) p.obstacles.push_back({gx, gy});
      }
    }
  }
  return p;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Drawing

Image drawPlot(const PlotSpec& spec) {
  Canvas canvas(spec.width, spec.height, spec.style.background);
  drawPlot(canvas, {0.0, 0.0, double(spec.width), double(spec.height)}, spec);
  return canvas.takeImage();
}

Axes drawPlot(Canvas& canvas, Rect panel, const PlotSpec& spec) {
  const FigureStyle& st = spec.style;

  AxesSpec axesSpec;
  axesSpec.title = spec.title;
  axesSpec.xLabel = spec.xLabel;
  axesSpec.yLabel = spec.yLabel;
  axesSpec.grid = spec.grid;
  axesSpec.xLog = spec.xLog;
  axesSpec.yLog = spec.yLog;
  axesSpec.style = st;
  Extent xs, ys;
  for (const Series& s : spec.series) {
    const std::size_t n = std::min(s.x.size(), s.y.size());
    for (std::size_t i = 0; i < n; ++i) {
      if (onAxis(s.x[i], spec.xLog) && onAxis(s.y[i], spec.yLog)) xs.add(s.x[i]), ys.add(s.y[i]);
    }
  }
  for (const ReferenceLine& r : spec.references) {
    if (onAxis(r.y, spec.yLog)) ys.add(r.y);
  }
  auto padded = [](const Extent& e, bool logarithmic) {
    return logarithmic ? paddedLogRange(e.lo, e.hi) : paddedRange(e.lo, e.hi);
  };
  const AxisRange xr = spec.xRange ? *spec.xRange : padded(xs, spec.xLog);
  const AxisRange yr = spec.yRange ? *spec.yRange : padded(ys, spec.yLog);
  axesSpec.xMin = xr.min, axesSpec.xMax = xr.max;
  axesSpec.yMin = yr.min, axesSpec.yMax = yr.max;

  std::vector<detail::LegendEntry> entries;
  for (const Series& s : spec.series) {
    if (s.label.empty()) continue;
    entries.push_back({s.label, s.color, st.px(s.width), s.dash, s.marker, st.px(s.markerSize)});
  }
  const bool legend = spec.legend != LegendPosition::None && !entries.empty();
  const detail::LegendLayout legendLayout = detail::legendLayout(entries, st);
  const double outsideReserve = legendLayout.width + std::round(0.5 * legendLayout.font);

  LegendPosition position = spec.legend;
  axesSpec.reserveRight =
      (legend && position == LegendPosition::OutsideRight) ? outsideReserve : 0.0;
  Axes axes(panel, axesSpec);
  Placed placed = place(canvas, axes, spec);
  Rect legendBox;
  if (legend) {
    long hidden = 0;
    legendBox =
        detail::placeLegend(legendLayout, axes.area(), position, placed.obstacles, st, &hidden);
    // Auto: when every spot inside would hide data, the legend moves beside the axes, unless
    // that would take more than a third of the panel's width from the data.
    if (position == LegendPosition::Auto && hidden > 0 && outsideReserve < panel.w / 3.0) {
      position = LegendPosition::OutsideRight;
      axesSpec.reserveRight = outsideReserve;
      axes = Axes(panel, axesSpec);
      placed = place(canvas, axes, spec);
      legendBox =
          detail::placeLegend(legendLayout, axes.area(), position, placed.obstacles, st, nullptr);
    }
  }
  const Rect& area = axes.area();
  axes.drawBackground(canvas);

  canvas.pushClip(area);
  for (std::size_t i = 0; i < spec.references.size(); ++i) {
    const ReferenceLine& r = spec.references[i];
    Stroke s;
    s.color = r.color;
    s.width = st.px(r.width);
    if (r.dashed) s.dash = dashedPattern(s.width);
    const double y = placed.referenceY[i];
    canvas.line({area.left(), y}, {area.right(), y}, s);
  }
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const Series& s = spec.series[k];
    const std::vector<Point>& line = placed.lines[k];
    if (s.width > 0.0) {
      Stroke stroke;
      stroke.color = s.color;
      stroke.width = st.px(s.width);
      if (s.dash == Series::Dashed) stroke.dash = dashedPattern(stroke.width);
      if (s.dash == Series::Dotted) stroke.dash = dottedPattern(stroke.width);
      canvas.polyline(line, stroke);
    }
    if (s.marker != Marker::None) {
      for (const Point& p : line) {
        if (std::isfinite(p.x)) drawMarker(canvas, p, s.marker, st.px(s.markerSize), s.color);
      }
    }
  }
  canvas.popClip();

  // Reference labels on a translucent backing, so that they stay legible over data.
  for (std::size_t i = 0; i < spec.references.size(); ++i) {
    const ReferenceLine& r = spec.references[i];
    if (r.label.empty()) continue;
    TextStyle t = referenceTextStyle(st);
    t.color = r.color;
    t.vAlign = placed.labelAligns[i];
    t.hAlign = placed.labelHAligns[i];
    Rgba backing = st.background;
    backing.a = 170;
    canvas.fillRect(placed.labelBoxes[i].inset(-1.0).intersect(area), backing);
    canvas.text(placed.labelAnchors[i], r.label, t);
  }

  axes.drawFrame(canvas);
  if (legend) detail::drawLegend(canvas, legendBox, legendLayout, entries, st);
  return axes;
}

}  // namespace granular::render
