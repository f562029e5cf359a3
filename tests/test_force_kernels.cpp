/// The contact law's loops and the integrators' loops exist in two builds (baseline x86-64 and
/// AVX2, core/engine/src/force_pass.cpp and integrators.cpp) and the CPU picks one. They must give
/// the same bits: a run on one machine reproduces on another whichever build each has.
#include <gtest/gtest.h>

#include <vector>

#include "force_pass.hpp"
#include "physics_fixtures.hpp"

using namespace granular;
using granular::testing::fallingGrid;

namespace {

/// Restores the CPU's own choice when a test ends.
class KernelBuildGuard {
 public:
  KernelBuildGuard() : saved_(forceKernelBuild()) {}
  ~KernelBuildGuard() { setForceKernelBuild(saved_); }

 private:
  ForceKernelBuild saved_;
};

struct RunRecord {
  std::uint64_t hash = 0;
  EnergyBalance energy;
  std::vector<Vec3> contactForces;  ///< forEachContact's forces at the end (measuring pass)
  std::uint64_t contacts = 0;
};

RunRecord runWith(ForceKernelBuild build, const SimulationConfig& cfg) {
  EXPECT_TRUE(setForceKernelBuild(build));
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
  KernelBuildGuard guard;
  if (!setForceKernelBuild(ForceKernelBuild::Avx2)) {
    GTEST_SKIP() << "this CPU has no AVX2";
  }
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    for (double friction : {0.0, 0.3}) {
      for (NormalLaw law : {NormalLaw::Hooke, NormalLaw::Hertz}) {
        SimulationConfig cfg;
        cfg.integrator = integrator;
        cfg.material.friction = friction;
        cfg.material.normalLaw = law;
        cfg.timeStep = 1e-4;
        const RunRecord base = runWith(ForceKernelBuild::Baseline, cfg);
        const RunRecord wide = runWith(ForceKernelBuild::Avx2, cfg);
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
  KernelBuildGuard guard;
  EXPECT_TRUE(setForceKernelBuild(ForceKernelBuild::Baseline));  // every x86-64 CPU runs it
  EXPECT_EQ(forceKernelBuild(), ForceKernelBuild::Baseline);
}
