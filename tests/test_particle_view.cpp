/// The 3-D particle view (render/particle_view.hpp) in an OSMesa context: geometry against the
/// analytic perspective projection, shading, depth, lines, camera framing, determinism.
/// Small images (160 × 120) keep each test to a few tens of milliseconds.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "granular/render/gl_context.hpp"
#include "granular/render/image.hpp"
#include "granular/render/particle_view.hpp"

/// LeakSanitizer hook (sanitize preset): Mesa 22.3's OSMesaMakeCurrent allocates a framebuffer
/// per context that OSMesaDestroyContext never frees (≈ 200 bytes per context, inside
/// libOSMesa, also after unbinding first). Not ours; without this the suite fails under LSan.
/// One definition per test binary: other GL tests rely on this one.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libOSMesa.so\n";
}

namespace granular::render {
namespace {

constexpr int kWidth = 160, kHeight = 120;  // [px]
const Rgba kWhite{255, 255, 255, 255};

int luminance(Rgba c) {
  return 299 * c.r + 587 * c.g + 114 * c.b;
}  // ×1000

bool isBackground(Rgba c) {
  return c == kWhite;
}

/// One context and renderer for the whole suite (creating them costs more than a render).
class ParticleViewTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    context_ = std::make_unique<GlContext>();
    renderer_ = std::make_unique<ParticleRenderer>(GlContext::procLoader());
  }
  static void TearDownTestSuite() {
    context_->makeCurrent();  // GL objects go before their context, with it current
    renderer_.reset();
    context_.reset();
  }
  /// The suite's renderer, with its context made current (a test may have made another one
  /// current, and OSMesa leaves none current when that one is destroyed).
  static ParticleRenderer& renderer() {
    context_->makeCurrent();
    return *renderer_;
  }

  /// Looking along +y at the origin from distance `distance` [m], 30° vertical field of view.
  static Camera axisCamera(double distance) {
    Camera camera;
    camera.eye = Vec3(0.0, -distance, 0.0);
    camera.target = Vec3::Zero();
    camera.up = Vec3::UnitZ();
    camera.fovYDegrees = 30.0;
    return camera;
  }

  /// Projected radius [px] of a sphere of radius r seen on the axis from distance d with the
  /// camera above: the tangent cone's half-angle is asin(r/d).
  static double projectedRadius(double r, double d, double fovYDegrees, int height) {
    const double halfAngle = std::asin(r / d);
    return std::tan(halfAngle) / std::tan(0.5 * fovYDegrees * std::numbers::pi / 180.0) * 0.5 *
           height;
  }

 private:
  static inline std::unique_ptr<GlContext> context_;
  static inline std::unique_ptr<ParticleRenderer> renderer_;
};

TEST_F(ParticleViewTest, ContextIsCoreProfileOnOSMesa) {
  GlContext probe;  // a second context works and becomes current
  EXPECT_NE(probe.version().find("Core Profile"), std::string::npos) << probe.version();
  EXPECT_FALSE(probe.renderer().empty());
}

TEST_F(ParticleViewTest, RefusesClearlyWithoutACurrentContext) {
  // OSMesa contexts are current per thread: a new thread has none, and every GL call there
  // would silently do nothing.
  std::string message;
  std::thread([&] {
    try {
      ParticleRenderer orphan(GlContext::procLoader());
    } catch (const RenderError& e) {
      message = e.what();
    }
  }).join();
  EXPECT_NE(message.find("current"), std::string::npos) << message;
}

TEST_F(ParticleViewTest, SphereCoversItsProjectedDiscOnWhite) {
  const double r = 1.0, d = 6.0;
  const std::vector<Vec3> centres = {Vec3::Zero()};
  const std::vector<double> radii = {r};
  const Rgba base{200, 60, 60, 255};
  const std::vector<Rgba> colours = {base};
  ParticleScene scene;
  scene.centres = centres;
  scene.radii = radii;
  scene.colours = colours;

  const Image image = renderer().render(scene, axisCamera(d), kWidth, kHeight);
  ASSERT_EQ(image.width, kWidth);
  ASSERT_EQ(image.height, kHeight);

  const double radius = projectedRadius(r, d, 30.0, kHeight);  // ≈ 37.9 px
  const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
  int inside = 0, outside = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const double dist = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
      const Rgba c = image.at(x, y);
      EXPECT_EQ(c.a, 255);
      if (dist < radius - 2.0) {
        EXPECT_FALSE(isBackground(c)) << "inside the disc at " << x << "," << y;
        ++inside;
      } else if (dist > radius + 2.0) {
        EXPECT_TRUE(isBackground(c)) << "outside the disc at " << x << "," << y;
        ++outside;
      }
    }
  }
  EXPECT_GT(inside, 3000);
  EXPECT_GT(outside, 10000);

  // Lit from the camera: the centre is brighter than every point near the rim.
  const Rgba centre = image.at(kWidth / 2, kHeight / 2);
  for (int k = 0; k < 8; ++k) {
    const double phi = k * std::numbers::pi / 4.0;
    const int x = int(cx + 0.85 * radius * std::cos(phi)),
              y = int(cy + 0.85 * radius * std::sin(phi));
    EXPECT_GT(luminance(centre), luminance(image.at(x, y))) << "rim sample " << k;
  }
  // Colours are not washed out: the centre is close to the sphere's own colour.
  EXPECT_NEAR(centre.r, base.r, 30);
  EXPECT_NEAR(centre.g, base.g, 30);
  EXPECT_NEAR(centre.b, base.b, 30);
  EXPECT_GT(centre.r, 2 * centre.g);
}

TEST_F(ParticleViewTest, NearerSphereOccludesFartherInEitherDrawOrder) {
  ParticleRenderer& renderer = ParticleViewTest::renderer();
  const Camera camera = axisCamera(6.0);
  const Rgba red{220, 30, 30, 255}, blue{30, 30, 220, 255};
  // Red at the origin (projected radius ≈ 37.9 px); blue 3 m behind it, 0.8 m to the right:
  // its centre projects ≈ 19.9 px right of the image centre, radius ≈ 25 px.
  const Vec3 nearCentre = Vec3::Zero(), farCentre(0.8, 3.0, 0.0);
  for (bool nearFirst : {true, false}) {
    const std::vector<Vec3> centres = nearFirst ? std::vector<Vec3>{nearCentre, farCentre}
                                                : std::vector<Vec3>{farCentre, nearCentre};
    const std::vector<double> radii = {1.0, 1.0};
    const std::vector<Rgba> colours =
        nearFirst ? std::vector<Rgba>{red, blue} : std::vector<Rgba>{blue, red};
    ParticleScene scene;
    scene.centres = centres;
    scene.radii = radii;
    scene.colours = colours;
    const Image image = renderer.render(scene, camera, kWidth, kHeight);

    const auto farPixel = projectToPixel(camera, kWidth, kHeight, farCentre);
    ASSERT_TRUE(farPixel);
    EXPECT_NEAR(farPixel->x() - 0.5 * kWidth, 19.9, 0.2);
    // Inside both discs: the near (red) sphere wins.
    const Rgba both = image.at(int(farPixel->x()), int(farPixel->y()));
    EXPECT_GT(both.r, 3 * both.b) << "nearFirst=" << nearFirst;
    // Inside the far disc only: blue.
    const Rgba farOnly = image.at(int(farPixel->x()) + 22, int(farPixel->y()));
    EXPECT_GT(farOnly.b, 3 * farOnly.r) << "nearFirst=" << nearFirst;
  }
}

TEST_F(ParticleViewTest, RendersAreBitIdentical) {
  std::mt19937_64 rng(20261123);
  auto uniform = [&] { return double(rng() >> 11) * 0x1.0p-53; };
  std::vector<Vec3> centres;
  std::vector<double> radii;
  std::vector<Rgba> colours;
  for (int i = 0; i < 400; ++i) {
    centres.emplace_back(0.64 * uniform(), 0.64 * uniform(), 1.1 * uniform());
    radii.push_back(0.03 + 0.005 * uniform());
    colours.push_back(
        {std::uint8_t(rng() & 255), std::uint8_t(rng() & 255), std::uint8_t(rng() & 255), 255});
  }
  ParticleScene scene;
  scene.centres = centres;
  scene.radii = radii;
  scene.colours = colours;
  const Vec3 boxMin = Vec3::Zero(), boxMax(0.64, 0.64, 1.1);
  scene.lines = boxEdges(boxMin, boxMax, true);
  const Camera camera = fitCamera(boxMin, boxMax, -60.0, 25.0, 30.0, double(kWidth) / kHeight);

  ParticleRenderer& first = renderer();
  const Image a = first.render(scene, camera, kWidth, kHeight);
  const Image b = first.render(scene, camera, kWidth, kHeight);
  ParticleRenderer second(GlContext::procLoader());  // fresh GL objects, same context
  const Image c = second.render(scene, camera, kWidth, kHeight);
  EXPECT_EQ(a.pixels, b.pixels);
  EXPECT_EQ(a.pixels, c.pixels);
}

TEST_F(ParticleViewTest, BoxEdgesAreDrawnAndOpenTopLeavesTheTopOut) {
  const Vec3 boxMin = Vec3::Zero(), boxMax(0.64, 0.64, 1.1);
  EXPECT_EQ(boxEdges(boxMin, boxMax).size(), 12u);
  const std::vector<Segment> open = boxEdges(boxMin, boxMax, true);
  ASSERT_EQ(open.size(), 8u);
  for (const auto& [a, b] : open) EXPECT_FALSE(a.z() == boxMax.z() && b.z() == boxMax.z());

  const Camera camera = fitCamera(boxMin, boxMax, -60.0, 25.0, 30.0, double(kWidth) / kHeight);
  ParticleRenderer& renderer = ParticleViewTest::renderer();
  for (bool openTop : {false, true}) {
    ParticleScene scene;  // lines only
    scene.lines = boxEdges(boxMin, boxMax, openTop);
    const Image image = renderer.render(scene, camera, kWidth, kHeight);
    int dark = 0;
    for (std::size_t i = 0; i < image.pixels.size(); i += 4) dark += image.pixels[i] < 128;
    EXPECT_GT(dark, 300) << "openTop=" << openTop;  // ≈ 8–12 edges × 60–100 px × 2 px wide
    for (const auto& [a, b] : boxEdges(boxMin, boxMax)) {
      const auto mid = projectToPixel(camera, kWidth, kHeight, 0.5 * (a + b));
      ASSERT_TRUE(mid);
      const Rgba c = image.at(int(mid->x()), int(mid->y()));
      const bool topEdge = a.z() == boxMax.z() && b.z() == boxMax.z();
      if (openTop && topEdge) {
        EXPECT_TRUE(isBackground(c)) << "top edge drawn at " << mid->transpose();
      } else {
        EXPECT_LT(c.r, 160) << "edge missing at " << mid->transpose();
      }
    }
  }
}

TEST_F(ParticleViewTest, LineBehindASphereIsHidden) {
  // A vertical line 2 m behind a sphere on the axis: hidden where the sphere covers it.
  const std::vector<Vec3> centres = {Vec3::Zero()};
  const std::vector<double> radii = {1.0};
  ParticleScene scene;
  scene.centres = centres;
  scene.radii = radii;
  scene.defaultColour = {240, 240, 240, 255};  // light grey: the dark line would show on it
  scene.lines = {{Vec3(0.0, 2.0, -3.0), Vec3(0.0, 2.0, 3.0)}};
  scene.lineWidth = 3.0;
  const Image image = renderer().render(scene, axisCamera(6.0), kWidth, kHeight);
  const Rgba centre = image.at(kWidth / 2, kHeight / 2);
  EXPECT_GT(centre.r, 150);  // sphere, not line
  const Rgba aboveSphere = image.at(kWidth / 2, 5);
  EXPECT_LT(aboveSphere.r, 100);  // the line itself, where nothing hides it
}

TEST_F(ParticleViewTest, FitCameraKeepsTheBoxInside) {
  const Vec3 boxMin(-0.1, 0.2, 0.0), boxMax(0.54, 0.84, 1.1);
  for (double aspect : {160.0 / 120.0, 0.5, 2.5}) {
    for (double azimuth : {-90.0, -60.0, 0.0, 135.0}) {
      for (double elevation : {-30.0, 0.0, 20.0, 89.0, 90.0}) {
        const int width = int(std::lround(120 * aspect)), height = 120;
        const Camera camera = fitCamera(boxMin, boxMax, azimuth, elevation, 30.0, aspect);
        double extent = 0.0;  // largest |ndc| over the corners
        for (int i = 0; i < 8; ++i) {
          const Vec3 corner((i & 1) ? boxMax.x() : boxMin.x(), (i & 2) ? boxMax.y() : boxMin.y(),
                            (i & 4) ? boxMax.z() : boxMin.z());
          const auto p = projectToPixel(camera, width, height, corner);
          ASSERT_TRUE(p);
          EXPECT_GE(p->x(), 0.0);
          EXPECT_LE(p->x(), width);
          EXPECT_GE(p->y(), 0.0);
          EXPECT_LE(p->y(), height);
          extent = std::max({extent, std::abs(2.0 * p->x() / width - 1.0),
                             std::abs(2.0 * p->y() / height - 1.0)});
        }
        // Framed, not lost in the middle: some corner reaches the default 5 % margin.
        EXPECT_NEAR(extent, 0.95, 1e-6) << aspect << " " << azimuth << " " << elevation;
      }
    }
  }
}

TEST_F(ParticleViewTest, FittedSceneLeavesTheBorderWhite) {
  // Spheres filling the box up to its faces, box edges drawn: nothing reaches the image border
  // (the 5 % margin, 3 px here, exceeds the 2 px that a 2 px wide line reaches past a corner).
  const Vec3 boxMin = Vec3::Zero(), boxMax(0.64, 0.64, 1.1);
  std::vector<Vec3> centres;
  std::vector<double> radii;
  for (double x = 0.035; x < 0.64; x += 0.07)
    for (double y = 0.035; y < 0.64; y += 0.07)
      for (double z = 0.035; z < 1.1; z += 0.07) {
        centres.emplace_back(x, y, z);
        radii.push_back(0.035);
      }
  ParticleScene scene;
  scene.centres = centres;
  scene.radii = radii;
  scene.lines = boxEdges(boxMin, boxMax);
  const Camera camera = fitCamera(boxMin, boxMax, -60.0, 25.0, 30.0, double(kWidth) / kHeight);
  const Image image = renderer().render(scene, camera, kWidth, kHeight);
  for (int x = 0; x < kWidth; ++x) {
    EXPECT_TRUE(isBackground(image.at(x, 0)));
    EXPECT_TRUE(isBackground(image.at(x, kHeight - 1)));
  }
  for (int y = 0; y < kHeight; ++y) {
    EXPECT_TRUE(isBackground(image.at(0, y)));
    EXPECT_TRUE(isBackground(image.at(kWidth - 1, y)));
  }
}

TEST_F(ParticleViewTest, EmptySceneIsBackground) {
  ParticleScene scene;
  scene.background = {10, 20, 30, 255};
  const Image image = renderer().render(scene, axisCamera(5.0), 17, 9, 3);  // odd sizes
  ASSERT_EQ(image.width, 17);
  ASSERT_EQ(image.height, 9);
  for (int y = 0; y < 9; ++y)
    for (int x = 0; x < 17; ++x) EXPECT_EQ(image.at(x, y), (Rgba{10, 20, 30, 255}));
}

TEST_F(ParticleViewTest, RejectsBadInput) {
  const std::vector<Vec3> centres = {Vec3::Zero(), Vec3::Ones()};
  const std::vector<double> radii = {0.1};
  ParticleScene scene;
  scene.centres = centres;
  scene.radii = radii;
  EXPECT_THROW(renderer().render(scene, axisCamera(5.0), 16, 16), std::invalid_argument);
  scene.centres = std::span<const Vec3>(centres).first(1);
  EXPECT_THROW(renderer().render(scene, axisCamera(5.0), 0, 16), std::invalid_argument);
  EXPECT_THROW(renderer().render(scene, axisCamera(5.0), 16, 16, 0), std::invalid_argument);
  // 20000 px after supersampling exceeds llvmpipe's 16384 px limit.
  EXPECT_THROW(renderer().render(scene, axisCamera(5.0), 10000, 16, 2), RenderError);
  // The renderer still works afterwards.
  EXPECT_FALSE(renderer().render(scene, axisCamera(5.0), 16, 16).empty());
}

}  // namespace
}  // namespace granular::render
