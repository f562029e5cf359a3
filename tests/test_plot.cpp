/// Ticks and line plots (render/ticks.hpp, render/plot.hpp): nice tick values and noise-free
/// labels, and the anatomy of a plot: data inside the axes, tick labels beside them, a legend
/// with samples in the series' colours over empty space, nothing at the image border.
///
/// Sections: ticks · plot anatomy · line weights · legend · panels.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <random>

#include "granular/render/inspect.hpp"
#include "granular/render/plot.hpp"
#include "granular/render/ticks.hpp"

namespace granular::render {
namespace {

constexpr Rgba kWhite{255, 255, 255, 255};
constexpr Rgba kLegendEdge{204, 204, 204, 255};  // the legend frame's grey (plot_legend.cpp)

PixelRegion region(const Rect& r) {
  return {int(std::floor(r.left())), int(std::floor(r.top())), int(std::ceil(r.right())),
          int(std::ceil(r.bottom()))};
}

// ---------------------------------------------------------------------------------------------
// Ticks

/// m · 10^k with m ∈ {1, 2, 5}.
bool isOneTwoFive(double step) {
  const double k = std::floor(std::log10(step) + 1e-9);
  const double m = step / std::pow(10.0, k);
  return std::abs(m - 1.0) < 1e-9 || std::abs(m - 2.0) < 1e-9 || std::abs(m - 5.0) < 1e-9;
}

TEST(Ticks, UnitRangeGetsFifthsWithOneDecimal) {
  // On [0, 1.087]: step 0.1 would give 11 ticks (> 8), 0.5 only 3 (< 4); 0.2 gives 6.
  const Ticks t = niceTicks(0.0, 1.087);
  EXPECT_DOUBLE_EQ(t.step, 0.2);
  ASSERT_EQ(t.values.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(t.values[i], 0.2 * double(i), 1e-15);
  EXPECT_EQ(t.labels.front(), "0.0");
  EXPECT_EQ(t.labels[3], "0.6");  // 3 · 0.2 is 0.6000000000000001 in binary
  EXPECT_EQ(t.labels.back(), "1.0");
  EXPECT_EQ(t.exponent, 0);
}

TEST(Ticks, NegativeRangeUsesTwentiesAndTheMinusSign) {
  // On [−1663, −1550]: step 10 gives 12 ticks, 50 gives 3 (−1650, −1600, −1550); 20 gives 6.
  const Ticks t = niceTicks(-1663.0, -1550.0);
  EXPECT_DOUBLE_EQ(t.step, 20.0);
  ASSERT_EQ(t.values.size(), 6u);
  EXPECT_DOUBLE_EQ(t.values.front(), -1660.0);
  EXPECT_DOUBLE_EQ(t.values.back(), -1560.0);
  EXPECT_EQ(t.labels.front(), "\u22121660");
}

TEST(Ticks, AreOneTwoFiveMultiplesInsideTheRange) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, std::floor(12.0 * unit(rng)) - 6.0);
    const double lo = (unit(rng) - 0.5) * 20.0 * scale;
    const double hi = lo + (0.05 + 10.0 * unit(rng)) * scale;
    const Ticks t = niceTicks(lo, hi);
    ASSERT_TRUE(isOneTwoFive(t.step)) << lo << " " << hi << " step " << t.step;
    // 4 to 8 ticks whenever some 1-2-5 step gives that many. Consecutive steps differ by up to
    // 2.5×, so a range can fall between (9 ticks for one step, 3 for the next): then 3 or 9.
    bool possible = false;
    for (int k = -8; k <= 8; ++k) {
      for (double m : {1.0, 2.0, 5.0}) {
        const double s = m * std::pow(10.0, k);
        const double n = std::floor(hi / s + 1e-9) - std::ceil(lo / s - 1e-9) + 1.0;
        possible = possible || (n >= 4.0 && n <= 8.0);
      }
    }
    const std::size_t n = t.values.size();
    if (possible) {
      EXPECT_TRUE(n >= 4 && n <= 8) << lo << " " << hi << ": " << n;
    } else {
      EXPECT_TRUE(n == 3 || n == 9) << lo << " " << hi << ": " << n;
    }
    ASSERT_EQ(t.labels.size(), t.values.size());
    for (double v : t.values) {
      EXPECT_GE(v, lo - 1e-9 * (hi - lo));
      EXPECT_LE(v, hi + 1e-9 * (hi - lo));
      EXPECT_NEAR(v / t.step, std::round(v / t.step), 1e-6) << v << " step " << t.step;
    }
  }
}

TEST(Ticks, LabelsCarryNoFloatingPointNoise) {
  EXPECT_EQ(formatTick(0.1 + 0.2, 0.1), "0.3");
  EXPECT_EQ(formatTick(-0.2, 0.1), "\u22120.2");
  EXPECT_EQ(formatTick(-1e-17, 0.1), "0.0");  // no negative zero
  EXPECT_EQ(formatTick(1500.0, 500.0), "1500");
  EXPECT_EQ(formatTick(0.75, 0.25), "0.75");
  EXPECT_EQ(formatTick(2.0, 1.0), "2");
}

TEST(Ticks, TinyValuesFactorOutAPowerOfTen) {
  // On [0, 2.5e−5] the step is 5e−6 (2e−6 gives 13 ticks, 1e−5 only 3); the largest tick,
  // 2.5e−5, lies in [1e−6, 1e−3), so the labels count millionths.
  const Ticks t = niceTicks(0.0, 2.5e-5);
  EXPECT_EQ(t.exponent, -6);
  EXPECT_EQ(t.multiplier(), "\u00d710\u207b\u2076");
  ASSERT_EQ(t.labels.size(), 6u);
  EXPECT_EQ(t.labels[0], "0");
  EXPECT_EQ(t.labels[1], "5");
  EXPECT_EQ(t.labels[5], "25");
}

// ---------------------------------------------------------------------------------------------
// Plot anatomy

PlotSpec crossingLines() {
  PlotSpec p;
  p.title = "Anatomy";
  p.xLabel = "Time t [s]";
  p.yLabel = "Stress σ [kPa]";
  p.width = 800;
  p.height = 500;
  Series rising, falling;
  rising.color = {200, 30, 30, 255};
  rising.width = 1.2;
  rising.label = "Eq. (1)";
  falling.color = {30, 30, 200, 255};
  falling.width = 3.0;
  falling.label = "Eq. (2)";
  for (int i = 0; i <= 200; ++i) {
    const double x = i / 200.0;
    rising.x.push_back(x);
    rising.y.push_back(x);
    falling.x.push_back(x);
    falling.y.push_back(1.0 - x);
  }
  p.series = {rising, falling};
  p.references.push_back({0.25, "limit", {80, 80, 80, 255}, 1.2, true});
  return p;
}

/// Longest horizontal run of pixels within `tol` of `color`.
int longestRun(const Image& img, Rgba color, int tol) {
  int best = 0;
  for (int y = 0; y < img.height; ++y) {
    int run = 0;
    for (int x = 0; x < img.width; ++x) {
      const Rgba c = img.at(x, y);
      const bool match = std::abs(c.r - color.r) <= tol && std::abs(c.g - color.g) <= tol &&
                         std::abs(c.b - color.b) <= tol;
      run = match ? run + 1 : 0;
      best = std::max(best, run);
    }
  }
  return best;
}

TEST(Plot, AxesHoldTheDataWithLabelsBesideThem) {
  const PlotSpec spec = crossingLines();
  Canvas canvas(spec.width, spec.height);
  const Axes axes = drawPlot(canvas, {0.0, 0.0, double(spec.width), double(spec.height)}, spec);
  const Image& img = canvas.image();
  const Rect& area = axes.area();
  ASSERT_GT(area.w, 0.5 * spec.width);
  ASSERT_GT(area.h, 0.5 * spec.height);

  // Data inside the axes, in both series' colours.
  EXPECT_GT(countColorPixels(img, spec.series[0].color, 30, region(area)), 100);
  EXPECT_GT(countColorPixels(img, spec.series[1].color, 30, region(area)), 300);
  // The data range is padded: the series' ends (x = 0 and 1) lie inside the frame.
  EXPECT_GT(axes.xToPixel(0.0), area.left() + 5.0);
  EXPECT_LT(axes.xToPixel(1.0), area.right() - 5.0);

  // Dark tick-label and axis-label ink left of the ticks and below them.
  const double tick = spec.style.px(spec.style.tickLength) + 2.0;
  const Rect left = Rect::fromEdges(0.0, area.top(), area.left() - tick, area.bottom());
  const Rect below = Rect::fromEdges(area.left(), area.bottom() + tick, area.right(), spec.height);
  EXPECT_GT(countColorPixels(img, {0, 0, 0, 255}, 60, region(left)), 100);
  EXPECT_GT(countColorPixels(img, {0, 0, 0, 255}, 60, region(below)), 100);
  // Tick values are laid out in order along the axes.
  ASSERT_GE(axes.xTicks().values.size(), 4u);
  ASSERT_GE(axes.yTicks().values.size(), 4u);

  // The legend's line samples: horizontal runs of each series' colour at least 80 % of the
  // two-em sample; the data lines are diagonal and make short runs only.
  const int sample = int(0.8 * 2.0 * spec.style.px(spec.style.fontSize));
  EXPECT_GE(longestRun(img, spec.series[0].color, 40), sample);
  EXPECT_GE(longestRun(img, spec.series[1].color, 20), sample);

  // Nothing touches the border: the style's 8 px margin, less a pixel of anti-aliasing.
  const InkBox ink = inkBounds(img, kWhite, 10);
  EXPECT_GE(ink.x0, 6);
  EXPECT_GE(ink.y0, 6);
  EXPECT_LE(ink.x1, spec.width - 7);
  EXPECT_LE(ink.y1, spec.height - 7);
}

TEST(Plot, LargeValuesFactorOutAPowerOfTen) {
  PlotSpec spec;
  Series s;
  s.x = {0.0, 1.0, 2.0};
  s.y = {0.0, 2.0e6, 3.0e6};
  spec.series = {s};
  Canvas canvas(600, 400);
  const Axes axes = drawPlot(canvas, {0.0, 0.0, 600.0, 400.0}, spec);
  EXPECT_EQ(axes.yTicks().exponent, 6);
  // The multiplier sits above the frame's top-left corner.
  const Rect& a = axes.area();
  const Rect above = Rect::fromEdges(a.left() - 2.0, 0.0, a.left() + 60.0, a.top() - 2.0);
  EXPECT_GT(countColorPixels(canvas.image(), {0, 0, 0, 255}, 60, region(above)), 10);
}

// ---------------------------------------------------------------------------------------------
// Line weights

TEST(Plot, ThinAndBoldLinesDifferByTheirWidths) {
  PlotSpec spec;
  spec.legend = LegendPosition::None;
  spec.yRange = AxisRange{0.0, 3.0};
  Series thin, bold;
  thin.color = bold.color = {0, 0, 0, 255};
  thin.width = 1.2;
  bold.width = 3.0;
  thin.x = bold.x = {0.0, 1.0};
  thin.y = {1.0, 1.0};
  bold.y = {2.0, 2.0};
  spec.series = {thin, bold};
  Canvas canvas(spec.width, spec.height);
  const Axes axes = drawPlot(canvas, {0.0, 0.0, double(spec.width), double(spec.height)}, spec);
  const int column = int(axes.area().center().x);
  auto inkAround = [&](double y) {
    double sum = 0.0;
    for (int row = int(y) - 6; row <= int(y) + 6; ++row) {
      sum += (255.0 - canvas.image().at(column, row).r) / 255.0;
    }
    return sum;
  };
  // At scale 1 the widths are in pixels; each column carries the width's worth of ink.
  EXPECT_NEAR(inkAround(axes.yToPixel(1.0)), 1.2, 0.05);
  EXPECT_NEAR(inkAround(axes.yToPixel(2.0)), 3.0, 0.05);
}

// ---------------------------------------------------------------------------------------------
// Legend

TEST(Plot, LegendGoesWhereThereIsNoData) {
  PlotSpec spec;
  spec.yRange = AxisRange{0.0, 1.2};
  Series top;
  top.label = "plateau";
  top.x = {0.0, 1.0};
  top.y = {1.15, 1.15};
  spec.series = {top};
  Canvas canvas(spec.width, spec.height);
  const Axes axes = drawPlot(canvas, {0.0, 0.0, double(spec.width), double(spec.height)}, spec);
  const Rect& a = axes.area();
  const Rect upper = Rect::fromEdges(a.left(), a.top(), a.right(), a.center().y);
  const Rect lower = Rect::fromEdges(a.left(), a.center().y, a.right(), a.bottom());
  // The line runs just under the top, through both upper corners' legend spots, so the legend
  // box (grey frame) goes to the lower half.
  EXPECT_EQ(countColorPixels(canvas.image(), kLegendEdge, 3, region(upper)), 0);
  EXPECT_GT(countColorPixels(canvas.image(), kLegendEdge, 3, region(lower)), 50);
}

TEST(Plot, LegendMovesOutsideWhenDataFillTheAxes) {
  PlotSpec spec;
  Series noise;
  noise.label = "scatter";
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 2000; ++i) {
    noise.x.push_back(i / 2000.0);
    noise.y.push_back(unit(rng));
  }
  spec.series = {noise};
  Canvas canvas(spec.width, spec.height);
  const Axes axes = drawPlot(canvas, {0.0, 0.0, double(spec.width), double(spec.height)}, spec);
  const Rect& a = axes.area();
  EXPECT_EQ(countColorPixels(canvas.image(), kLegendEdge, 3, region(a)), 0);
  const Rect right = Rect::fromEdges(a.right() + 2.0, 0.0, spec.width, spec.height);
  EXPECT_GT(countColorPixels(canvas.image(), kLegendEdge, 3, region(right)), 50);
}

// ---------------------------------------------------------------------------------------------
// Panels

TEST(Plot, PanelsShareAnImageWithoutOverlap) {
  const PlotSpec spec = crossingLines();
  Canvas canvas(1000, 420);
  drawPlot(canvas, {0.0, 0.0, 500.0, 420.0}, spec);
  drawPlot(canvas, {500.0, 0.0, 500.0, 420.0}, spec);
  const InkBox left = inkBounds(canvas.image(), kWhite, 10, {0, 0, 500, 420});
  const InkBox right = inkBounds(canvas.image(), kWhite, 10, {500, 0, 1000, 420});
  EXPECT_LE(left.x1, 500 - 7);
  EXPECT_GE(right.x0, 500 + 6);
  EXPECT_GT(left.inkPixels, 1000);
  EXPECT_GT(right.inkPixels, 1000);
}

TEST(Plot, LargeFigureDrawsQuickly) {
  PlotSpec spec = crossingLines();
  spec.width = 1600;
  spec.height = 1000;
  spec.style = FigureStyle::forDpi(200);
  for (Series& s : spec.series) {
    s.x.clear();
    s.y.clear();
    for (int i = 0; i < 3000; ++i) {
      s.x.push_back(i / 3000.0);
      s.y.push_back(0.5 + 0.4 * std::sin(40.0 * i / 3000.0 + s.width));
    }
  }
  spec.series.push_back(spec.series[0]);
  spec.series.push_back(spec.series[1]);
  const auto start = std::chrono::steady_clock::now();
  const Image img = drawPlot(spec);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("draw_ms", int(1000.0 * seconds));
  EXPECT_FALSE(inkBounds(img, kWhite, 10).empty());
  // About 30 ms in a release build; the bound leaves room for sanitizers and loaded machines.
  EXPECT_LT(seconds, 2.0);
}

}  // namespace
}  // namespace granular::render
