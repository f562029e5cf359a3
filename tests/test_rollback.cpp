/// The growth watch and the rollback (docs/physics.md §2.16): an automatic step from an
/// estimate of the network's highest frequency that is too low (studies::scaleSpectrumEstimate
/// poses one: the step then lies 1.4–1.7 × above the real edge) grows a mode. The next check
/// finds it in the energy ledger and takes the steps since the last check again at a shorter
/// step, so the run ends as a stable one would: the balance closed, the bed at rest, the last
/// step stable on the exact damped network. The same bits on 1, 2 and 3 threads (on ranks:
/// tests/ranks) and across a checkpoint; where the caller has seen the state since the last
/// check (a driver stepping one step a call, a setter's check between calls), the growth is kept
/// and counted, and the step shrinks all the same.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "granular/checkpoint.hpp"
#include "granular/engine_studies.hpp"
#include "network_matrices.hpp"
#include "physics_fixtures.hpp"
#include "temp_folder.hpp"

using namespace granular;
using granular::testing::gearStepRadius;
using granular::testing::largestEigenvalue;
using granular::testing::networkMatrix;
using granular::testing::verletStepRadius;

namespace {

double topOf(const Simulation& sim) {
  double top = 0.0;
  for (std::size_t i = 0; i < sim.particles().size(); ++i) {
    top = std::max(top, sim.particles().position[i].z() + sim.particles().radius[i]);
  }
  return top;
}

/// A lid pressing the bed by 20 % of its height at 0.05 m/s, then holding for 1 s: one call of
/// advanceTo each.
void press(Simulation& sim) {
  sim.addWall(Wall{"lid", Vec3(0, 0, topOf(sim)), Vec3(0, 0, -1)});
  const std::size_t lid = std::size_t(sim.findWall("lid"));
  const double speed = 0.05;
  sim.setWallVelocity(lid, Vec3(0, 0, -speed));
  sim.advanceTo(sim.time() + 0.2 * topOf(sim) / speed);
  sim.setWallVelocity(lid, Vec3::Zero());
  sim.advanceTo(sim.time() + 1.0);
}

class Rollback : public granular::testing::TempFolderTest {
 protected:
  Rollback() : TempFolderTest("granular_rollback") {}
};

}  // namespace

TEST_F(Rollback, AStepAboveTheEdgeFromAnEstimateTooLowIsUndoneAndTheRunEndsAsAStableOne) {
  Simulation sim = granular::testing::settledAutomaticBed(3, 3, 3, 1);
  ASSERT_TRUE(sim.stepCheck().estimated);
  // The estimate at 0.6 of itself: the steps it allows are 1.67 × the estimate's, above the
  // real edge (the estimate's own step is within 6 % of it, bench/RESULTS.md).
  studies::scaleSpectrumEstimate(sim, 0.6);
  const double balanceBefore = sim.energy().total();
  press(sim);
  const EnergyBalance e = sim.energy();
  EXPECT_GE(sim.counters().rollbacks, 1u);
  EXPECT_EQ(sim.counters().keptGrowths, 0u);  // every growth inside one call: all undone
  ASSERT_GT(e.wallWork, 0.0);
  // What the growing modes created is gone with them: the balance closes as the stable run's
  // does (tests/test_network_frequency.cpp, the lid at the estimate's own step).
  EXPECT_LT(std::abs(e.total() - balanceBefore), 0.01 * e.wallWork);
  EXPECT_LT(e.kinetic(), 1e-3 * e.wallWork);
  // The step it ends at is stable on the whole damped linearised network.
  const Eigen::MatrixXd a = networkMatrix(sim, false), d = networkMatrix(sim, true);
  EXPECT_LE(verletStepRadius(a, d, sim.stepCheck().chosenStep, 0.5), 1.0 + 1e-6);
  // The state kept is counted in the memory held: about the arrays again.
  const MemoryUse memory = sim.memoryUse();
  EXPECT_GT(memory.rollback, (memory.total() - memory.rollback) / 2);
  std::printf("%llu rollbacks; balance moved %.3g J of %.3g J work; last step %.4g s\n",
              static_cast<unsigned long long>(sim.counters().rollbacks), e.total() - balanceBefore,
              e.wallWork, sim.stepCheck().chosenStep);
}

TEST_F(Rollback, AGear5StepAboveTheEdgeIsUndoneAlikeAndTheSameBitsOnTwoThreads) {
  // Gear5's automatic step comes from the estimate too, at its own interval: the same bed at
  // rest, the estimate at 0.6 of itself, one call of 1 s: a mode grows from the round-off,
  // the checks find it and undo it until the step is stable, on one and two threads alike.
  Simulation one = granular::testing::settledAutomaticBed(3, 3, 3, 1, Integrator::Gear5);
  Simulation two = granular::testing::settledAutomaticBed(3, 3, 3, 2, Integrator::Gear5);
  ASSERT_TRUE(one.stepCheck().estimated);
  const double balanceBefore = one.energy().total();
  for (Simulation* sim : {&one, &two}) {
    studies::scaleSpectrumEstimate(*sim, 0.6);
    sim->advanceTo(sim->time() + 1.0);
  }
  const EnergyBalance e = one.energy();
  EXPECT_GE(one.counters().rollbacks, 1u);
  EXPECT_EQ(one.counters().keptGrowths, 0u);
  const double weight = std::abs(e.gravityWork);
  EXPECT_LT(std::abs(e.total() - balanceBefore), 1e-5 * weight);
  EXPECT_LT(e.kinetic(), 1e-5 * weight);
  const Eigen::MatrixXd a = networkMatrix(one, false), d = networkMatrix(one, true);
  EXPECT_LE(gearStepRadius(a, d, one.stepCheck().chosenStep), 1.0 + 1e-6);
  EXPECT_EQ(two.stateHash(), one.stateHash());
  EXPECT_EQ(two.counters().rollbacks, one.counters().rollbacks);
  EXPECT_EQ(two.stepCount(), one.stepCount());
  std::printf(
      "gear5: %llu rollbacks; balance moved %.3g J (gravity's work %.3g J); last step "
      "%.4g s\n",
      static_cast<unsigned long long>(one.counters().rollbacks), e.total() - balanceBefore, weight,
      one.stepCheck().chosenStep);
}

TEST_F(Rollback, IsTheSameBitsOnOneTwoAndThreeThreadsAndAcrossACheckpoint) {
  Simulation one = granular::testing::settledAutomaticBed(6, 6, 5, 1);
  studies::scaleSpectrumEstimate(one, 0.6);
  press(one);
  ASSERT_GE(one.counters().rollbacks, 1u);
  for (int threads : {2, 3}) {
    SCOPED_TRACE(::testing::Message() << threads << " threads");
    Simulation many = granular::testing::settledAutomaticBed(6, 6, 5, threads);
    studies::scaleSpectrumEstimate(many, 0.6);
    press(many);
    EXPECT_EQ(many.stateHash(), one.stateHash());
    EXPECT_EQ(many.counters().rollbacks, one.counters().rollbacks);
    EXPECT_EQ(many.stepCount(), one.stepCount());
    EXPECT_EQ(many.time(), one.time());
    EXPECT_EQ(many.energy().total(), one.energy().total());
  }
  // A checkpoint after the rollbacks: the restored run goes on as the one that wrote it
  // (the raised estimate and the counts travel with it; the study's factor is set again).
  const std::filesystem::path file = dir_ / "pressed.ckpt";
  writeCheckpoint(one, file, 0);
  Simulation resumed = readCheckpoint(file);
  studies::scaleSpectrumEstimate(resumed, 0.6);
  EXPECT_EQ(resumed.counters().rollbacks, one.counters().rollbacks);
  const std::size_t lid = std::size_t(one.findWall("lid"));
  for (Simulation* sim : {&one, &resumed}) {
    sim->setWallVelocity(lid, Vec3(0, 0, -0.05));
    sim->advanceTo(sim->time() + 0.5);
  }
  EXPECT_EQ(resumed.stateHash(), one.stateHash());
  EXPECT_EQ(resumed.counters().rollbacks, one.counters().rollbacks);
  EXPECT_EQ(resumed.counters().keptGrowths, one.counters().keptGrowths);
}

TEST_F(Rollback, AGrowthTheCallerHasSeenIsKeptCountedAndTheStepShrinks) {
  // Stepping one step a call, the caller sees every state: a check that finds a mode grown since
  // the last check cannot undo it (the point lies before this call). It counts it, raises the
  // estimate, and the step shrinks; the growth stays in the ledger.
  Simulation sim = granular::testing::settledAutomaticBed(3, 3, 3, 1);
  studies::scaleSpectrumEstimate(sim, 0.6);
  sim.addWall(Wall{"lid", Vec3(0, 0, topOf(sim)), Vec3(0, 0, -1)});
  sim.setWallVelocity(std::size_t(sim.findWall("lid")), Vec3(0, 0, -0.05));
  const double first = sim.stepCheck().chosenStep;
  while (sim.counters().keptGrowths == 0 && sim.time() < 5.0) sim.step();
  ASSERT_EQ(sim.counters().keptGrowths, 1u);
  EXPECT_EQ(sim.counters().rollbacks, 0u);
  EXPECT_LE(sim.stepCheck().chosenStep, 0.8 * first * (1.0 + 1e-9));
}

TEST_F(Rollback, ASetterBetweenCallsNeverReturnsToAStateTheCallerHasSeen) {
  // Calls of 5 steps, and between each two a setter whose check re-chooses the step (the lid's
  // speed nudged): a growing mode that such a check finds is kept, never undone, so the steps
  // and the clock the caller has seen stand.
  Simulation sim = granular::testing::settledAutomaticBed(3, 3, 3, 1);
  studies::scaleSpectrumEstimate(sim, 0.6);
  sim.addWall(Wall{"lid", Vec3(0, 0, topOf(sim)), Vec3(0, 0, -1)});
  const std::size_t lid = std::size_t(sim.findWall("lid"));
  std::uint64_t keptBySetters = 0;
  for (int k = 0; k < 400; ++k) {
    sim.run(5);
    const std::uint64_t steps = sim.stepCount(), kept = sim.counters().keptGrowths;
    const double time = sim.time();
    sim.setWallVelocity(lid, Vec3(0, 0, k % 2 == 0 ? -0.05 : -0.051));
    ASSERT_EQ(sim.stepCount(), steps) << "a setter took the run back, call " << k;
    ASSERT_EQ(sim.time(), time);
    keptBySetters += sim.counters().keptGrowths - kept;
  }
  EXPECT_GE(keptBySetters, 1u) << "no setter's check found a growing mode";
}
