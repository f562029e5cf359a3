/// Walls in the particle view (render/particle_view.hpp's surfaces and outlines, from
/// app/gui/wall_drawing.hpp): a cylinder tints what it covers without hiding the spheres inside
/// it, hides nothing in front of it, leaves no trace in the next scene without walls, and the
/// figure's camera frames a wall taller than the box.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "granular/render/gl_context.hpp"
#include "granular/render/image.hpp"
#include "granular/render/particle_figure.hpp"
#include "granular/render/particle_view.hpp"
#include "wall_drawing.hpp"

namespace granular::render {
namespace {

constexpr int kWidth = 160, kHeight = 120;  // [px]
const Rgba kWhite{255, 255, 255, 255};
const Rgba kRed{220, 30, 30, 255};

class WallViewTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    context_ = std::make_unique<GlContext>();
    renderer_ = std::make_unique<ParticleRenderer>(GlContext::procLoader());
  }
  static void TearDownTestSuite() {
    context_->makeCurrent();
    renderer_.reset();
    context_.reset();
  }
  static ParticleRenderer& renderer() {
    context_->makeCurrent();
    return *renderer_;
  }

 private:
  static inline std::unique_ptr<GlContext> context_;
  static inline std::unique_ptr<ParticleRenderer> renderer_;
};

/// A cylinder of radius 0.5 m from z = 0 to 1 m about the z axis, as the view draws it.
gui::WallDrawing cylinder() {
  Wall w;
  w.shape = WallShape::Frustum;
  w.normal = Vec3::UnitZ();
  w.length = 1.0;
  w.radiusStart = w.radiusEnd = 0.5;
  return gui::wallDrawing(std::vector<Wall>{w});
}

/// Level with the cylinder's middle, 4 m in front of it, looking along +y.
Camera sideCamera() {
  Camera c;
  c.eye = Vec3(0.0, -4.0, 0.5);
  c.target = Vec3(0.0, 0.0, 0.5);
  return c;
}

TEST_F(WallViewTest, CylinderTintsWhatItCoversAndTheSphereInsideShowsThrough) {
  const std::vector<Vec3> centres = {Vec3(0.0, 0.0, 0.5)};
  const std::vector<double> radii = {0.15};
  const std::vector<Rgba> colours = {kRed};
  const gui::WallDrawing walls = cylinder();
  ParticleScene scene;
  scene.centres = centres;
  scene.radii = radii;
  scene.colours = colours;
  scene.surfaces = walls.triangles;
  scene.outlines = walls.outlines;
  const Camera camera = sideCamera();
  const Image image = renderer().render(scene, camera, kWidth, kHeight);

  // (a) Inside the cylinder's silhouette, away from the sphere and the rims: not the
  // background, tinted towards the wall's blue (white loses more red than blue).
  for (const Vec3& x :
       {Vec3(-0.3, 0.0, 0.2), Vec3(0.3, 0.0, 0.2), Vec3(-0.3, 0.0, 0.8), Vec3(0.3, 0.0, 0.8)}) {
    const auto p = projectToPixel(camera, kWidth, kHeight, x);
    ASSERT_TRUE(p);
    const Rgba c = image.at(int(p->x()), int(p->y()));
    EXPECT_NE(c, kWhite) << x.transpose();
    EXPECT_GT(int(c.b) - int(c.r), 10) << x.transpose();
    EXPECT_EQ(c.a, 255);  // blending keeps the image opaque
  }
  // Beside the cylinder: the background.
  const auto outside = projectToPixel(camera, kWidth, kHeight, Vec3(0.8, 0.0, 0.5));
  ASSERT_TRUE(outside);
  EXPECT_EQ(image.at(int(outside->x()), int(outside->y())), kWhite);

  // (b) The sphere inside shows through the front wall: its red dominates at its centre.
  const auto centre = projectToPixel(camera, kWidth, kHeight, centres[0]);
  ASSERT_TRUE(centre);
  const Rgba s = image.at(int(centre->x()), int(centre->y()));
  EXPECT_GT(s.r, 2 * s.g);
  EXPECT_GT(s.r, 2 * s.b);
  EXPECT_GT(s.r, 120);
}

TEST_F(WallViewTest, SphereInFrontOfAWallIsNotTinted) {
  // Between the eye and the cylinder: the wall behind it must fail the depth test.
  const std::vector<Vec3> centres = {Vec3(0.0, -1.5, 0.5)};
  const std::vector<double> radii = {0.2};
  const std::vector<Rgba> colours = {kRed};
  const gui::WallDrawing walls = cylinder();
  ParticleScene scene;
  scene.centres = centres;
  scene.radii = radii;
  scene.colours = colours;
  const Camera camera = sideCamera();
  const Image bare = renderer().render(scene, camera, kWidth, kHeight);
  scene.surfaces = walls.triangles;
  scene.outlines = walls.outlines;
  const Image walled = renderer().render(scene, camera, kWidth, kHeight);
  const auto p = projectToPixel(camera, kWidth, kHeight, centres[0]);
  ASSERT_TRUE(p);
  EXPECT_EQ(walled.at(int(p->x()), int(p->y())), bare.at(int(p->x()), int(p->y())));
}

TEST_F(WallViewTest, AWallLeavesNoTraceInTheNextSceneWithout) {
  // The surface pass turns blending on and depth writes off; the scene after must draw as if
  // it had never run, bit for bit.
  const std::vector<Vec3> centres = {Vec3(0.0, 0.0, 0.5), Vec3(0.2, 0.1, 0.3)};
  const std::vector<double> radii = {0.15, 0.1};
  ParticleScene scene;
  scene.centres = centres;
  scene.radii = radii;
  scene.lines = boxEdges(Vec3(-0.5, -0.5, 0.0), Vec3(0.5, 0.5, 1.0), true);
  const Camera camera = sideCamera();
  const Image before = renderer().render(scene, camera, kWidth, kHeight);
  const gui::WallDrawing walls = cylinder();
  ParticleScene walled = scene;
  walled.surfaces = walls.triangles;
  walled.outlines = walls.outlines;
  const Image withWalls = renderer().render(walled, camera, kWidth, kHeight);
  const Image after = renderer().render(scene, camera, kWidth, kHeight);
  EXPECT_NE(withWalls.pixels, before.pixels);
  EXPECT_EQ(after.pixels, before.pixels);
}

TEST_F(WallViewTest, FramingTakesInAWallTallerThanTheBox) {
  // A silo three times as tall as the box its particles start in.
  Wall w;
  w.shape = WallShape::Frustum;
  w.normal = Vec3::UnitZ();
  w.length = 3.0;
  w.radiusStart = w.radiusEnd = 0.5;
  const gui::WallDrawing walls = gui::wallDrawing(std::vector<Wall>{w});
  const Vec3 boxMin(-0.5, -0.5, 0.0), boxMax(0.5, 0.5, 1.0);
  const auto [lo, hi] = boundsWith(boxMin, boxMax, walls.triangles, walls.outlines);
  EXPECT_NEAR(hi.z(), 3.0, 1e-12);
  EXPECT_NEAR(lo.z(), 0.0, 1e-12);
  // Without walls, the box itself.
  const auto [boxLo, boxHi] = boundsWith(boxMin, boxMax, {}, {});
  EXPECT_EQ(boxLo, boxMin);
  EXPECT_EQ(boxHi, boxMax);

  const Camera camera = fitCamera(lo, hi, -60.0, 20.0, 30.0, double(kWidth) / kHeight);
  for (const Triangle& t : walls.triangles) {
    for (const Vec3& x : t) {
      const auto p = projectToPixel(camera, kWidth, kHeight, x);
      ASSERT_TRUE(p);
      EXPECT_TRUE(p->x() >= 0 && p->x() <= kWidth && p->y() >= 0 && p->y() <= kHeight)
          << x.transpose() << " at " << p->transpose();
    }
  }
}

TEST_F(WallViewTest, ParticleFigureDrawsAWallTallerThanTheBoxWhole) {
  // A silo three times as tall as its box, in a figure without a title: the wall is drawn
  // (background turned light blue), and the view's camera frames it whole, so the band above
  // the view stays background: framed by the box alone, the cylinder would run off the view's
  // top edge.
  const std::vector<Vec3> centres = {Vec3(0.0, 0.0, 0.2)};
  const std::vector<double> radii = {0.15};
  const std::vector<double> values = {1.0};
  Wall w;
  w.shape = WallShape::Frustum;
  w.normal = Vec3::UnitZ();
  w.length = 3.0;
  w.radiusStart = w.radiusEnd = 0.5;
  const gui::WallDrawing walls = gui::wallDrawing(std::vector<Wall>{w});
  ParticleFigureSpec spec;
  spec.centres = centres;
  spec.radii = radii;
  spec.values = values;
  spec.boxMin = Vec3(-0.5, -0.5, 0.0);
  spec.boxMax = Vec3(0.5, 0.5, 1.0);
  spec.width = 200;
  spec.height = 300;
  FigureRenderer figures;
  const Image bare = figures.particleFigure(spec);
  spec.surfaces = walls.triangles;
  spec.outlines = walls.outlines;
  const Image walled = figures.particleFigure(spec);
  ASSERT_EQ(walled.width, bare.width);
  ASSERT_EQ(walled.height, bare.height);
  long tinted = 0;  // background in the bare figure, tinted towards the wall's blue here
  for (int y = 0; y < bare.height; ++y) {
    for (int x = 0; x < bare.width; ++x) {
      const Rgba c = walled.at(x, y);
      tinted += bare.at(x, y) == kWhite && int(c.b) > int(c.r) + 25;
    }
  }
  EXPECT_GT(tinted, 2000);
  const int viewTop = int(spec.style.px(spec.style.margin));
  for (int y = 0; y <= viewTop + 2; ++y) {
    for (int x = 0; x < walled.width; ++x) {
      ASSERT_EQ(walled.at(x, y), kWhite) << "ink at " << x << "," << y;
    }
  }
}

}  // namespace
}  // namespace granular::render
