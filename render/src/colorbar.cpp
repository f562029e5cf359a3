/// Colour bars (colorbar.hpp).
///
/// Sections: ticks and sizes · drawing.
#include "granular/render/colorbar.hpp"

#include <algorithm>
#include <cmath>

#include "granular/render/axes.hpp"

namespace granular::render {

// ---------------------------------------------------------------------------------------------
// Ticks and sizes

namespace {

struct BarSizes {
  double font = 0, labelFont = 0, lw = 1, tickLength = 0, tickPad = 0, labelPad = 0;
  double thickness = 0;
  TextMetrics tick, label;
};

BarSizes sizesFor(const ColorBarSpec& spec) {
  const FigureStyle& st = spec.style;
  BarSizes z;
  z.font = st.px(st.fontSize);
  z.labelFont = st.px(st.labelFontSize);
  z.lw = std::max(1.0, std::round(st.px(st.axisWidth)));
  z.tickLength = std::round(st.px(st.tickLength));
  z.tickPad = 0.35 * z.font;
  z.labelPad = 0.4 * z.labelFont;
  z.thickness = std::round(st.px(spec.thickness));
  z.tick = Font::get(FontWeight::Regular, z.font)->measure("");
  z.label = Font::get(FontWeight::Regular, z.labelFont)->measure("");
  return z;
}

bool discrete(const ColorBarSpec& spec) {
  return spec.levels.size() >= 2;
}

double lowEnd(const ColorScale& s, const ColorBarSpec& spec) {
  return discrete(spec) ? spec.levels.front() : s.min;
}
double highEnd(const ColorScale& s, const ColorBarSpec& spec) {
  return discrete(spec) ? spec.levels.back() : s.max;
}

/// Continuous bars: axis ticks. Discrete bars: the levels, every k-th labelled so the labels
/// keep apart.
Ticks barTicks(const ColorScale& scale, const ColorBarSpec& spec, double length) {
  const BarSizes z = sizesFor(spec);
  const bool horizontal = spec.orientation == Orientation::Horizontal;
  const double lo = lowEnd(scale, spec), hi = highEnd(scale, spec);
  if (!discrete(spec)) return ticksForAxis(lo, hi, length, horizontal, z.font);
  double step = INFINITY;
  for (std::size_t i = 0; i + 1 < spec.levels.size(); ++i) {
    step = std::min(step, std::abs(spec.levels[i + 1] - spec.levels[i]));
  }
  // The labels' format (and power of ten) comes from nice ticks over the same range.
  const Ticks format = niceTicks(lo, hi);
  const double unit = std::pow(10.0, -format.exponent);
  const Font& font = *Font::get(FontWeight::Regular, z.font);
  for (std::size_t every = 1; every <= spec.levels.size(); ++every) {
    Ticks t;
    t.exponent = format.exponent;
    t.step = step * double(every);
    for (std::size_t i = 0; i < spec.levels.size(); i += every) {
      t.values.push_back(spec.levels[i]);
      t.labels.push_back(formatTick(spec.levels[i] * unit, step * unit));
    }
    bool fits = true;
    for (std::size_t i = 0; i + 1 < t.values.size() && fits; ++i) {
      const double distance = std::abs(t.values[i + 1] - t.values[i]) / std::abs(hi - lo) * length;
      const double needed =
          horizontal
              ? 0.5 * (font.measure(t.labels[i]).width + font.measure(t.labels[i + 1]).width) +
                    z.font
              : z.tick.capHeight + 0.8 * z.font;
      fits = distance >= needed;
    }
    if (fits) return t;
  }
  return {};
}

double widestLabel(const Ticks& t, double font) {
  double w = 0.0;
  for (const auto& s : t.labels)
    w = std::max(w, Font::get(FontWeight::Regular, font)->measure(s).width);
  return w;
}

}  // namespace

double colorBarExtent(const ColorScale& scale, const ColorBarSpec& spec, double length) {
  const BarSizes z = sizesFor(spec);
  const Ticks t = barTicks(scale, spec, length);
  const double title = spec.title.empty() ? 0.0 : z.labelPad + z.label.ascent + z.label.descent;
  const double labels = spec.orientation == Orientation::Vertical ? widestLabel(t, z.font)
                                                                  : z.tick.ascent + z.tick.descent;
  return z.thickness + z.lw + z.tickLength + z.tickPad + labels + title;
}

double colorBarOverhang(const ColorScale& scale, const ColorBarSpec& spec, double length) {
  const BarSizes z = sizesFor(spec);
  if (spec.orientation == Orientation::Vertical) return 0.5 * z.tick.capHeight + z.lw;
  const Ticks t = barTicks(scale, spec, length);
  return 0.5 * widestLabel(t, z.font) + z.lw;
}

// ---------------------------------------------------------------------------------------------
// Drawing

void drawColorBarAt(Canvas& canvas, Rect bar, const ColorScale& scale, const ColorBarSpec& spec) {
  const BarSizes z = sizesFor(spec);
  const FigureStyle& st = spec.style;
  const bool vertical = spec.orientation == Orientation::Vertical;
  bar = Rect::fromEdges(std::round(bar.left()), std::round(bar.top()), std::round(bar.right()),
                        std::round(bar.bottom()));
  if (bar.empty()) return;
  const double length = vertical ? bar.h : bar.w;
  const double lo = lowEnd(scale, spec), hi = highEnd(scale, spec);
  // Position along the bar [px] of a value: low end at the bottom (left), high at the top (right).
  auto along = [&](double v) {
    const double f = (hi != lo) ? (v - lo) / (hi - lo) : 0.5;
    return vertical ? bar.bottom() - f * bar.h : bar.left() + f * bar.w;
  };

  if (discrete(spec)) {
    const int bands = int(spec.levels.size()) - 1;
    for (int k = 0; k < bands; ++k) {
      const double a = along(spec.levels[std::size_t(k)]),
                   b = along(spec.levels[std::size_t(k) + 1]);
      const Rgba c = bandColor(scale.map, k, bands);
      canvas.fillRect(
          vertical ? Rect::fromEdges(bar.left(), std::min(a, b), bar.right(), std::max(a, b))
                   : Rect::fromEdges(std::min(a, b), bar.top(), std::max(a, b), bar.bottom()),
          c);
    }
  } else {
    // One colour per pixel row (column), sampled at its centre.
    const int n = int(length);
    for (int i = 0; i < n; ++i) {
      const double f = (i + 0.5) / n;
      const Rgba c = scale.map(vertical ? 1.0 - f : f);
      canvas.fillRect(vertical ? Rect{bar.left(), bar.top() + i, bar.w, 1.0}
                               : Rect{bar.left() + i, bar.top(), 1.0, bar.h},
                      c);
    }
  }
  // Frame just outside the bar, like the axes' spines.
  const double lw = z.lw;
  canvas.fillRect(Rect::fromEdges(bar.left() - lw, bar.top() - lw, bar.right() + lw, bar.top()),
                  st.ink);
  canvas.fillRect(
      Rect::fromEdges(bar.left() - lw, bar.bottom(), bar.right() + lw, bar.bottom() + lw), st.ink);
  canvas.fillRect(Rect::fromEdges(bar.left() - lw, bar.top(), bar.left(), bar.bottom()), st.ink);
  canvas.fillRect(Rect::fromEdges(bar.right(), bar.top(), bar.right() + lw, bar.bottom()), st.ink);

  const Ticks t = barTicks(scale, spec, length);
  TextStyle text;
  text.size = z.font;
  text.color = st.ink;
  double labelsEnd = 0.0;  // right (vertical) or bottom (horizontal) edge of the labels [px]
  if (vertical) {
    text.hAlign = HAlign::Left;
    text.vAlign = VAlign::Middle;
    const double x = bar.right() + lw;
    labelsEnd = x + z.tickLength + z.tickPad;
    for (std::size_t i = 0; i < t.values.size(); ++i) {
      // The tick's centre follows the value; its row snaps to whole pixels.
      const double y =
          std::clamp(std::round(along(t.values[i]) - 0.5 * lw), bar.top() - lw, bar.bottom());
      canvas.fillRect({x, y, z.tickLength, lw}, st.ink);
      const Rect box = canvas.text({x + z.tickLength + z.tickPad, y + 0.5 * lw}, t.labels[i], text);
      labelsEnd = std::max(labelsEnd, box.right());
    }
    if (t.exponent != 0) {
      text.vAlign = VAlign::Bottom;
      canvas.text({bar.left() - lw, bar.top() - lw - 0.25 * z.font}, t.multiplier(), text);
    }
    if (!spec.title.empty()) {
      TextStyle title;
      title.size = z.labelFont;
      title.color = st.ink;
      title.angle = 90.0;
      title.hAlign = HAlign::Center;
      title.vAlign = VAlign::Top;
      canvas.text({labelsEnd + z.labelPad, bar.center().y}, spec.title, title);
    }
  } else {
    text.hAlign = HAlign::Center;
    text.vAlign = VAlign::Top;
    const double y = bar.bottom() + lw;
    for (std::size_t i = 0; i < t.values.size(); ++i) {
      const double x =
          std::clamp(std::round(along(t.values[i]) - 0.5 * lw), bar.left() - lw, bar.right());
      canvas.fillRect({x, y, lw, z.tickLength}, st.ink);
      canvas.text({x + 0.5 * lw, y + z.tickLength + z.tickPad}, t.labels[i], text);
    }
    labelsEnd = y + z.tickLength + z.tickPad + z.tick.ascent + z.tick.descent;
    if (t.exponent != 0) {
      text.hAlign = HAlign::Left;
      text.vAlign = VAlign::Middle;
      canvas.text({bar.right() + lw + 0.3 * z.font, bar.center().y}, t.multiplier(), text);
    }
    if (!spec.title.empty()) {
      TextStyle title;
      title.size = z.labelFont;
      title.color = st.ink;
      title.hAlign = HAlign::Center;
      title.vAlign = VAlign::Top;
      canvas.text({bar.center().x, labelsEnd + z.labelPad}, spec.title, title);
    }
  }
}

Rect drawColorBar(Canvas& canvas, Rect area, const ColorScale& scale, const ColorBarSpec& spec) {
  const BarSizes z = sizesFor(spec);
  Rect bar;
  if (spec.orientation == Orientation::Vertical) {
    const Ticks probe = barTicks(scale, spec, area.h);
    // Room above for the multiplier row when the labels carry a power of ten.
    const double top = probe.exponent != 0 ? z.tick.ascent + z.tick.descent + 0.25 * z.font
                                           : colorBarOverhang(scale, spec, area.h);
    const double bottom = colorBarOverhang(scale, spec, area.h);
    bar = Rect::fromEdges(area.left() + z.lw, area.top() + top, area.left() + z.lw + z.thickness,
                          area.bottom() - bottom);
  } else {
    const double side = colorBarOverhang(scale, spec, area.w);
    const Ticks probe = barTicks(scale, spec, area.w);
    double right = side;
    if (probe.exponent != 0) {
      right +=
          Font::get(FontWeight::Regular, z.font)->measure(probe.multiplier()).width + 0.3 * z.font;
    }
    bar = Rect::fromEdges(area.left() + side, area.top() + z.lw, area.right() - right,
                          area.top() + z.lw + z.thickness);
  }
  bar = Rect::fromEdges(std::round(bar.left()), std::round(bar.top()), std::round(bar.right()),
                        std::round(bar.bottom()));
  drawColorBarAt(canvas, bar, scale, spec);
  return bar;
}

}  // namespace granular::render
