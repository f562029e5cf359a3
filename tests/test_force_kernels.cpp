/// The contact law's loops, the integrators' loops and the exact sums' exist in two builds
/// (baseline x86-64 and AVX2, granular/simd_build.hpp) and the CPU picks one. They must give
/// the same bits: a run on one machine reproduces on another whichever build each has.
#include <gtest/gtest.h>

#include <vector>

#include "force_pass.hpp"
#include "granular/simd_build.hpp"
#include "physics_fixtures.hpp"
#include "simd_build_guard.hpp"

using namespace granular;
using granular::testing::fallingGrid;
using granular::testing::SimdBuildGuard;

namespace {

struct RunRecord {
  std::uint64_t hash = 0;
  EnergyBalance energy;
  std::vector<Vec3> contactForces;  ///< forEachContact's forces at the end (measuring pass)
  std::uint64_t contacts = 0;
};

RunRecord runWith(SimdBuild build, const SimulationConfig& cfg) {
  EXPECT_TRUE(setSimdBuild(build));
  Simulation sim = fallingGrid(4, 4, 4, cfg, 0.5, 5);
  sim.run(2500);
  RunRecord r;
  r.hash = sim.stateHash();
  r.energy = sim.energy();
  sim.forEachContact([&](const ContactView& c) { r.contactForces.push_back(c.force); });
  r.contacts = sim.counters().particleContacts + sim.counters().wallContacts;
  return r;
}

}  // namespace

TEST(ForceKernels, BaselineAndAvx2BuildsGiveTheSameBits) {
  SimdBuildGuard guard;
  if (!setSimdBuild(SimdBuild::Avx2)) {
    GTEST_SKIP() << "no AVX2 build here (a CPU without AVX2, or a sanitizer build)";
  }
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    for (double friction : {0.0, 0.3}) {
      for (NormalLaw law : {NormalLaw::Hooke, NormalLaw::Hertz}) {
        SimulationConfig cfg;
        cfg.integrator = integrator;
        cfg.material.friction = friction;
        cfg.material.normalLaw = law;
        cfg.timeStep = 1e-4;
        cfg.exactSums = law == NormalLaw::Hertz;  // the exact sums' loops follow the switch too
        const RunRecord base = runWith(SimdBuild::Baseline, cfg);
        const RunRecord wide = runWith(SimdBuild::Avx2, cfg);
        const std::string what = std::string(integrator == Integrator::Gear5 ? "gear5" : "verlet") +
                                 ", mu " + std::to_string(friction) +
                                 (law == NormalLaw::Hertz ? ", Hertz" : ", Hooke");
        EXPECT_GT(base.contacts, 20u) << what;  // the grid has landed: contacts in use
        EXPECT_EQ(base.hash, wide.hash) << what;
        EXPECT_EQ(base.energy.of("dissipated_normal_J"), wide.energy.of("dissipated_normal_J"))
            << what;
        EXPECT_EQ(base.energy.of("dissipated_friction_J"), wide.energy.of("dissipated_friction_J"))
            << what;
        EXPECT_EQ(base.energy.of("elastic_tangential_J"), wide.energy.of("elastic_tangential_J"))
            << what;
        ASSERT_EQ(base.contactForces.size(), wide.contactForces.size()) << what;
        for (std::size_t k = 0; k < base.contactForces.size(); ++k) {
          ASSERT_EQ(base.contactForces[k], wide.contactForces[k]) << what << ", contact " << k;
        }
        if (friction > 0.0) {
          EXPECT_GT(base.energy.of("dissipated_friction_J"), 0.0) << what;  // some contacts slid
        }
      }
    }
  }
}

TEST(ForceKernels, TheCpusChoiceIsReported) {
  SimdBuildGuard guard;
  EXPECT_TRUE(setSimdBuild(SimdBuild::Baseline));  // every x86-64 CPU runs it
  EXPECT_EQ(simdBuild(), SimdBuild::Baseline);
}
