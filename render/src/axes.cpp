/// Axes layout, mapping and frame (axes.hpp).
///
/// Sections: sizes · tick choice · layout · mapping · drawing.
///
/// The frame lines lie just outside the data area (area() is the inside, where data are clipped)
/// and the data range maps onto the frame lines' centres, so a value at the end of the range sits
/// on the frame like in Matplotlib, and nothing drawn inside covers the frame.
#include "granular/render/axes.hpp"

#include <algorithm>
#include <cmath>

namespace granular::render {

// ---------------------------------------------------------------------------------------------
// Sizes

namespace {

struct Sizes {
  double tickFont = 0, labelFont = 0, titleFont = 0;
  double outer = 0;  // free border inside the panel [px]
  double tickLength = 0;
  double tickPad = 0;   // tick end → tick label
  double labelPad = 0;  // tick labels → axis label
  double titlePad = 0;  // title → frame
  TextMetrics tick, label, title;
};

Sizes sizesFor(const FigureStyle& s) {
  Sizes z;
  z.tickFont = s.px(s.fontSize);
  z.labelFont = s.px(s.labelFontSize);
  z.titleFont = s.px(s.titleFontSize);
  z.outer = s.px(s.margin);
  z.tickLength = s.px(s.tickLength);
  // Matplotlib's pads: 3.5 pt, 4 pt and 6 pt against 10 pt and 12 pt text.
  z.tickPad = 0.35 * z.tickFont;
  z.labelPad = 0.4 * z.labelFont;
  z.titlePad = 0.5 * z.titleFont;
  z.tick = Font::get(FontWeight::Regular, z.tickFont)->measure("");
  z.label = Font::get(FontWeight::Regular, z.labelFont)->measure("");
  z.title = Font::get(FontWeight::Regular, z.titleFont)->measure("");
  return z;
}

double textWidth(const std::string& text, double size) {
  return Font::get(FontWeight::Regular, size)->measure(text).width;
}

double rowHeight(const TextMetrics& m) {
  return m.ascent + m.descent;
}

// ---------------------------------------------------------------------------------------------
// Tick choice

/// A value's position along an axis in the units it is drawn in: log10 on a logarithmic one.
double axisCoordinate(double v, bool logarithmic) {
  return logarithmic ? (v > 0.0 ? std::log10(v) : NAN) : v;
}

/// Whether neighbouring tick labels keep apart on an axis `length` px long: one em between
/// horizontal labels, 0.8 em between the cap heights of stacked ones.
bool labelsFit(const Ticks& t, double lo, double hi, bool logarithmic, double length,
               bool horizontal, double font, const TextMetrics& m) {
  const double span = std::abs(axisCoordinate(hi, logarithmic) - axisCoordinate(lo, logarithmic));
  if (t.values.size() < 2 || !(span > 0.0)) return true;
  for (std::size_t i = 0; i + 1 < t.values.size(); ++i) {
    const double distance = std::abs(axisCoordinate(t.values[i + 1], logarithmic) -
                                     axisCoordinate(t.values[i], logarithmic)) /
                            span * length;
    const double needed =
        horizontal ? 0.5 * (textWidth(t.labels[i], font) + textWidth(t.labels[i + 1], font)) + font
                   : m.capHeight + 0.8 * font;
    if (distance < needed) return false;
  }
  return true;
}

double maxLabelWidth(const Ticks& t, double font) {
  double w = 0.0;
  for (const auto& s : t.labels) w = std::max(w, textWidth(s, font));
  return w;
}

}  // namespace

Ticks ticksForAxis(double lo, double hi, double length, bool horizontal, double font,
                   bool logarithmic) {
  const TextMetrics m = Font::get(FontWeight::Regular, font)->measure("");
  if (logarithmic) {
    Ticks coarsest;
    for (int decades : {1, 2, 3, 5, 10, 20, 50, 100}) {
      Ticks c = logTicks(lo, hi, decades);
      if (decades == 1 || c.values.size() >= 2) coarsest = c;
      if (labelsFit(c, lo, hi, true, length, horizontal, font, m)) return c;
      if (c.step == 0.0) break;  // a short range: its labels are not powers to thin out
    }
    return coarsest;
  }
  const int maxCount = std::clamp(int(length / (2.0 * font)) + 1, 2, 8);
  Ticks t = niceTicks(lo, hi, std::min(4, maxCount), maxCount);
  if (labelsFit(t, lo, hi, false, length, horizontal, font, m)) return t;
  Ticks coarsest = t;
  for (double step : candidateSteps(lo, hi, 8)) {
    if (step <= t.step * (1.0 + 1e-9)) continue;
    Ticks c = ticksWithStep(lo, hi, step);
    if (c.values.size() >= 2) coarsest = c;
    if (labelsFit(c, lo, hi, false, length, horizontal, font, m)) return c;
  }
  return coarsest;
}

// ---------------------------------------------------------------------------------------------
// Layout

Axes::Axes(Rect panel, const AxesSpec& spec) : spec_(spec), panel_(panel) {
  auto widen = [](double& lo, double& hi, bool logarithmic) {
    if (logarithmic) {
      if (!(lo > 0.0 && hi > 0.0 && std::isfinite(lo) && std::isfinite(hi))) lo = 1.0, hi = 10.0;
      if (lo == hi) lo /= 1.1, hi *= 1.1;
      return;
    }
    if (!(std::isfinite(lo) && std::isfinite(hi))) lo = 0.0, hi = 1.0;
    if (lo == hi) {
      const double d = lo == 0.0 ? 1.0 : 0.05 * std::abs(lo);
      lo -= d, hi += d;
    }
  };
  widen(spec_.xMin, spec_.xMax, spec_.xLog);
  widen(spec_.yMin, spec_.yMax, spec_.yLog);
  layout();
}

void Axes::layout() {
  const FigureStyle& st = spec_.style;
  lineWidth_ = std::max(1, int(std::lround(st.px(st.axisWidth))));
  const Sizes z = sizesFor(st);
  const double lw = lineWidth_;

  const double topBase =
      panel_.top() + z.outer + (spec_.title.empty() ? 0.0 : rowHeight(z.title) + z.titlePad);
  const double bottomBase =
      panel_.bottom() - z.outer - rowHeight(z.tick) - z.tickPad - z.tickLength - lw;
  // The row under the tick labels holds the x label and the x multiplier.
  auto bottomFor = [&](bool labelRow) {
    return labelRow ? bottomBase - std::max(rowHeight(z.label), rowHeight(z.tick)) - z.labelPad
                    : bottomBase;
  };
  double bottom = bottomFor(!spec_.xLabel.empty());
  const double leftBase = panel_.left() + z.outer + z.tickPad + z.tickLength + lw +
                          (spec_.yLabel.empty() ? 0.0 : rowHeight(z.label) + z.labelPad);
  const double rightLimit = panel_.right() - z.outer - spec_.reserveRight;
  double left = leftBase + 2.0 * z.tickFont, right = rightLimit - lw, top = topBase + lw;

  auto fitTicks = [&](double axisLeft, double axisRight, double axisTop, double axisBottom) {
    yTicks_ =
        ticksForAxis(spec_.yMin, spec_.yMax, axisBottom - axisTop, false, z.tickFont, spec_.yLog);
    xTicks_ =
        ticksForAxis(spec_.xMin, spec_.xMax, axisRight - axisLeft, true, z.tickFont, spec_.xLog);
  };
  // The y multiplier ("×10³") shares the title's row when the centred title leaves room at its
  // left, so that panels with and without one keep their frames level.
  auto multiplierBesideTitle = [&](double axisLeft, double axisRight) {
    if (spec_.title.empty()) return false;
    const double titleLeft =
        0.5 * (axisLeft + axisRight) - 0.5 * textWidth(spec_.title, z.titleFont);
    return axisLeft - lw + textWidth(yTicks_.multiplier(), z.tickFont) + z.tickFont <= titleLeft;
  };
  for (int pass = 0; pass < 3; ++pass) {
    fitTicks(left, right, top, bottom);
    // Top: room for the y multiplier row, or for half of the top tick label.
    multiplierRow_ = yTicks_.exponent != 0 && !multiplierBesideTitle(left, right);
    top =
        topBase + lw +
        (multiplierRow_ ? rowHeight(z.tick) : (spec_.title.empty() ? 0.5 * z.tick.capHeight : 0.0));
    left = leftBase + maxLabelWidth(yTicks_, z.tickFont);
    bottom = bottomFor(!spec_.xLabel.empty() || xTicks_.exponent != 0);
    // Right: the last x tick label may overhang the frame by half its width.
    right = rightLimit - lw;
    if (!xTicks_.values.empty()) {
      const double f = xFraction(xTicks_.values.back());
      const double half = 0.5 * textWidth(xTicks_.labels.back(), z.tickFont);
      if (f > 0.0) right = std::min(right, left + (rightLimit - half - left) / f);
      const double f0 = xFraction(xTicks_.values.front());
      const double half0 = 0.5 * textWidth(xTicks_.labels.front(), z.tickFont);
      // The first label may overhang to the left past the y tick labels' column.
      const double overhang = panel_.left() + z.outer + half0 - (left + f0 * (right - left));
      if (overhang > 0.0) left += overhang;
    }
  }
  area_ = Rect::fromEdges(std::round(left), std::round(top), std::round(right), std::round(bottom));
  if (spec_.equalAspect) {
    // The same number of pixels per data unit on both axes, centred in the space laid out.
    const double sx = (area_.w + lw) / std::abs(spec_.xMax - spec_.xMin);
    const double sy = (area_.h + lw) / std::abs(spec_.yMax - spec_.yMin);
    const double s = std::min(sx, sy);
    const double w = s * std::abs(spec_.xMax - spec_.xMin) - lw;
    const double h = s * std::abs(spec_.yMax - spec_.yMin) - lw;
    area_ = {std::round(area_.x + 0.5 * (area_.w - w)), std::round(area_.y + 0.5 * (area_.h - h)),
             std::round(w), std::round(h)};
    fitTicks(area_.left(), area_.right(), area_.top(), area_.bottom());
  }
  area_.w = std::max(area_.w, 1.0);
  area_.h = std::max(area_.h, 1.0);
}

Rect Axes::reserved() const {
  return Rect::fromEdges(panel_.right() - spec_.reserveRight, area_.top(), panel_.right(),
                         area_.bottom());
}

// ---------------------------------------------------------------------------------------------
// Mapping: the range ends sit on the frame lines' centres, half a line width outside the area.

double Axes::xFraction(double x) const {
  const double lo = axisCoordinate(spec_.xMin, spec_.xLog);
  return (axisCoordinate(x, spec_.xLog) - lo) / (axisCoordinate(spec_.xMax, spec_.xLog) - lo);
}

double Axes::yFraction(double y) const {
  const double lo = axisCoordinate(spec_.yMin, spec_.yLog);
  return (axisCoordinate(y, spec_.yLog) - lo) / (axisCoordinate(spec_.yMax, spec_.yLog) - lo);
}

double Axes::xToPixel(double x) const {
  const double half = 0.5 * lineWidth_;
  const double x0 = area_.left() - half, x1 = area_.right() + half;
  return x0 + xFraction(x) * (x1 - x0);
}

double Axes::yToPixel(double y) const {
  const double half = 0.5 * lineWidth_;
  const double y0 = area_.bottom() + half, y1 = area_.top() - half;
  return y0 + yFraction(y) * (y1 - y0);
}

Point Axes::toData(Point p) const {
  const double half = 0.5 * lineWidth_;
  const double x0 = area_.left() - half, x1 = area_.right() + half;
  const double y0 = area_.bottom() + half, y1 = area_.top() - half;
  // The inverse of the fractions: along log10 of the range on a logarithmic axis.
  auto along = [](double f, double lo, double hi, bool logarithmic) {
    if (!logarithmic) return lo + f * (hi - lo);
    return std::pow(10.0, std::log10(lo) + f * (std::log10(hi) - std::log10(lo)));
  };
  return {along((p.x - x0) / (x1 - x0), spec_.xMin, spec_.xMax, spec_.xLog),
          along((p.y - y0) / (y1 - y0), spec_.yMin, spec_.yMax, spec_.yLog)};
}

// ---------------------------------------------------------------------------------------------
// Drawing

void Axes::drawBackground(Canvas& canvas) const {
  if (!spec_.grid) return;
  const FigureStyle& st = spec_.style;
  const double lw = lineWidth_;
  for (double v : xTicks_.values) {
    const double x = std::round(xToPixel(v) - 0.5 * lw);
    if (x >= area_.left() && x + lw <= area_.right()) {
      canvas.fillRect({x, area_.top(), lw, area_.h}, st.gridColor);
    }
  }
  for (double v : yTicks_.values) {
    const double y = std::round(yToPixel(v) - 0.5 * lw);
    if (y >= area_.top() && y + lw <= area_.bottom()) {
      canvas.fillRect({area_.left(), y, area_.w, lw}, st.gridColor);
    }
  }
}

void Axes::drawFrame(Canvas& canvas) const {
  const FigureStyle& st = spec_.style;
  const Sizes z = sizesFor(st);
  const double lw = lineWidth_;
  const Rect& a = area_;
  // Spines: whole-pixel bars just outside the area, so they are crisp at any scale.
  canvas.fillRect(Rect::fromEdges(a.left() - lw, a.top() - lw, a.right() + lw, a.top()), st.ink);
  canvas.fillRect(Rect::fromEdges(a.left() - lw, a.bottom(), a.right() + lw, a.bottom() + lw),
                  st.ink);
  canvas.fillRect(Rect::fromEdges(a.left() - lw, a.top(), a.left(), a.bottom()), st.ink);
  canvas.fillRect(Rect::fromEdges(a.right(), a.top(), a.right() + lw, a.bottom()), st.ink);

  TextStyle tickText;
  tickText.size = z.tickFont;
  tickText.color = st.ink;
  const double tickLength = std::round(z.tickLength);

  // Minor ticks (logarithmic axes), outward like the others and shorter, without labels.
  const double minorLength = std::round(0.55 * z.tickLength);
  for (double v : xTicks_.minor) {
    const double x = std::round(xToPixel(v) - 0.5 * lw);
    canvas.fillRect({x, a.bottom() + lw, lw, minorLength}, st.ink);
  }
  for (double v : yTicks_.minor) {
    const double y = std::round(yToPixel(v) - 0.5 * lw);
    canvas.fillRect({a.left() - lw - minorLength, y, minorLength, lw}, st.ink);
  }

  // x ticks, outward below the frame, labels centred under them.
  tickText.hAlign = HAlign::Center;
  tickText.vAlign = VAlign::Top;
  const double xLabelTop = a.bottom() + lw + tickLength + z.tickPad;
  for (std::size_t i = 0; i < xTicks_.values.size(); ++i) {
    const double x = std::round(xToPixel(xTicks_.values[i]) - 0.5 * lw);
    canvas.fillRect({x, a.bottom() + lw, lw, tickLength}, st.ink);
    canvas.text({x + 0.5 * lw, xLabelTop}, xTicks_.labels[i], tickText);
  }
  // y ticks, outward left of the frame, labels right-aligned and centred on them.
  tickText.hAlign = HAlign::Right;
  tickText.vAlign = VAlign::Middle;
  const double yLabelRight = a.left() - lw - tickLength - z.tickPad;
  double widest = 0.0;
  for (std::size_t i = 0; i < yTicks_.values.size(); ++i) {
    const double y = std::round(yToPixel(yTicks_.values[i]) - 0.5 * lw);
    canvas.fillRect({a.left() - lw - tickLength, y, tickLength, lw}, st.ink);
    const Rect box = canvas.text({yLabelRight, y + 0.5 * lw}, yTicks_.labels[i], tickText);
    widest = std::max(widest, box.w);
  }

  // Multipliers: y above the top-left corner, x right-aligned below the tick labels.
  TextStyle multiplier = tickText;
  const double labelRowTop = xLabelTop + rowHeight(z.tick) + z.labelPad;
  double xMultiplierLeft = a.right() + lw;
  if (yTicks_.exponent != 0) {
    multiplier.hAlign = HAlign::Left;
    multiplier.vAlign = VAlign::Bottom;
    const double y = multiplierRow_ ? a.top() - lw - 0.25 * z.tickFont : a.top() - lw - z.titlePad;
    canvas.text({a.left() - lw, y}, yTicks_.multiplier(), multiplier);
  }
  if (xTicks_.exponent != 0) {
    multiplier.hAlign = HAlign::Right;
    multiplier.vAlign = VAlign::Top;
    const Rect box = canvas.text({a.right() + lw, labelRowTop}, xTicks_.multiplier(), multiplier);
    xMultiplierLeft = box.left();
  }

  TextStyle label;
  label.size = z.labelFont;
  label.color = st.ink;
  if (!spec_.xLabel.empty()) {
    label.hAlign = HAlign::Center;
    label.vAlign = VAlign::Top;
    // Centred under the area, moved left if it would run into the multiplier.
    const double w = canvas.measureText(spec_.xLabel, label).width;
    const double cx = std::min(a.center().x, xMultiplierLeft - 0.5 * z.labelFont - 0.5 * w);
    canvas.text({cx, labelRowTop}, spec_.xLabel, label);
  }
  if (!spec_.yLabel.empty()) {
    label.hAlign = HAlign::Center;
    label.vAlign = VAlign::Bottom;
    label.angle = 90.0;
    canvas.text({yLabelRight - widest - z.labelPad, a.center().y}, spec_.yLabel, label);
  }
  if (!spec_.title.empty()) {
    TextStyle title;
    title.size = z.titleFont;
    title.color = st.ink;
    title.hAlign = HAlign::Center;
    title.vAlign = VAlign::Bottom;
    const double above = multiplierRow_ ? rowHeight(z.tick) : 0.0;
    canvas.text({a.center().x, a.top() - lw - above - z.titlePad}, spec_.title, title);
  }
}

}  // namespace granular::render
