/// Image-diff tests of the figures against goldens (small, deterministic inputs, fixed camera),
/// and the guards that catch a blank, clipped or incomplete figure.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "golden.hpp"
#include "granular/packings.hpp"
#include "granular/render/canvas.hpp"
#include "granular/render/contour.hpp"
#include "granular/render/figure_checks.hpp"
#include "granular/render/particle_figure.hpp"
#include "granular/render/plot.hpp"
#include "granular/scene.hpp"

using namespace granular;
using namespace granular::render;
using granular::testing::matchesGolden;

namespace {

/// 200 spheres of the paper's sizes, coloured by height: a miniature Fig. 3.
Image miniatureParticleFigure() {
  BoxSpec box;
  const Particles p = denseRandomPacking(200, 0.030, 0.035, 500.0, 3, &box);
  std::vector<double> height;
  for (const Vec3& x : p.position) height.push_back(x.z());
  static FigureRenderer renderer;
  ParticleFigureSpec spec;
  spec.centres = p.position;
  spec.radii = p.radius;
  spec.values = height;
  spec.boxMin = box.min;
  spec.boxMax = box.max;
  spec.title = "Test assembly";
  spec.colorBarTitle = "z [m]";
  spec.width = 260;
  spec.height = 300;
  spec.style = FigureStyle::forDpi(70);
  return renderer.particleFigure(spec);
}

/// A miniature Fig. 5: three thin and three bold lines with a dashed reference.
Image miniatureTimePlot() {
  PlotSpec p;
  p.title = "Stresses vs time";
  p.xLabel = "t [s]";
  p.yLabel = "σ [Pa]";
  p.width = 360;
  p.height = 240;
  p.style = FigureStyle::forDpi(70);
  for (int c = 0; c < 3; ++c) {
    for (double width : {1.2, 3.2}) {
      Series s;
      s.color = categorical(c);
      s.width = width;
      s.label = "σ" + std::to_string(c + 1) + (width > 2 ? " bold" : " thin");
      for (int k = 0; k <= 100; ++k) {
        const double t = 0.01 * k;
        s.x.push_back(t);
        s.y.push_back(-1600.0 - 60.0 * c + 15.0 * std::sin(2 * std::numbers::pi * (t + 0.1 * c)) +
                      (width > 2 ? 5.0 : 0.0));
      }
      p.series.push_back(s);
    }
  }
  ReferenceLine ref;
  ref.y = -1700;
  ref.label = "reference";
  p.references.push_back(ref);
  return drawPlot(p);
}

/// A miniature Fig. 9: a convex σ33 field on a midsection, growing with depth.
Image miniatureContour() {
  ContourSpec spec;
  const int nx = 25, nz = 41;
  spec.values.assign(nz, std::vector<double>(nx));
  for (int k = 0; k < nz; ++k) {
    for (int i = 0; i < nx; ++i) {
      const double x = i / double(nx - 1), depth = 1.0 - k / double(nz - 1);
      spec.values[k][i] = -3000.0 * depth * (1.0 - 0.3 * (2 * x - 1) * (2 * x - 1));
    }
  }
  spec.xMax = 0.6;
  spec.yMax = 1.0;
  spec.title = "σ₃₃ midsection";
  spec.xLabel = "x [m]";
  spec.yLabel = "z [m]";
  spec.colorBarTitle = "σ₃₃ [Pa]";
  spec.width = 260;
  spec.height = 340;
  spec.style = FigureStyle::forDpi(70);
  return drawContour(spec);
}

/// A miniature Fig. 10: trajectories bending towards the walls, the walls as the frame.
Image miniatureTrajectories() {
  ContourSpec spec;
  spec.xMax = 0.6;
  spec.yMax = 1.0;
  spec.colorBar = false;
  spec.title = "σ₁ trajectories";
  spec.xLabel = "x [m]";
  spec.yLabel = "z [m]";
  for (int l = 1; l <= 7; ++l) {
    PolylineOverlay line;
    const double x0 = 0.6 * l / 8.0;
    for (int k = 0; k <= 20; ++k) {
      const double z = k / 20.0;
      line.points.push_back({x0 + 0.08 * (x0 - 0.3) * z * z, z});
    }
    line.width = 1.5;
    spec.polylines.push_back(line);
  }
  spec.width = 220;
  spec.height = 340;
  spec.style = FigureStyle::forDpi(70);
  return drawContour(spec);
}

FigureExpectations particleExpectations() {
  FigureExpectations e;
  e.colorBarMap = viridis;
  e.minBarPixels = 10;
  return e;
}

}  // namespace

TEST(Figures, ParticleFigureMatchesGolden) {
  const Image image = miniatureParticleFigure();
  EXPECT_TRUE(matchesGolden(image, "particle_figure"));
  EXPECT_TRUE(figureProblems(image, particleExpectations()).empty());
}

TEST(Figures, TimePlotMatchesGolden) {
  const Image image = miniatureTimePlot();
  EXPECT_TRUE(matchesGolden(image, "time_plot"));
  EXPECT_TRUE(figureProblems(image, FigureExpectations{}).empty());
}

TEST(Figures, ContourMatchesGolden) {
  const Image image = miniatureContour();
  EXPECT_TRUE(matchesGolden(image, "contour"));
  FigureExpectations expect;
  expect.colorBarMap = viridis;
  expect.colorBarFromX = 0.7;
  expect.titleBand = 0.2;  // equal aspect centres the map vertically
  EXPECT_TRUE(figureProblems(image, expect).empty());
}

TEST(Figures, TrajectoriesMatchGolden) {
  const Image image = miniatureTrajectories();
  EXPECT_TRUE(matchesGolden(image, "trajectories"));
  EXPECT_TRUE(figureProblems(image, FigureExpectations{}).empty());
}

TEST(Figures, GuardsCatchBlankClippedOrIncompleteFigures) {
  const Image good = miniatureParticleFigure();
  const FigureExpectations expect = particleExpectations();
  ASSERT_TRUE(figureProblems(good, expect).empty());

  EXPECT_FALSE(figureProblems(Image(good.width, good.height), expect).empty());  // blank

  Image clipped = good;  // shifted left by 40 px: the assembly runs off the edge
  for (int y = 0; y < good.height; ++y) {
    for (int x = 0; x < good.width; ++x) {
      clipped.set(x, y, x + 40 < good.width ? good.at(x + 40, y) : Rgba{255, 255, 255, 255});
    }
  }
  EXPECT_FALSE(figureProblems(clipped, expect).empty());

  Canvas noBar(good);  // the colour bar (right fifth) painted over
  noBar.fillRect(Rect{0.8 * good.width, 0, 0.2 * good.width - 3, double(good.height)},
                 {255, 255, 255, 255});
  EXPECT_FALSE(figureProblems(noBar.image(), expect).empty());

  Canvas noTitle(good);  // the title band painted over
  noTitle.fillRect(Rect{0, 0, double(good.width), 0.08 * good.height}, {255, 255, 255, 255});
  EXPECT_FALSE(figureProblems(noTitle.image(), expect).empty());

  Canvas noLabels(miniatureTimePlot());  // the lower half's text gone
  noLabels.fillRect(
      Rect{0, 0.5 * noLabels.height(), double(noLabels.width()), 0.5 * noLabels.height()},
      {255, 255, 255, 255});
  noLabels.fillRect(Rect{0, 0.5 * noLabels.height(), 30, 30}, {200, 200, 200, 255});  // not blank
  EXPECT_FALSE(figureProblems(noLabels.image(), FigureExpectations{}).empty());
}
