/// Logarithmic axes (render/ticks.hpp logTicks, AxesSpec::xLog/yLog, PlotSpec::xLog/yLog): ticks
/// at the powers of ten labelled "10⁻⁴", minor ticks between them, decades equally long on the
/// axis, and plots that leave out what has no logarithm.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "granular/render/axes.hpp"
#include "granular/render/plot.hpp"
#include "granular/render/ticks.hpp"

namespace granular::render {
namespace {

/// "10" and the exponent in superscript digits, with U+207B for minus, as the labels write it.
std::string superscriptPower(int exponent) {
  static const char* const kDigits[10] = {"\u2070", "\u00b9", "\u00b2", "\u00b3", "\u2074",
                                          "\u2075", "\u2076", "\u2077", "\u2078", "\u2079"};
  std::string s = "10";
  if (exponent < 0) s += "\u207b";
  for (char c : std::to_string(std::abs(exponent))) s += kDigits[c - '0'];
  return s;
}

TEST(LogTicks, DecadesFromTenToTheMinusFiveToTheMinusTwoAreLabelledAsPowersOfTen) {
  const Ticks t = logTicks(1e-5, 1e-2);
  ASSERT_EQ(t.values.size(), 4u);
  ASSERT_EQ(t.labels.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    const int exponent = -5 + i;
    EXPECT_DOUBLE_EQ(t.values[i], std::pow(10.0, exponent));
    EXPECT_EQ(t.labels[i], superscriptPower(exponent));
  }
  EXPECT_EQ(t.labels[1], "10\u207b\u2074");  // 10⁻⁴, spelled out once
  EXPECT_EQ(t.exponent, 0);                  // no "×10ⁿ" factored out of the labels
  // The minor ticks: 2–9 × 10^k of the three decades between, each inside its decade.
  EXPECT_EQ(t.minor.size(), 3u * 8u);
  for (double v : t.minor) {
    const double mantissa = v / std::pow(10.0, std::floor(std::log10(v) + 1e-9));
    EXPECT_GT(mantissa, 1.5) << v;
    EXPECT_LT(mantissa, 9.5) << v;
    EXPECT_GT(v, 1e-5);
    EXPECT_LT(v, 1e-2);
  }
}

TEST(LogTicks, PowersOfTenAboveOneHaveSuperscriptExponentsToo) {
  const Ticks t = logTicks(0.5, 2000.0);
  ASSERT_EQ(t.labels.size(), 4u);
  EXPECT_EQ(t.labels.front(), "10\u2070");  // 10⁰
  EXPECT_EQ(t.labels.back(), "10\u00b3");   // 10³
}

TEST(LogTicks, AShortRangeIsLabelledAtOneTwoAndFiveTimesAPower) {
  // [1.5·10⁻⁴, 8·10⁻⁴] holds no power of ten: 2 and 5 × 10⁻⁴ are labelled, 3, 4, 6, 7, 8 not.
  const Ticks t = logTicks(1.5e-4, 8e-4);
  ASSERT_EQ(t.values.size(), 2u);
  EXPECT_DOUBLE_EQ(t.values[0], 2e-4);
  EXPECT_DOUBLE_EQ(t.values[1], 5e-4);
  EXPECT_EQ(t.labels[0], "2\u00d710\u207b\u2074");
  EXPECT_EQ(t.labels[1], "5\u00d710\u207b\u2074");
  EXPECT_EQ(t.minor.size(), 5u);
}

TEST(LogTicks, EveryOtherDecadeLabelsTheEvenPowersAndKeepsTheRestAsMinorTicks) {
  const Ticks t = logTicks(1e-8, 1e2, 2);
  ASSERT_EQ(t.values.size(), 6u);
  for (std::size_t i = 0; i < t.values.size(); ++i) {
    EXPECT_DOUBLE_EQ(t.values[i], std::pow(10.0, -8 + 2 * int(i)));
  }
  EXPECT_DOUBLE_EQ(t.step, 2.0);
  bool oddPowerIsMinor = false;
  for (double v : t.minor) oddPowerIsMinor = oddPowerIsMinor || v == 1e-7;
  EXPECT_TRUE(oddPowerIsMinor);
}

TEST(LogTicks, NothingWithoutALogarithm) {
  EXPECT_TRUE(logTicks(0.0, 1.0).values.empty());
  EXPECT_TRUE(logTicks(-1.0, 1.0).values.empty());
  EXPECT_TRUE(logTicks(1.0, INFINITY).values.empty());
}

TEST(LogAxes, ALongRangeOnAShortAxisLabelsFewerDecades) {
  // Twelve decades on 150 px at 12 px text cannot all be labelled without touching.
  const Ticks t = ticksForAxis(1e-12, 1.0, 150.0, false, 12.0, true);
  EXPECT_GE(t.step, 2.0);
  EXPECT_GE(t.values.size(), 2u);
  for (std::size_t i = 1; i < t.values.size(); ++i) {
    EXPECT_NEAR(std::log10(t.values[i] / t.values[i - 1]), t.step, 1e-9);
  }
}

TEST(LogAxes, DecadesAreEquallyLongAndPixelsMapBack) {
  AxesSpec spec;
  spec.xMin = 1e-5, spec.xMax = 1e-1;
  spec.yMin = 1e-4, spec.yMax = 1e2;
  spec.xLog = spec.yLog = true;
  const Axes axes({0.0, 0.0, 800.0, 600.0}, spec);
  const double xDecade = axes.xToPixel(1e-4) - axes.xToPixel(1e-5);
  const double yDecade = axes.yToPixel(1e-3) - axes.yToPixel(1e-4);
  EXPECT_GT(xDecade, 0.0);
  EXPECT_LT(yDecade, 0.0);  // upwards
  for (int k = -5; k < -1; ++k) {
    EXPECT_NEAR(axes.xToPixel(std::pow(10.0, k + 1)) - axes.xToPixel(std::pow(10.0, k)), xDecade,
                1e-9 * std::abs(xDecade));
  }
  // 10^−2.5 lies halfway between 10⁻³ and 10⁻², not near 10⁻².
  EXPECT_NEAR(axes.xToPixel(std::pow(10.0, -2.5)),
              0.5 * (axes.xToPixel(1e-3) + axes.xToPixel(1e-2)), 1e-9);
  const Point back = axes.toData(axes.toPixel(3e-4, 7.0));
  EXPECT_NEAR(back.x, 3e-4, 1e-12);
  EXPECT_NEAR(back.y, 7.0, 1e-9);
  EXPECT_TRUE(std::isnan(axes.xToPixel(0.0)));
  // The ticks are the decades, labelled as powers.
  ASSERT_FALSE(axes.xTicks().values.empty());
  EXPECT_EQ(axes.xTicks().labels.front(), superscriptPower(-5));
}

TEST(LogAxes, APlotLeavesOutValuesWithoutALogarithm) {
  PlotSpec spec;
  spec.xLog = spec.yLog = true;
  Series s;
  s.x = {1e-6, 1e-5, 1e-4, 1e-3};
  s.y = {0.0, 1e-5, 1e-3, 1e-2};  // the first point has no logarithm
  spec.series = {s};
  spec.references.push_back({1e-3, "0.1 %", {80, 80, 80, 255}, 1.2, true});
  Canvas canvas(800, 500);
  const Axes axes = drawPlot(canvas, {0.0, 0.0, 800.0, 500.0}, spec);
  // The range holds the three points that have one, padded by 5 % of their decades.
  EXPECT_GT(axes.spec().yMin, 0.0);
  EXPECT_LT(axes.spec().yMin, 1e-5);
  EXPECT_GT(axes.spec().xMin, 1e-6);  // the x of the left-out point does not count
  EXPECT_LT(axes.spec().xMin, 1e-5);
  EXPECT_GT(axes.spec().yMax, 1e-2);
  EXPECT_EQ(axes.yTicks().labels.front(), superscriptPower(-5));
}

}  // namespace
}  // namespace granular::render
