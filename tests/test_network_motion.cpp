/// The step control's scan (networkMotion, docs/physics.md §2.16) counts the listed pairs in
/// chunks of arrays (pair_motion.hpp): it must count what the walk over the contacts one at a
/// time counts, to the bit, in both vector builds, or an automatic run would choose other steps
/// than the check's own walk reads.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "granular/exact_sum.hpp"
#include "granular/simd_build.hpp"
#include "network_bound.hpp"
#include "physics_fixtures.hpp"
#include "simd_build_guard.hpp"
#include "simulation_state.hpp"

using namespace granular;
using granular::testing::fallingGrid;
using granular::testing::SimdBuildGuard;

namespace {

/// What the walk one contact at a time gives: NetworkFrequency's motion fields by their
/// definitions (network_frequency.hpp).
NetworkFrequency walked(const SimulationState& s, double lookahead) {
  NetworkFrequency out;
  ExactSum energy;
  visitNetworkContacts(s, lookahead, [&](const NetworkContact& n) {
    out.fastestApproach = std::max(out.fastestApproach, n.approach);
    (n.touching ? out.contacts : out.approaching) += 1;
    energy.add(0.5 * n.mass * n.relativeSpeed * n.relativeSpeed);
  });
  out.relativeKinetic = energy.value();
  return out;
}

}  // namespace

TEST(NetworkMotion, TheScansChunksCountWhatTheWalkOneContactAtATimeCounts) {
  SimdBuildGuard guard;
  std::vector<SimdBuild> builds{SimdBuild::Baseline};
  if (setSimdBuild(SimdBuild::Avx2)) builds.push_back(SimdBuild::Avx2);
  for (NormalLaw law : {NormalLaw::Hooke, NormalLaw::Hertz}) {
    SimulationConfig cfg;
    cfg.material.normalLaw = law;
    cfg.material.friction = 0.3;
    cfg.integrator = Integrator::VelocityVerlet;
    cfg.timeStep = 1e-4;
    cfg.threads = 1;
    // A grid thrown down at 1 m/s: pairs and the floor apart and closing, striking, and resting.
    Simulation sim = fallingGrid(5, 5, 4, cfg, 1.0);
    std::size_t touching = 0, approaching = 0;
    for (int stage = 0; stage < 6; ++stage) {
      sim.run(400);
      const SimulationState& s = SimulationAccess::state(sim);
      for (double lookahead : {0.0, 2e-3, 0.5}) {
        const NetworkFrequency expected = walked(s, lookahead);
        for (SimdBuild build : builds) {
          ASSERT_TRUE(setSimdBuild(build));
          const NetworkFrequency scanned = networkMotion(s, lookahead);
          SCOPED_TRACE(::testing::Message()
                       << "law " << int(law) << ", after " << sim.stepCount()
                       << " steps, lookahead " << lookahead << " s, build " << int(build));
          EXPECT_EQ(scanned.contacts, expected.contacts);
          EXPECT_EQ(scanned.approaching, expected.approaching);
          EXPECT_EQ(scanned.fastestApproach, expected.fastestApproach);
          EXPECT_EQ(scanned.relativeKinetic, expected.relativeKinetic);
        }
        touching += expected.contacts;
        approaching += expected.approaching;
      }
    }
    // The comparison saw both kinds of contact.
    EXPECT_GT(touching, 100u);
    EXPECT_GT(approaching, 10u);
  }
}

TEST(NetworkMotion, TheScanIsTheSameBitsOnOneTwoAndThreeThreads) {
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.integrator = Integrator::VelocityVerlet;
  cfg.timeStep = 1e-4;
  cfg.threads = 1;
  Simulation sim = fallingGrid(20, 20, 6, cfg, 1.0);
  sim.run(3000);
  const SimulationState& s = SimulationAccess::state(sim);
  // Enough pairs that the scan runs on the threads it is given (pair_motion.hpp).
  ASSERT_GT(s.neighbours.second.size(), 4096u);
  for (double lookahead : {0.0, 2e-3, 0.5}) {
    const NetworkFrequency expected = walked(s, lookahead);
    for (int threads : {1, 2, 3}) {
      sim.setThreads(threads);
      const NetworkFrequency scanned = networkMotion(s, lookahead);
      SCOPED_TRACE(::testing::Message()
                   << "lookahead " << lookahead << " s, " << threads << " threads");
      EXPECT_EQ(scanned.contacts, expected.contacts);
      EXPECT_EQ(scanned.approaching, expected.approaching);
      EXPECT_EQ(scanned.fastestApproach, expected.fastestApproach);
      EXPECT_EQ(scanned.relativeKinetic, expected.relativeKinetic);
    }
  }
}
