/// Seconds per frame of the 3-D particle view (ParticleRenderer, OpenGL 3.3 core on OSMesa's
/// llvmpipe) at 1920 × 1080.
///
/// Scenes: dense random packings (denseRandomPacking, seed 20261123) of the paper's radii,
/// 0.030–0.035 m, laid out in the proportions of the paper's 0.64 × 0.64 × 1.1 m box: 1980
/// spheres (the paper's count) and 10⁶. Colours by height (as a caller's colour map would give),
/// the open-top box's edges drawn, camera from fitCamera (azimuth −60°, elevation 20°, 30° field
/// of view). A frame is render(): instance upload, drawing at supersample × the size, the box
/// filter down, glReadPixels and the row flip. Context creation, renderer set-up and scene
/// building are not timed; the first frame (shader JIT compilation, framebuffer allocation) is
/// timed apart and reported as first_frame_s.
///
/// Counters:
///   s_per_frame     wall-clock seconds per frame (llvmpipe draws on all cores, so real time)
///   first_frame_s   the untimed first frame's wall-clock seconds
///   spheres         sphere count
///
/// Run: build/release/bench/granular_bench_render [--benchmark_filter=...]; see bench/RESULTS.md.
/// Exits 1 when a case failed (its error is in the table).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdint>
#include <exception>
#include <map>
#include <memory>
#include <vector>

#include "benchmark_failures.hpp"
#include "granular/packings.hpp"
#include "granular/render/gl_context.hpp"
#include "granular/render/particle_figure.hpp"
#include "granular/render/particle_view.hpp"
#include "granular/scene.hpp"

namespace {

using granular::Vec3;
using granular::render::Rgba;

constexpr double kRadiusMin = 0.030;  // the paper's radii [m]
constexpr double kRadiusMax = 0.035;
constexpr double kDensity = 500.0;  // [kg/m³], irrelevant to drawing
constexpr std::uint64_t kSeed = 20261123;
constexpr int kWidth = 1920, kHeight = 1080;  // [px]

struct Bed {
  granular::Particles particles;
  granular::BoxSpec box;
  std::vector<Rgba> colours;
};

/// The packing for n spheres, built once per n.
const Bed& bed(std::size_t n) {
  static std::map<std::size_t, Bed> cache;
  if (auto it = cache.find(n); it != cache.end()) return it->second;
  Bed b;
  granular::PackingLayout layout;
  layout.aspect = Vec3(0.64, 0.64, 1.1);
  b.particles =
      granular::denseRandomPacking(n, kRadiusMin, kRadiusMax, kDensity, kSeed, &b.box, layout);
  // Blue at the bottom to orange at the top: distinct colours per sphere, as in real use.
  b.colours.resize(n);
  const double z0 = b.box.min.z(), height = b.box.max.z() - b.box.min.z();
  for (std::size_t i = 0; i < n; ++i) {
    const double t = (b.particles.position[i].z() - z0) / height;
    b.colours[i] = {std::uint8_t(30 + 220 * t), std::uint8_t(120 - 40 * t),
                    std::uint8_t(230 - 200 * t), 255};
  }
  return cache.emplace(n, std::move(b)).first->second;
}

/// One context and renderer for the whole run (context creation is not what we time).
granular::render::ParticleRenderer& renderer() {
  static granular::render::GlContext context;
  static granular::render::ParticleRenderer instance(granular::render::GlContext::procLoader());
  return instance;
}

/// state.range(0) = sphere count, state.range(1) = supersampling factor.
void renderBenchmark(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const int supersample = static_cast<int>(state.range(1));
  try {
    const Bed& b = bed(n);
    granular::render::ParticleScene scene;
    scene.centres = b.particles.position;
    scene.radii = b.particles.radius;
    scene.colours = b.colours;
    scene.lines = granular::render::boxEdges(b.box.min, b.box.max, /*openTop=*/true);
    const granular::render::Camera camera = granular::render::fitCamera(
        b.box.min, b.box.max, -60.0, 20.0, 30.0, double(kWidth) / kHeight);

    granular::render::ParticleRenderer& r = renderer();
    const auto start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(r.render(scene, camera, kWidth, kHeight, supersample));
    const double firstFrame =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    for (auto _ : state) {
      granular::render::Image image = r.render(scene, camera, kWidth, kHeight, supersample);
      benchmark::DoNotOptimize(image.pixels.data());
    }
    state.counters["s_per_frame"] = benchmark::Counter(
        double(state.iterations()), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["first_frame_s"] = firstFrame;
    state.counters["spheres"] = double(n);
  } catch (const std::exception& e) {
    granular::bench::failCase(state, e);
  }
}

/// The whole Fig. 3 from data in memory: the 3-D view plus title and colour bar composed on the
/// canvas, at 1920×1080; state.range(0) = 1 also encodes the PNG (to /tmp).
void figureBenchmark(benchmark::State& state) {
  try {
    const Bed& b = bed(1980);
    std::vector<double> values;
    for (const Vec3& x : b.particles.position) values.push_back(x.z());
    // Its own context, made current here: run after the renderBenchmark cases.
    static granular::render::FigureRenderer figures;
    granular::render::ParticleFigureSpec spec;
    spec.centres = b.particles.position;
    spec.radii = b.particles.radius;
    spec.values = values;
    spec.boxMin = b.box.min;
    spec.boxMax = b.box.max;
    spec.title = "Settled assembly";
    spec.colorBarTitle = "Σ|F_ij| [N]";
    spec.width = kWidth;
    spec.height = kHeight;
    spec.style = granular::render::FigureStyle::forDpi(150);
    for (auto _ : state) {
      granular::render::Image image = figures.particleFigure(spec);
      if (state.range(0) == 1) granular::render::writePng(image, "/tmp/granular_bench_fig3.png");
      benchmark::DoNotOptimize(image.pixels.data());
    }
    state.counters["s_per_figure"] = benchmark::Counter(
        double(state.iterations()), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  } catch (const std::exception& e) {
    granular::bench::failCase(state, e);
  }
}

}  // namespace

BENCHMARK(renderBenchmark)
    ->ArgNames({"n", "supersample"})
    ->Args({1980, 2})
    ->Args({1980, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK(renderBenchmark)
    ->ArgNames({"n", "supersample"})
    ->Args({1000000, 2})
    ->Args({1000000, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(4)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

BENCHMARK(figureBenchmark)
    ->ArgNames({"png"})
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return granular::bench::anyCaseFailed() ? 1 : 0;
}
