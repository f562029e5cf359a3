/// granular_bench_gear_stability — the largest step at which each integrator keeps a settled,
/// damped bed's energy balance: the evidence for the core's step limits (kMaxStepFractionGear5,
/// kMaxStepFractionVerlet in contact_theory.hpp; bench/RESULTS.md, "Gear in a bed").
///
/// A 6×6×4 bed of spheres (R 0.030–0.035 m, the paper's material, μ = 0.3) falls into a box and
/// settles for 1.5 s with velocity Verlet at t_c/50; from that one state, each integrator then
/// holds it for 0.5 s at Δt = t_c/k. A stable scheme keeps the energy balance (stored +
/// dissipated − work in) to its truncation error; an unstable one pumps energy in. The table
/// gives the balance error over the hold divided by the bed's potential energy scale m g h.
///
/// Usage: granular_bench_gear_stability [--verlet-only] [--fractions K1,K2,...]
///   (all of it: a few seconds on one core). --fractions sets the k of Δt = t_c/k (default
///   10,15,20,25,30,40,50); --verlet-only skips Gear5, to probe Verlet's limit at large steps.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "granular/checkpoint.hpp"
#include "granular/engine_studies.hpp"
#include "granular/error.hpp"
#include "granular/simulation.hpp"
#include "physics_fixtures.hpp"  // the tests' falling-grid bed

using namespace granular;

namespace {

[[noreturn]] void usage(const char* why) {
  std::fprintf(
      stderr,
      "granular_bench_gear_stability: %s\n"
      "usage: granular_bench_gear_stability [--verlet-only] [--fractions K1,K2,...]\n"
      "  --fractions  the k of each step t_c/k, each k >= 1 (default 10,15,20,25,30,40,50)\n",
      why);
  std::exit(2);
}

std::vector<double> parseFractions(const std::string& text) {
  std::vector<double> ks;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double k = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !(k >= 1.0)) usage(("bad fraction '" + item + "'").c_str());
    ks.push_back(k);
  }
  if (ks.empty()) usage("--fractions needs at least one k");
  return ks;
}

}  // namespace

int main(int argc, char** argv) {
  bool verletOnly = false;
  std::vector<double> fractions{10.0, 15.0, 20.0, 25.0, 30.0, 40.0, 50.0};
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--verlet-only") == 0) {
      verletOnly = true;
    } else if (std::strcmp(argv[a], "--fractions") == 0 && a + 1 < argc) {
      fractions = parseFractions(argv[++a]);
    } else {
      usage(("unknown or incomplete option '" + std::string(argv[a]) + "'").c_str());
    }
  }
  const auto file = std::filesystem::temp_directory_path() / "granular_gear_stability.ckpt";
  std::printf("| law | γn [1/s] | integrator | Δt | energy error / (m g h) | verdict |\n");
  std::printf("|---|---:|---|---|---:|---|\n");
  for (NormalLaw law : {NormalLaw::Hooke, NormalLaw::Hertz}) {
    for (double damping : {20.0, 60.0, 200.0}) {
      SimulationConfig cfg;
      cfg.material.friction = 0.3;
      cfg.material.normalLaw = law;
      cfg.material.normalDamping = damping;
      cfg.integrator = Integrator::VelocityVerlet;
      cfg.timeStep = 1e-6;
      Simulation bed = testing::fallingGrid(6, 6, 4, cfg, 0.1);
      const double tc = bed.contactScale().duration;
      bed.setTimeStep(tc / 50);
      bed.run(std::uint64_t(1.5 / (tc / 50)));
      writeCheckpoint(bed, file, 0);
      double mass = 0;
      for (double m : bed.particles().mass) mass += m;
      const double scale = mass * 9.81 * 0.2;  // [J]; the bed is ~0.2 m high
      for (Integrator integrator : {Integrator::VelocityVerlet, Integrator::Gear5}) {
        if (verletOnly && integrator == Integrator::Gear5) continue;
        for (double k : fractions) {
          Simulation sim = readCheckpoint(file);
          // Past the core's limits on purpose: this is the measurement that sets them.
          studies::disableStepLimit(sim, true);
          sim.setIntegrator(integrator);
          sim.setTimeStep(tc / k);
          const bool refused = tc / k > maxStableStep(sim.contactScale(), integrator) * (1 + 1e-12);
          const double e0 = sim.energy().total();
          std::string verdict = "holds";
          double error = 0;
          try {
            sim.run(std::uint64_t(0.5 / (tc / k)));
            error = std::abs(sim.energy().total() - e0) / scale;
            if (error > 1e-3) verdict = "gains energy";
          } catch (const NumericalError&) {
            verdict = "blows up";
            error = INFINITY;
          }
          if (refused) verdict += " (refused by the core)";
          std::printf("| %s | %g | %s | t_c/%g | %.2e | %s |\n",
                      law == NormalLaw::Hooke ? "Hooke" : "Hertz", damping,
                      integrator == Integrator::Gear5 ? "Gear5" : "Verlet", k, error,
                      verdict.c_str());
          std::fflush(stdout);
        }
      }
    }
  }
  std::filesystem::remove(file);
}
