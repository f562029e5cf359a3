/// granular_bench_scale: time per step and memory per particle from 10³ to 10⁶ particles, on 1
/// and 2 threads (issue 6, "Scale"). A plain program rather than a Google Benchmark, because
/// the memory figure needs the whole process to itself: it prints a markdown table row per case.
///
/// The bed: a dense random packing (denseRandomPacking, seed 20261123) of the paper's material
/// and radii (0.030–0.035 m) with a square footprint and `--layers` lattice layers (default 12,
/// a bed ≈ 0.55 m deep, like the lower half of the paper's), in a box with side walls and a
/// floor, settled under gravity for `--settle` steps (untimed, velocity Verlet at the same step,
/// heavier normal damping: scale_bed_settling.hpp) so that every particle carries its weight
/// through ≈ 5-6 contacts. A fixed
/// depth keeps the load per particle the same at every n, so the cost per particle-step should be
/// the same too: linear scaling. The timed steps then run with the integrator and friction asked
/// for, 1 and 2 threads, from the same settled state.
///
/// Memory: VmHWM (the process's peak resident set, from /proc/self/status, reset before each
/// row) minus the resident set before the packing was built, divided by n: everything the timed
/// run needed per particle, transient buffers of neighbour-list rebuilds included; then the same
/// after one more (untimed) step that rebuilds the list, the peak of a run that holds a rebuild.
/// Arrays of 1 MiB and more are mapped on their own (mallopt in main), so that an array freed
/// by a rebuild leaves the resident set at once instead of staying in glibc's heap. Two
/// threads need a little more than one: the pairs straddling them keep a copy of their spring
/// for the second thread, and the force pass's plan lists them (core/engine/src/force_pass.cpp).
///
/// Usage: granular_bench_scale [--n 1000,10000,...] [--settle S] [--steps T] [--layers L]
///                             [--friction MU] [--integrator gear5|verlet]
///                             [--shuffle | --cell-order]
/// --shuffle puts the particles in a random order (seeded) instead of the packing's layer by
/// layer order, to measure what a cache-unfriendly order costs; --cell-order puts them in
/// granular::spatialOrder's Morton cell order (0.07 m cells, a diameter).
/// One process per size is best for the memory figure (the peak is per process):
///   for n in 1000 10000 100000 1000000; do granular_bench_scale --n $n; done
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "granular/engine_studies.hpp"
#include "granular/packings.hpp"
#include "granular/scene.hpp"
#include "granular/simulation.hpp"
#include "granular/spatial_order.hpp"
#include "proc_status.hpp"
#include "scale_bed_settling.hpp"

namespace {

constexpr double kRadiusMin = 0.030;  // the paper's radii [m]
constexpr double kRadiusMax = 0.035;
constexpr double kTimeStep = 1e-4;  // [s], contact duration / 87 for the paper's material
constexpr std::uint64_t kSeed = 20261123;

using granular::bench::statusBytes;

struct Options {
  std::vector<long> sizes = {1000, 10000, 100000};
  long settle = 1500;
  long steps = 0;  // 0: about 2·10⁷ particle-steps per case, at least 20 steps
  long layers = 12;
  double gap = 0.02;  // lattice gap of the packing (PackingLayout::gap)
  double friction = 0.3;
  granular::Integrator integrator = granular::Integrator::Gear5;
  bool shuffle = false;    // random particle order instead of the packing's layer order
  bool cellOrder = false;  // Morton cell order (granular::spatialOrder) instead
};

[[noreturn]] void usage(const std::string& what) {
  std::cerr << "granular_bench_scale: " << what
            << "\nusage: granular_bench_scale [--n N1,N2,...] [--settle S] [--steps T] "
               "[--layers L] [--gap G] [--friction MU] [--integrator gear5|verlet] [--shuffle | "
               "--cell-order]\n";
  std::exit(2);
}

long positiveInteger(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (end == text.c_str() || *end != '\0' || v < 1) {
    usage(option + " = '" + text + "': expected an integer >= 1");
  }
  return v;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--shuffle") {
      o.shuffle = true;
      continue;
    }
    if (arg == "--cell-order") {
      o.cellOrder = true;
      continue;
    }
    if (k + 1 >= argc) usage("missing value after " + arg);
    const std::string value = argv[++k];
    if (arg == "--n") {
      o.sizes.clear();
      std::istringstream list(value);
      for (std::string item; std::getline(list, item, ',');) {
        o.sizes.push_back(positiveInteger("--n", item));
      }
    } else if (arg == "--settle") {
      o.settle = positiveInteger(arg, value);
    } else if (arg == "--steps") {
      o.steps = positiveInteger(arg, value);
    } else if (arg == "--layers") {
      o.layers = positiveInteger(arg, value);
    } else if (arg == "--gap") {
      o.gap = std::strtod(value.c_str(), nullptr);
      if (!(o.gap >= 0.0 && o.gap <= 1.0)) usage("--gap must be in [0, 1]");
    } else if (arg == "--friction") {
      o.friction = std::strtod(value.c_str(), nullptr);
      if (!(o.friction >= 0.0 && o.friction <= 10.0)) usage("--friction must be in [0, 10]");
    } else if (arg == "--integrator") {
      if (value == "gear5") {
        o.integrator = granular::Integrator::Gear5;
      } else if (value == "verlet") {
        o.integrator = granular::Integrator::VelocityVerlet;
      } else {
        usage("--integrator = '" + value + "': expected gear5 or verlet");
      }
    } else {
      usage("unknown option " + arg);
    }
  }
  return o;
}

/// A seeded Fisher-Yates permutation of the particles (raw 64-bit draws, so it is the same
/// everywhere).
void shuffleParticles(granular::Particles& p) {
  std::mt19937_64 rng(kSeed);
  for (std::size_t i = p.size(); i > 1; --i) {
    const std::size_t k = static_cast<std::size_t>(rng() % i);
    std::swap(p.position[i - 1], p.position[k]);
    std::swap(p.velocity[i - 1], p.velocity[k]);
    std::swap(p.angularVelocity[i - 1], p.angularVelocity[k]);
    std::swap(p.radius[i - 1], p.radius[k]);
    std::swap(p.mass[i - 1], p.mass[k]);
  }
}

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

void runCase(long n, const Options& o) {
  const double baseline = statusBytes("VmRSS");
  // A square footprint with `layers` lattice layers: denseRandomPacking puts ≈ √(2n/L) sites
  // along x and y when the aspect's z is 2n/(2n/L)^{3/2}.
  granular::PackingLayout layout;
  layout.gap = o.gap;
  const double perSide = std::sqrt(2.0 * static_cast<double>(n) / static_cast<double>(o.layers));
  layout.aspect = granular::Vec3(1.0, 1.0, 2.0 * static_cast<double>(n) / std::pow(perSide, 3));
  granular::BoxSpec box;
  granular::Particles particles =
      granular::denseRandomPacking(static_cast<std::size_t>(n), kRadiusMin, kRadiusMax,
                                   granular::Material{}.density, kSeed, &box, layout);

  if (o.shuffle) shuffleParticles(particles);
  if (o.cellOrder) {
    particles = granular::reordered(particles, granular::spatialOrder(particles.position, 0.07));
  }

  granular::SimulationConfig config;
  config.material.friction = o.friction;
  config.integrator = o.integrator;
  config.timeStep = kTimeStep;
  config.threads = 2;
  // The bed settles as settlingConfig says (heavier damping, velocity Verlet); the timed
  // simulation then starts from the settled particles at rest with the paper's material and the
  // integrator asked for. The settling simulation is gone before the timed one is built, so the
  // peak memory is one simulation's (plus one copy of the particles' 88 bytes).
  const auto settleStart = std::chrono::steady_clock::now();
  {
    granular::Simulation settle(std::move(particles), granular::buildWalls(box),
                                granular::bench::settlingConfig(config));
    settle.run(static_cast<std::uint64_t>(o.settle));
    std::fprintf(stderr, "n = %ld: settled %ld steps, kinetic energy %.3g J per particle\n", n,
                 o.settle, settle.kineticEnergy() / static_cast<double>(n));
    particles = settle.particles();
  }
  std::fill(particles.velocity.begin(), particles.velocity.end(), granular::Vec3::Zero());
  std::fill(particles.angularVelocity.begin(), particles.angularVelocity.end(),
            granular::Vec3::Zero());
  const double settleSeconds = seconds(settleStart);
  config.threads = 1;  // the timed runs set their count; built on one, nothing is allocated
                       // for two threads before the 2-thread row
  granular::Simulation sim(std::move(particles), granular::buildWalls(box), config);
  const long steps =
      o.steps > 0 ? o.steps : std::max(20L, static_cast<long>(2e7 / static_cast<double>(n)));
  for (int threads : {1, 2}) {
    // The peak so far is the settling run's or the last row's: start the count afresh (Linux:
    // "5" to clear_refs resets VmHWM to the current set), so that each row shows what a run on
    // its thread count needs.
    malloc_trim(0);  // hand the freed heap back first (glibc keeps it otherwise)
    std::ofstream("/proc/self/clear_refs") << "5";
    sim.setThreads(threads);
    sim.run(2);  // warm the caches and the thread pool
    const std::uint64_t rebuildsBefore = sim.counters().rebuilds;
    double contacts = 0;
    const auto start = std::chrono::steady_clock::now();
    // In runs of up to 10 steps, as a stage runs the steps nobody observes (Simulation::run,
    // whose steps predict the next in their corrector's loop); contacts counted at each run's end.
    for (long k = 0; k < steps; k += 10) {
      const long batch = std::min(10L, steps - k);
      sim.run(static_cast<std::uint64_t>(batch));
      contacts +=
          static_cast<double>(batch) * (2.0 * static_cast<double>(sim.counters().particleContacts) +
                                        static_cast<double>(sim.counters().wallContacts));
    }
    const double wall = seconds(start);
    const double particleSteps = static_cast<double>(n) * static_cast<double>(steps);
    const double peak = statusBytes("VmHWM");
    const std::uint64_t rebuilds = sim.counters().rebuilds - rebuildsBefore;
    // One more step, untimed, that rebuilds the neighbour list: the timed steps may hold no
    // rebuild (at 10⁶ a rebuild comes every few hundred steps), yet the run's peak is there.
    granular::studies::setRebuildEveryStep(sim, true);
    sim.step();
    granular::studies::setRebuildEveryStep(sim, false);
    const double rebuildPeak = statusBytes("VmHWM");
    {
      // Where the bytes are, from the arrays' capacities (stderr, beside the table).
      const granular::MemoryUse m = sim.memoryUse();
      const double per = 1.0 / static_cast<double>(n);
      std::fprintf(stderr,
                   "n = %ld, %d thread(s): arrays %.0f B/particle = particles %.0f + integrator "
                   "%.0f + "
                   "neighbour list %.0f + history %.0f + force plan %.0f + force scratch "
                   "%.0f; neighbour pairs %.2f/particle\n",
                   n, threads, per * static_cast<double>(m.total()),
                   per * static_cast<double>(m.particles), per * static_cast<double>(m.integrator),
                   per * static_cast<double>(m.neighbours), per * static_cast<double>(m.history),
                   per * static_cast<double>(m.forcePlan), per * static_cast<double>(m.scratch),
                   per * static_cast<double>(sim.counters().neighbourPairs));
    }
    std::printf(
        "| %ld%s | %d | %s | %.2g | %.3f | %.3g M | %.1f | %.2f | %lu | %.0f | %.0f | %.0f s |\n",
        n, o.shuffle ? " (shuffled)" : (o.cellOrder ? " (cell order)" : ""), threads,
        o.integrator == granular::Integrator::Gear5 ? "Gear5" : "Verlet", o.friction,
        1e3 * wall / static_cast<double>(steps), particleSteps / wall / 1e6,
        1e9 * wall / particleSteps, contacts / particleSteps, static_cast<unsigned long>(rebuilds),
        (peak - baseline) / static_cast<double>(n),
        (rebuildPeak - baseline) / static_cast<double>(n), settleSeconds);
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  // Arrays of a megabyte and more get pages of their own, returned when freed: glibc would
  // otherwise raise its threshold to the size of the first such array freed and keep later
  // ones in its heap, so the resident set would hold every array a rebuild ever freed, and
  // the peak would measure the allocator's retention rather than what the run needs.
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  std::printf(
      "| n | threads | integrator | μ | ms / step | particle-steps / s | ns / particle-step | "
      "contacts / particle | rebuilds | peak bytes / particle | peak with a rebuild | "
      "settle (untimed) |\n"
      "|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (long n : o.sizes) {
    try {
      runCase(n, o);
    } catch (const std::exception& e) {
      std::cerr << "granular_bench_scale: n = " << n << ": " << e.what() << "\n";
      return 1;
    }
  }
  return 0;
}
