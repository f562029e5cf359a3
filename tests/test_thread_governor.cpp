/// The thread governor (engine/src/thread_governor.hpp): between all threads and one, the faster
/// by timing; and the run's bits whatever it chooses, when.
#include <gtest/gtest.h>

#include <omp.h>

#include "granular/simulation.hpp"
#include "physics_fixtures.hpp"
#include "simulation_state.hpp"
#include "thread_governor.hpp"

using namespace granular;

namespace {

/// Feeds `steps` steps to the governor, each taking `all` seconds with every thread and `one`
/// with one thread; the count it steps with at the end.
int feed(ThreadGovernor& g, std::uint64_t steps, double all, double one) {
  for (std::uint64_t k = 0; k < steps; ++k) g.stepTook(g.threads() == 0 ? all : one);
  return g.threads();
}

TEST(ThreadGovernor, KeepsAllThreadsOnAQuietMachine) {
  ThreadGovernor g;
  // Two threads at 1.0, one at 1.8: every trial of one thread loses, and the trials take a
  // small share of the steps (15 in about 1100: one trial's 27 s of steps is 1/40 of the time).
  std::uint64_t atOne = 0;
  for (int k = 0; k < 100000; ++k) {
    atOne += g.threads() == 1;
    g.stepTook(g.threads() == 0 ? 1.0 : 1.8);
  }
  EXPECT_EQ(g.threads(), 0);
  EXPECT_GT(atOne, 0u);                  // it does try
  EXPECT_LT(double(atOne), 0.02 * 1e5);  // at 1.4 % of the steps
}

TEST(ThreadGovernor, TakesOneThreadBesideABusyProcessAndAllAgainWhenItEnds) {
  ThreadGovernor g;
  // Spinning threads beside a busy process: two threads at 6.0, one at 1.9. The first trial
  // comes after two windows.
  EXPECT_EQ(feed(g, 3 * ThreadGovernor::kWindow, 6.0, 1.9), 1);
  EXPECT_EQ(feed(g, 20000, 6.0, 1.9), 1);  // its trials of all lose
  // The other process ends: all threads at 1.0 win the next trial, within a few thousand steps
  // (the last trial, 15 steps at 6.0, set the time until the next: 40 × 90 s, 2000 steps at 1.8).
  EXPECT_EQ(feed(g, 5000, 1.0, 1.8), 0);
}

TEST(ThreadGovernor, AMarginalWinIsNoReasonToSwitch) {
  ThreadGovernor g;
  EXPECT_EQ(feed(g, 20000, 1.0, 0.95), 0);  // 5 % faster: noise
  EXPECT_EQ(feed(g, 5000, 1.0, 0.8), 1);    // 20 % faster: taken
}

TEST(ThreadGovernor, ASlowStepInAWindowDoesNotDecide) {
  // A neighbour-list rebuild or a step check makes one step several times slower now and then:
  // the slowest step of a window does not count. One thread at 0.8 but for one step at 10.0 in
  // each of its windows still wins against all threads at 1.0.
  ThreadGovernor g;
  std::size_t trialStep = 0;
  for (std::uint64_t k = 0; k < 3 * ThreadGovernor::kWindow; ++k) {
    g.stepTook(g.threads() == 0 ? 1.0 : (trialStep++ == 3 ? 10.0 : 0.8));
  }
  EXPECT_EQ(g.threads(), 1);
}

TEST(ThreadGovernor, AHeavyTailOfWaitsCountsAgainstACount) {
  // Beside a busy process most steps of two threads are as quick as ever, but one in three
  // waits a time slice for its core: their mean, not their median, is the cost.
  ThreadGovernor g;
  std::size_t step = 0;
  for (std::uint64_t k = 0; k < 3 * ThreadGovernor::kWindow; ++k) {
    g.stepTook(g.threads() == 0 ? (step++ % 3 == 0 ? 8.0 : 1.0) : 1.8);
  }
  EXPECT_EQ(g.threads(), 1);
}

TEST(ThreadGovernor, SwitchingCountsMidRunGivesTheSameBits) {
  if (omp_get_max_threads() < 2) GTEST_SKIP() << "one thread only";
  // A frictional bed falling and settling (rebuilds, springs), stepped at one thread, and at a
  // count switched between all and one every few steps, in and out of predicted-ahead runs.
  auto bed = [](int threads) {
    SimulationConfig cfg;
    cfg.material.friction = 0.3;
    cfg.timeStep = 1.5e-4;
    cfg.threads = threads;
    return granular::testing::fallingGrid(6, 6, 4, cfg, 0.3);
  };
  Simulation fixed = bed(1);
  Simulation switched = bed(0);
  for (int block = 0; block < 40; ++block) {
    auto& state = const_cast<SimulationState&>(SimulationAccess::state(switched));
    state.governor.choose(block % 3 == 0 ? 1 : 0);
    fixed.run(7);
    switched.run(7);
    switched.step();
    fixed.step();
  }
  EXPECT_EQ(switched.stateHash(), fixed.stateHash());
  EXPECT_EQ(switched.energy().total(), fixed.energy().total());
}

}  // namespace
