/// granular_bench_mesh_cylinder: the cost of a wall drawn as a triangle mesh. One settled bed in
/// a cylinder on a floor, stepped in the analytic cylinder (WallShape::Frustum) and in the same
/// cylinder as a mesh of 2 · facets · rings triangles (default 10⁴), from the same state,
/// alternating, on 1 and 2 threads; a plain program that prints a markdown table (bench/RESULTS.md,
/// "Walls drawn as meshes").
///
/// The bed: a dense random packing (denseRandomPacking, seed 20261128) of the paper's material
/// and radii (0.030–0.035 m), cut to the cylinder inscribed in its footprint and to the first n
/// particles from the bottom, settled under gravity for `--settle` steps in the analytic cylinder
/// (untimed, scale_bed_settling.hpp's heavier damping and velocity Verlet). The timed runs start
/// from the settled particles at rest, friction 0.3, velocity Verlet at 10⁻⁴ s. The mesh's facets
/// touch the analytic cylinder at their middles (its corners lie outside it).
///
/// Usage: granular_bench_mesh_cylinder [--n N] [--facets F] [--rings R] [--settle S]
///                                      [--steps T] [--rounds K] [--threads 1|2]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "granular/packings.hpp"
#include "granular/scene.hpp"
#include "granular/simulation.hpp"
#include "granular/wall_mesh.hpp"
#include "scale_bed_settling.hpp"

namespace {

using granular::Vec3;

constexpr double kRadiusMin = 0.030, kRadiusMax = 0.035;  // the paper's [m]
constexpr double kTimeStep = 1e-4;                        // [s]
constexpr std::uint64_t kSeed = 20261128;

struct Options {
  long n = 100000;
  long facets = 100;
  long rings = 50;
  long settle = 1500;
  long steps = 40;
  long rounds = 3;
  long threads = 0;  ///< 0: 1 and then 2
};

long positive(const std::string& flag, const char* value) {
  char* end = nullptr;
  const long v = std::strtol(value, &end, 10);
  if (end == value || *end != '\0' || v <= 0) {
    std::cerr << "granular_bench_mesh_cylinder: " << flag << " needs a positive integer, not '"
              << value << "'\n";
    std::exit(2);
  }
  return v;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--help") {
      std::cout << "usage: granular_bench_mesh_cylinder [--n N] [--facets F] [--rings R] "
                   "[--settle S] [--steps T] [--rounds K] [--threads T]\n";
      std::exit(0);
    }
    if (k + 1 >= argc) {
      std::cerr << "granular_bench_mesh_cylinder: " << arg << " needs a value\n";
      std::exit(2);
    }
    const char* value = argv[++k];
    if (arg == "--n") {
      o.n = positive(arg, value);
    } else if (arg == "--facets") {
      o.facets = std::max(3L, positive(arg, value));
    } else if (arg == "--rings") {
      o.rings = positive(arg, value);
    } else if (arg == "--settle") {
      o.settle = positive(arg, value);
    } else if (arg == "--steps") {
      o.steps = positive(arg, value);
    } else if (arg == "--rounds") {
      o.rounds = positive(arg, value);
    } else if (arg == "--threads") {
      o.threads = positive(arg, value);
    } else {
      std::cerr << "granular_bench_mesh_cylinder: unknown option " << arg << " (--help)\n";
      std::exit(2);
    }
  }
  return o;
}

/// The cylinder about the vertical axis through `base`, of radius `radius` and height `height`.
granular::Wall analyticCylinder(const Vec3& base, double radius, double height) {
  granular::Wall w;
  w.name = "cylinder";
  w.shape = granular::WallShape::Frustum;
  w.point = base;
  w.normal = Vec3::UnitZ();
  w.length = height;
  w.radiusStart = w.radiusEnd = radius;
  w.pivot = base;
  return w;
}

/// The same cylinder as `facets` × `rings` quads of two triangles, the facets' middles on it.
granular::Wall meshCylinder(const Vec3& base, double radius, double height, long facets,
                            long rings) {
  granular::TriangleMesh m;
  const double corner = radius / std::cos(std::numbers::pi / double(facets));
  for (long j = 0; j <= rings; ++j) {
    for (long k = 0; k < facets; ++k) {
      const double a = 2.0 * std::numbers::pi * double(k) / double(facets);
      m.vertex.push_back(base + Vec3(corner * std::cos(a), corner * std::sin(a),
                                     height * double(j) / double(rings)));
    }
  }
  auto at = [&](long k, long j) { return std::uint32_t(j * facets + (k % facets)); };
  for (long j = 0; j < rings; ++j) {
    for (long k = 0; k < facets; ++k) {
      m.triangle.push_back({at(k, j), at(k + 1, j), at(k + 1, j + 1)});
      m.triangle.push_back({at(k, j), at(k + 1, j + 1), at(k, j + 1)});
    }
  }
  granular::Wall w;
  w.name = "cylinder";
  w.shape = granular::WallShape::Mesh;
  w.mesh = granular::poseMesh(std::make_shared<const granular::TriangleMesh>(std::move(m)),
                              Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitX());
  return w;
}

granular::Wall floorAt(const Vec3& base) {
  granular::Wall w;
  w.name = "bottom";
  w.point = base;
  w.normal = Vec3::UnitZ();
  return w;
}

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

/// Wall-clock seconds of `steps` steps.
double timed(granular::Simulation& sim, long steps) {
  const auto start = std::chrono::steady_clock::now();
  sim.run(static_cast<std::uint64_t>(steps));
  return seconds(start);
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  // A footprint a third as wide as the bed is tall: denseRandomPacking fills the box's cylinder
  // and its corners; the corners (1 − π/4 of it) are cut away, so ask for n / (π/4) and more.
  granular::PackingLayout layout;
  layout.aspect = Vec3(1.0, 1.0, 1.2);
  const auto asked = static_cast<std::size_t>(double(o.n) / (std::numbers::pi / 4.0) * 1.15);
  granular::BoxSpec box;
  const granular::Particles packed = granular::denseRandomPacking(
      asked, kRadiusMin, kRadiusMax, granular::Material{}.density, kSeed, &box, layout);
  const Vec3 base(0.5 * (box.min.x() + box.max.x()), 0.5 * (box.min.y() + box.max.y()),
                  box.min.z());
  const double radius = 0.5 * std::min(box.max.x() - box.min.x(), box.max.y() - box.min.y());
  const double height = 1.5 * (box.max.z() - box.min.z());
  granular::Particles particles;
  for (std::size_t i = 0; i < packed.size() && long(particles.size()) < o.n; ++i) {
    const Vec3 r = packed.position[i] - base;
    if (std::hypot(r.x(), r.y()) < radius - packed.radius[i]) {
      particles.add(packed.position[i], packed.radius[i], granular::Material{}.density);
    }
  }
  const auto n = long(particles.size());
  if (n < o.n) {
    std::fprintf(stderr, "granular_bench_mesh_cylinder: the packing gave %ld particles, not %ld\n",
                 n, o.n);
  }
  granular::SimulationConfig config;
  config.material.friction = 0.3;
  config.integrator = granular::Integrator::VelocityVerlet;
  config.timeStep = kTimeStep;
  config.threads = 2;
  const auto settleStart = std::chrono::steady_clock::now();
  {
    granular::Simulation settle(std::move(particles),
                                {floorAt(base), analyticCylinder(base, radius, height)},
                                granular::bench::settlingConfig(config));
    settle.run(static_cast<std::uint64_t>(o.settle));
    particles = settle.particles();
  }
  std::fill(particles.velocity.begin(), particles.velocity.end(), Vec3::Zero());
  std::fill(particles.angularVelocity.begin(), particles.angularVelocity.end(), Vec3::Zero());
  std::fprintf(stderr, "n = %ld in a cylinder of radius %.3f m: settled %ld steps in %.0f s\n", n,
               radius, o.settle, seconds(settleStart));

  const long triangles = 2 * o.facets * o.rings;
  std::printf(
      "| threads | cylinder | ms per step (rounds) | ns per particle-step | wall "
      "contacts | analytic / mesh time |\n|---|---|---|---|---|---|\n");
  const std::vector<int> threadCounts =
      o.threads > 0 ? std::vector<int>{int(o.threads)} : std::vector<int>{1, 2};
  for (int threads : threadCounts) {
    config.threads = threads;
    granular::Simulation analytic(particles,
                                  {floorAt(base), analyticCylinder(base, radius, height)}, config);
    granular::Simulation meshed(
        particles, {floorAt(base), meshCylinder(base, radius, height, o.facets, o.rings)}, config);
    analytic.run(5);  // the lists built, the caches warm
    meshed.run(5);
    std::vector<double> a, m;
    for (long round = 0; round < o.rounds; ++round) {  // alternating: the host's speed wanders
      a.push_back(timed(analytic, o.steps) / double(o.steps));
      m.push_back(timed(meshed, o.steps) / double(o.steps));
    }
    auto row = [&](const char* name, const std::vector<double>& t, const granular::Simulation& sim,
                   double ratio) {
      const auto [lo, hi] = std::minmax_element(t.begin(), t.end());
      double sum = 0.0;
      for (double x : t) sum += x;
      const double mean = sum / double(t.size());
      std::printf("| %d | %s | %.2f (%.2f–%.2f) | %.0f | %llu | %s |\n", threads, name, 1e3 * mean,
                  1e3 * *lo, 1e3 * *hi, 1e9 * mean / double(n),
                  static_cast<unsigned long long>(sim.counters().wallContacts),
                  ratio > 0 ? (std::to_string(ratio).substr(0, 4)).c_str() : "");
      return mean;
    };
    double sa = 0.0, sm = 0.0;
    for (double x : a) sa += x;
    for (double x : m) sm += x;
    row("analytic", a, analytic, 0.0);
    row(("mesh, " + std::to_string(triangles) + " triangles").c_str(), m, meshed, sa / sm);
  }
  return 0;
}
