/// Legend layout, placement and drawing for line plots (plot_legend.hpp). Sizes follow
/// Matplotlib's defaults in em of the legend font: 0.4 border pad, 2.0 line sample, 0.8 between
/// sample and label, 0.5 from the axes.
#include "plot_legend.hpp"

#include <algorithm>
#include <cmath>

namespace granular::render::detail {

namespace {

double rowHeight(const TextMetrics& m) {
  return m.ascent + m.descent;
}

}  // namespace

LegendLayout legendLayout(std::span<const LegendEntry> entries, const FigureStyle& style) {
  LegendLayout l;
  l.font = style.px(style.fontSize);
  const auto font = Font::get(FontWeight::Regular, l.font);
  const TextMetrics m = font->measure("");
  l.pad = 0.4 * l.font;
  l.handle = 2.0 * l.font;
  l.gap = 0.8 * l.font;
  l.row = rowHeight(m) + 0.35 * l.font;
  double widest = 0.0;
  for (const auto& e : entries) widest = std::max(widest, font->measure(e.label).width);
  const double n = double(entries.size());
  l.width = std::ceil(2.0 * l.pad + l.handle + l.gap + widest);
  l.height = std::ceil(2.0 * l.pad + n * rowHeight(m) + (n - 1.0) * 0.35 * l.font);
  return l;
}

Rect placeLegend(const LegendLayout& l, const Rect& area, LegendPosition position,
                 std::span<const Point> obstacles, const FigureStyle& style, long* hidden) {
  const double inset = std::round(0.5 * l.font);
  const double left = area.left() + inset, right = area.right() - inset - l.width;
  const double top = area.top() + inset, bottom = area.bottom() - inset - l.height;
  const double cx = std::round(area.center().x - 0.5 * l.width);
  const double cy = std::round(area.center().y - 0.5 * l.height);
  auto box = [&](double x, double y) {
    return Rect{std::round(x), std::round(y), l.width, l.height};
  };
  switch (position) {
    case LegendPosition::UpperRight:
      return box(right, top);
    case LegendPosition::UpperLeft:
      return box(left, top);
    case LegendPosition::LowerLeft:
      return box(left, bottom);
    case LegendPosition::LowerRight:
      return box(right, bottom);
    case LegendPosition::OutsideRight:
      return box(area.right() + std::round(style.px(style.axisWidth)) + inset, area.top());
    case LegendPosition::None:
    case LegendPosition::Auto:
      break;
  }
  // Matplotlib's order of preference for "best": corners, then the middles of the sides, then
  // the centre; the first of equally good spots wins.
  const Rect candidates[] = {box(right, top),    box(left, top), box(left, bottom),
                             box(right, bottom), box(right, cy), box(left, cy),
                             box(cx, bottom),    box(cx, top),   box(cx, cy)};
  Rect best = candidates[0];
  long bestCount = -1;
  for (const Rect& c : candidates) {
    const Rect grown = c.inset(-2.0);
    long count = 0;
    for (const Point& p : obstacles) count += grown.contains(p) ? 1 : 0;
    if (bestCount < 0 || count < bestCount) {
      bestCount = count;
      best = c;
    }
  }
  if (hidden) *hidden = bestCount;
  return best;
}

void drawLegend(Canvas& canvas, const Rect& box, const LegendLayout& l,
                std::span<const LegendEntry> entries, const FigureStyle& style) {
  // A slightly translucent white box (Matplotlib's framealpha 0.8) with a light grey frame.
  Rgba fill = style.background;
  fill.a = 204;
  canvas.fillRect(box, fill);
  const double fw = std::max(1.0, std::round(style.px(1.0)));
  const Rgba edge{204, 204, 204, 255};
  canvas.fillRect({box.x, box.y, box.w, fw}, edge);
  canvas.fillRect({box.x, box.bottom() - fw, box.w, fw}, edge);
  canvas.fillRect({box.x, box.y + fw, fw, box.h - 2.0 * fw}, edge);
  canvas.fillRect({box.right() - fw, box.y + fw, fw, box.h - 2.0 * fw}, edge);

  TextStyle text;
  text.size = l.font;
  text.color = style.ink;
  text.vAlign = VAlign::Baseline;
  const TextMetrics m = canvas.measureText("", text);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const LegendEntry& e = entries[i];
    const double rowTop = box.y + l.pad + double(i) * l.row;
    const double baseline = std::round(rowTop + m.ascent);
    double y = baseline - 0.5 * m.capHeight;  // visual middle of the label
    const double x0 = box.x + l.pad;
    if (e.width > 0.0) {
      // Odd widths on pixel centres, even widths on pixel edges: the sample stays crisp.
      const double w = std::max(1.0, e.width);
      y = (int(std::lround(w)) % 2 == 1) ? std::floor(y) + 0.5 : std::round(y);
      Stroke s;
      s.color = e.color;
      s.width = e.width;
      if (e.dash == Series::Dashed) s.dash = dashedPattern(e.width);
      if (e.dash == Series::Dotted) s.dash = dottedPattern(e.width);
      canvas.line({x0, y}, {x0 + l.handle, y}, s);
    }
    if (e.marker != Marker::None)
      drawMarker(canvas, {x0 + 0.5 * l.handle, y}, e.marker, e.markerSize, e.color);
    canvas.text({x0 + l.handle + l.gap, baseline}, e.label, text);
  }
}

}  // namespace granular::render::detail
