/// Timings of Simulation::step() on a dense random packing in a box under gravity.
///
/// Cases: 2000 and 100000 spheres of the paper's material (Material{} defaults, radii
/// 0.030–0.035 m, Δt = 1e-4 s), Gear5 and velocity Verlet, frictionless (μ = 0) and frictional
/// (μ = 0.3). Each case starts from a packing (denseRandomPacking, open-top box) that has fallen
/// for `settle` steps under gravity; building and settling are not timed, and the settled beds
/// are cached so that both integrators and every repetition start from the same state. Each
/// repetition times a fixed number of steps (2000 for n = 2000, 50 for n = 10⁵), three
/// repetitions, aggregates reported.
///
/// Counters:
///   particle_steps_per_s          particles × steps per second of wall time (the figure to quote)
///   contacts_per_particle         (2·particle contacts + wall contacts) / n, mean over the steps
///   neighbour_pairs_per_particle  candidate pairs in the neighbour list / n, mean over the steps
///
/// Run: build/release/bench/granular_bench [--quick] [--benchmark_filter=...]; see
/// bench/RESULTS.md. --quick: the 2000-sphere cases only, 20 timed steps, one repetition (a smoke
/// run of a few seconds, not a measurement). Exits 1 when a case failed (its error is in the
/// table).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstring>
#include <exception>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "benchmark_failures.hpp"
#include "granular/network_frequency.hpp"
#include "granular/network_spectrum.hpp"
#include "granular/packings.hpp"
#include "granular/scene.hpp"
#include "granular/simulation.hpp"

namespace {

using granular::Integrator;

constexpr double kRadiusMin = 0.030;  // the paper's radii [m]
constexpr double kRadiusMax = 0.035;
constexpr double kTimeStep = 1e-4;  // [s]
constexpr std::uint64_t kSeed = 20261123;

granular::SimulationConfig makeConfig(Integrator integrator, double friction) {
  granular::SimulationConfig config;
  config.material.friction = friction;
  config.integrator = integrator;
  config.timeStep = kTimeStep;
  return config;
}

struct Bed {
  granular::Particles particles;
  std::vector<granular::Wall> walls;
};

/// The packing after `settleSteps` steps under gravity (velocity Verlet), built once per
/// (n, settleSteps, friction).
const Bed& settledBed(std::size_t n, std::uint64_t settleSteps, double friction) {
  static std::map<std::tuple<std::size_t, std::uint64_t, double>, Bed> cache;
  const auto key = std::make_tuple(n, settleSteps, friction);
  if (auto it = cache.find(key); it != cache.end()) return it->second;

  granular::BoxSpec box;
  granular::Particles particles = granular::denseRandomPacking(
      n, kRadiusMin, kRadiusMax, granular::Material{}.density, kSeed, &box);
  granular::Simulation sim(std::move(particles), granular::buildWalls(box),
                           makeConfig(Integrator::VelocityVerlet, friction));
  sim.run(settleSteps);
  return cache.emplace(key, Bed{sim.particles(), sim.walls()}).first->second;
}

/// Times `step()`; state.range(0) = n, state.range(1) = settle steps.
void stepBenchmark(benchmark::State& state, Integrator integrator, double friction) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const auto settleSteps = static_cast<std::uint64_t>(state.range(1));
  try {
    const Bed& bed = settledBed(n, settleSteps, friction);
    granular::Simulation sim(bed.particles, bed.walls, makeConfig(integrator, friction));

    // The bed keeps moving while it is timed, so the contact counts are averaged over the timed
    // steps (reading two counters costs nothing next to a step).
    std::uint64_t contactEnds = 0, neighbourPairs = 0;
    for (auto _ : state) {
      sim.step();
      const granular::StepCounters& c = sim.counters();
      contactEnds += 2 * c.particleContacts + c.wallContacts;
      neighbourPairs += c.neighbourPairs;
    }

    const double count = static_cast<double>(n);
    const double steps = static_cast<double>(state.iterations());
    state.counters["particle_steps_per_s"] =
        benchmark::Counter(count * steps, benchmark::Counter::kIsRate);
    state.counters["contacts_per_particle"] = static_cast<double>(contactEnds) / (count * steps);
    state.counters["neighbour_pairs_per_particle"] =
        static_cast<double>(neighbourPairs) / (count * steps);
  } catch (const std::exception& e) {
    granular::bench::failCase(state, e);
  }
}

/// Times one look at the contact network of the settled bed, against a step: the bound of
/// the fixed step's checks (32 sweeps, granular/network_frequency.hpp), the Lanczos estimate
/// (granular/network_spectrum.hpp) from a cold start, or warm-started from the estimate 100
/// steps before (the steps untimed); state.range(0) = n, state.range(1) = settle steps.
enum class NetworkLook { Bound, Cold, Warm };
void networkBenchmark(benchmark::State& state, NetworkLook look) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const auto settleSteps = static_cast<std::uint64_t>(state.range(1));
  try {
    const Bed& bed = settledBed(n, settleSteps, 0.3);
    granular::Simulation sim(bed.particles, bed.walls, makeConfig(Integrator::VelocityVerlet, 0.3));
    granular::NetworkSpectrumStart start;
    if (look == NetworkLook::Warm) granular::networkSpectrumEstimate(sim, 0.0, &start);
    int products = 0;
    for (auto _ : state) {
      if (look == NetworkLook::Bound) {
        benchmark::DoNotOptimize(granular::networkFrequencyBound(sim).omegaMax);
        continue;
      }
      if (look == NetworkLook::Warm) {
        state.PauseTiming();
        sim.run(100);
        state.ResumeTiming();
      }
      const granular::NetworkSpectrum s =
          granular::networkSpectrumEstimate(sim, 0.0, look == NetworkLook::Warm ? &start : nullptr);
      benchmark::DoNotOptimize(s.omegaMax);
      products += s.products;
    }
    state.counters["products"] = double(products) / double(state.iterations());
  } catch (const std::exception& e) {
    granular::bench::failCase(state, e);
  }
}

/// Removes --quick from the arguments (Google Benchmark refuses flags it does not know); true if
/// it was there.
bool takeQuick(int& argc, char** argv) {
  bool quick = false;
  int kept = 1;
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--quick") == 0) {
      quick = true;
    } else {
      argv[kept++] = argv[k];
    }
  }
  argc = kept;
  return quick;
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = takeQuick(argc, argv);
  struct Case {
    std::int64_t n;            // particles
    std::int64_t settleSteps;  // untimed steps before timing
    std::int64_t steps;        // timed steps (fixed, so every run does the same work)
  };
  // settle 200 (0.02 s): the lattice has just started to fall, few contacts; settle 5000
  // (0.5 s): the 2000-sphere bed has landed (the paper's stage-2 load), the 10⁵ bed (3 m tall)
  // is landing from the bottom up.
  const std::vector<Case> cases =
      quick ? std::vector<Case>{{2000, 200, 20}, {2000, 5000, 20}}
            : std::vector<Case>{
                  {2000, 200, 2000}, {2000, 5000, 2000}, {100000, 200, 50}, {100000, 5000, 50}};
  const std::pair<Integrator, const char*> integrators[] = {
      {Integrator::Gear5, "Gear5"}, {Integrator::VelocityVerlet, "VelocityVerlet"}};
  const std::pair<double, const char*> frictions[] = {{0.0, "frictionless"}, {0.3, "frictional"}};

  for (const Case& c : cases) {
    for (const auto& [friction, frictionName] : frictions) {
      for (const auto& [integrator, integratorName] : integrators) {
        const std::string name = std::string("step/") + integratorName + "/" + frictionName;
        auto* b = benchmark::RegisterBenchmark(
            name.c_str(), [integrator = integrator, friction = friction](benchmark::State& s) {
              stepBenchmark(s, integrator, friction);
            });
        b->ArgNames({"n", "settle"})->Args({c.n, c.settleSteps});
        b->Iterations(c.steps)->Repetitions(quick ? 1 : 3)->ReportAggregatesOnly(!quick);
        b->Unit(benchmark::kMillisecond);
      }
    }
  }

  for (const auto& [look, lookName] :
       {std::pair{NetworkLook::Bound, "bound"}, std::pair{NetworkLook::Cold, "estimate"},
        std::pair{NetworkLook::Warm, "estimate-warm"}}) {
    const std::string name = std::string("network/") + lookName + "/frictional";
    auto* b = benchmark::RegisterBenchmark(
        name.c_str(), [look = look](benchmark::State& s) { networkBenchmark(s, look); });
    b->ArgNames({"n", "settle"})->Args({2000, 5000});
    b->Iterations(quick ? 2 : 50)->Repetitions(quick ? 1 : 3)->ReportAggregatesOnly(!quick);
    b->Unit(benchmark::kMillisecond);
  }

  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return granular::bench::anyCaseFailed() ? 1 : 0;
}
