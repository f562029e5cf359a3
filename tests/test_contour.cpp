/// Contour maps, colour bars and overlays (render/contour.hpp, render/colorbar.hpp): fields whose
/// level sets are known in closed form (f = x: vertical lines; f = r²: a disc) checked in pixels.
///
/// Sections: helpers · bands and isolines · labels · colour bars · overlays and edge cases.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "granular/render/colorbar.hpp"
#include "granular/render/contour.hpp"
#include "granular/render/inspect.hpp"

namespace granular::render {
namespace {

// ---------------------------------------------------------------------------------------------
// Helpers

constexpr Rgba kWhite{255, 255, 255, 255};
constexpr Rgba kRed{255, 0, 0, 255};

PixelRegion region(const Rect& r) {
  return {int(std::floor(r.left())), int(std::floor(r.top())), int(std::ceil(r.right())),
          int(std::ceil(r.bottom()))};
}

/// f(x, y) sampled on nx × ny nodes over [0, 1]².
template <class F>
std::vector<std::vector<double>> sample(int nx, int ny, F f) {
  std::vector<std::vector<double>> v(std::size_t(ny), std::vector<double>(std::size_t(nx), 0.0));
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i)
      v[std::size_t(j)][std::size_t(i)] = f(i / (nx - 1.0), j / (ny - 1.0));
  }
  return v;
}

ContourSpec linearField() {
  ContourSpec spec;
  spec.values = sample(41, 21, [](double x, double) { return x; });
  spec.map = grayscale;  // grey bands, so the red isolines stand out
  spec.isolineColor = kRed;
  spec.isolineWidth = 1.0;
  spec.labelIsolines = false;
  spec.equalAspect = false;
  spec.xLabel = "x [m]";
  spec.yLabel = "y [m]";
  spec.colorBarTitle = "f = x [m]";
  return spec;
}

bool isOneTwoFive(double step) {
  const double k = std::floor(std::log10(step) + 1e-9);
  const double m = step / std::pow(10.0, k);
  return std::abs(m - 1.0) < 1e-9 || std::abs(m - 2.0) < 1e-9 || std::abs(m - 5.0) < 1e-9;
}

// ---------------------------------------------------------------------------------------------
// Bands and isolines

TEST(Contour, AutomaticLevelsAreNiceAndCoverTheData) {
  const std::vector<double> levels = contourLevels(linearField());
  ASSERT_GE(levels.size(), 3u);
  EXPECT_LE(levels.front(), 0.0);
  EXPECT_GE(levels.back(), 1.0);
  const double step = levels[1] - levels[0];
  EXPECT_TRUE(isOneTwoFive(step)) << step;
  for (std::size_t i = 1; i < levels.size(); ++i)
    EXPECT_NEAR(levels[i] - levels[i - 1], step, 1e-12);
  // Whole steps just covering the data: no empty band at either end.
  EXPECT_GT(levels[1], 0.0);
  EXPECT_LT(levels[levels.size() - 2], 1.0);
}

TEST(Contour, LinearFieldGivesVerticalBandsOrderedByColour) {
  const ContourSpec spec = linearField();
  const std::vector<double> levels = contourLevels(spec);
  const int bands = int(levels.size()) - 1;
  Canvas canvas(spec.width, spec.height);
  const Axes axes = drawContour(canvas, {0.0, 0.0, double(spec.width), double(spec.height)}, spec);
  const Rect& a = axes.area();
  int previousGrey = -1;
  for (int k = 0; k < bands; ++k) {
    // Middle of the band's visible part; the same colour at every height.
    const double lo = std::max(levels[std::size_t(k)], 0.0),
                 hi = std::min(levels[std::size_t(k) + 1], 1.0);
    const int column = int(axes.xToPixel(0.5 * (lo + hi)));
    const Rgba expected = bandColor(grayscale, k, bands);
    for (double f : {0.2, 0.5, 0.8}) {
      const Rgba got = canvas.image().at(column, int(a.top() + f * a.h));
      EXPECT_NEAR(got.r, expected.r, 1) << "band " << k;
    }
    EXPECT_GT(int(expected.r), previousGrey);
    previousGrey = expected.r;
  }
}

TEST(Contour, IsolinesSitAtTheirLevels) {
  const ContourSpec spec = linearField();
  Canvas canvas(spec.width, spec.height);
  const Axes axes = drawContour(canvas, {0.0, 0.0, double(spec.width), double(spec.height)}, spec);
  const Rect& a = axes.area();
  int checked = 0;
  for (double level : contourLevels(spec)) {
    if (!(level > 0.0 && level < 1.0)) continue;  // isolines only inside the data range
    const double expected = axes.xToPixel(level);
    for (double f : {0.1, 0.5, 0.9}) {
      const int row = int(a.top() + f * a.h);
      // The reddest pixel near the expected column: red over grey has r − g > 0.
      int best = -1, bestRedness = 0;
      for (int x = int(expected) - 4; x <= int(expected) + 4; ++x) {
        const Rgba c = canvas.image().at(x, row);
        if (c.r - c.g > bestRedness) bestRedness = c.r - c.g, best = x;
      }
      ASSERT_GE(best, 0) << "no isoline near level " << level;
      EXPECT_LE(std::abs(best + 0.5 - expected), 1.0) << "level " << level;
      ++checked;
    }
  }
  EXPECT_GE(checked, 6);
}

TEST(Contour, DiscBandHasTheLevelSetsArea) {
  // f = (x − ½)² + (y − ½)² < 0.04 is a disc of radius 0.2; band 0 is black, band 1 white.
  ContourSpec spec;
  spec.values = sample(
      101, 101, [](double x, double y) { return (x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5); });
  spec.levels = {0.0, 0.04, 0.6};
  spec.map = grayscale;
  spec.isolines = false;
  Canvas canvas(spec.width, spec.height);
  const Axes axes = drawContour(canvas, {0.0, 0.0, double(spec.width), double(spec.height)}, spec);
  const double pxPerUnit = axes.xToPixel(1.0) - axes.xToPixel(0.0);
  EXPECT_NEAR(pxPerUnit, axes.yToPixel(0.0) - axes.yToPixel(1.0), 1e-9);  // equal aspect
  double ink = 0.0;
  const PixelRegion r = region(axes.area());
  for (int y = r.y0; y < r.y1; ++y) {
    for (int x = r.x0; x < r.x1; ++x) ink += (255.0 - canvas.image().at(x, y).r) / 255.0;
  }
  const double radius = 0.2 * pxPerUnit;
  EXPECT_NEAR(ink, std::numbers::pi * radius * radius, 0.01 * std::numbers::pi * radius * radius);
}

// ---------------------------------------------------------------------------------------------
// Labels

TEST(Contour, LabelsSitOnTheirIsolines) {
  ContourSpec plain = linearField();
  ContourSpec labelled = plain;
  labelled.labelIsolines = true;
  Canvas a(plain.width, plain.height), b(plain.width, plain.height);
  const Rect panel{0.0, 0.0, double(plain.width), double(plain.height)};
  const Axes axes = drawContour(a, panel, plain);
  drawContour(b, panel, labelled);
  const ImageDiff d = compareImages(b.image(), a.image(), 8);
  ASSERT_GT(d.differing, 0);
  // Every difference lies within a label's half height of an interior isoline, and every
  // interior isoline has one.
  const double reach = 0.85 * plain.style.px(plain.style.fontSize);
  std::vector<double> columns;
  for (double level : contourLevels(plain)) {
    if (level > 0.0 && level < 1.0) columns.push_back(axes.xToPixel(level));
  }
  std::vector<long> near(columns.size(), 0);
  long stray = 0;
  for (int y = 0; y < d.diff.height; ++y) {
    for (int x = 0; x < d.diff.width; ++x) {
      if (!(d.diff.at(x, y) == Rgba{255, 0, 0, 255})) continue;
      bool found = false;
      for (std::size_t i = 0; i < columns.size(); ++i) {
        if (std::abs(x + 0.5 - columns[i]) <= reach) ++near[i], found = true;
      }
      stray += found ? 0 : 1;
    }
  }
  EXPECT_EQ(stray, 0);
  for (std::size_t i = 0; i < columns.size(); ++i) EXPECT_GT(near[i], 20) << "isoline " << i;
}

// ---------------------------------------------------------------------------------------------
// Colour bars

TEST(ColorBar, ContinuousBarShowsTheMapsEndsAndLabels) {
  Canvas canvas(200, 400);
  ColorBarSpec spec;
  spec.title = "Σ|F_ij| [N]";
  const Rect area{20.0, 20.0, 160.0, 360.0};
  const Rect bar = drawColorBar(canvas, area, {0.0, 3.2, magma}, spec);
  const Image& img = canvas.image();
  EXPECT_GT(countColorPixels(img, magma(0.0), 3, region(bar)), int(bar.w));
  EXPECT_GT(countColorPixels(img, magma(1.0), 3, region(bar)), int(bar.w));
  // The high end at the top.
  EXPECT_EQ(img.at(int(bar.center().x), int(bar.top()) + 1), magma(1.0 - 1.5 / bar.h));
  // Labels right of the bar; everything inside the area.
  const Rect labels = Rect::fromEdges(bar.right() + 4.0, area.top(), area.right(), area.bottom());
  EXPECT_GT(countColorPixels(img, {0, 0, 0, 255}, 60, region(labels)), 100);
  const InkBox ink = inkBounds(img, kWhite, 10);
  EXPECT_GE(ink.x0, int(area.left()));
  EXPECT_LE(ink.x1, int(area.right()));
  EXPECT_GE(ink.y0, int(area.top()));
  EXPECT_LE(ink.y1, int(area.bottom()));
}

TEST(ColorBar, ContourMapsCarryADiscreteBar) {
  ContourSpec spec = linearField();
  spec.map = viridis;
  Canvas canvas(spec.width, spec.height);
  const Axes axes = drawContour(canvas, {0.0, 0.0, double(spec.width), double(spec.height)}, spec);
  const Rect right = Rect::fromEdges(axes.area().right() + 2.0, 0.0, spec.width, spec.height);
  EXPECT_GT(countColorPixels(canvas.image(), viridis(0.0), 2, region(right)), 50);
  EXPECT_GT(countColorPixels(canvas.image(), viridis(1.0), 2, region(right)), 50);
  const InkBox ink = inkBounds(canvas.image(), kWhite, 10);
  EXPECT_LE(ink.x1, spec.width - 7);  // the bar's title stays off the border
}

// ---------------------------------------------------------------------------------------------
// Overlays and edge cases

TEST(Contour, ArrowsAndTrajectoriesOverEmptyAxes) {
  ContourSpec spec;  // no values: axes and overlays only
  ArrowField field;
  field.positions = {{0.5, 0.5}};
  field.vectors = {{1.0, 0.0}};
  field.scale = 0.3;
  field.width = 2.0;
  spec.arrows = {field};
  PolylineOverlay path;
  path.color = {0, 160, 0, 255};
  path.width = 2.0;
  path.points = {{0.1, 0.1}, {0.3, 0.2}, {0.4, 0.15}};
  spec.polylines = {path};
  Canvas canvas(spec.width, spec.height);
  const Axes axes = drawContour(canvas, {0.0, 0.0, double(spec.width), double(spec.height)}, spec);
  const Rect& a = axes.area();
  // The arrow: black ink from its anchor to anchor + 0.3 along x, inside the frame.
  const Rect band = Rect::fromEdges(a.left() + 2.0, axes.yToPixel(0.5) - 20.0, a.right() - 2.0,
                                    axes.yToPixel(0.5) + 20.0);
  const InkBox ink = inkBounds(canvas.image(), kWhite, 30, region(band));
  EXPECT_NEAR(ink.x0, axes.xToPixel(0.5), 1.0);
  EXPECT_NEAR(ink.x1 + 1, axes.xToPixel(0.8), 1.0);
  EXPECT_GT(countColorPixels(canvas.image(), path.color, 10, region(a)), 20);
}

TEST(Contour, MissingValuesStayBlank) {
  ContourSpec spec;
  spec.values = sample(21, 21, [](double x, double y) { return x < 0.5 ? NAN : x + y; });
  spec.equalAspect = false;
  spec.isolines = false;  // labels may be white on dark bands: only the fill is looked at
  Canvas canvas(spec.width, spec.height);
  const Axes axes = drawContour(canvas, {0.0, 0.0, double(spec.width), double(spec.height)}, spec);
  const Rect& a = axes.area();
  const Rect leftQuarter = Rect::fromEdges(a.left(), a.top(), axes.xToPixel(0.45), a.bottom());
  const Rect rightQuarter = Rect::fromEdges(axes.xToPixel(0.55), a.top(), a.right(), a.bottom());
  const PixelRegion l = region(leftQuarter);
  EXPECT_EQ(countColorPixels(canvas.image(), kWhite, 0, l), long(l.x1 - l.x0) * (l.y1 - l.y0));
  EXPECT_EQ(countColorPixels(canvas.image(), kWhite, 0, region(rightQuarter)), 0);
}

TEST(Contour, RaggedRowsAreRejected) {
  ContourSpec spec;
  spec.values = {{0.0, 1.0, 2.0}, {0.0, 1.0}};
  EXPECT_THROW(drawContour(spec), std::invalid_argument);
}

}  // namespace
}  // namespace granular::render
