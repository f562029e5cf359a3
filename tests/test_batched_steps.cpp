/// Simulation::run(k) lets each step but the last predict the next one inside its corrector's
/// loop (core/engine/src/simulation.cpp, `advance`), and runStage runs the steps nobody observes as
/// such batches. These tests check that nothing of that shows: the same bits as one step() at a
/// time, the same observations, and a broken state still caught within the step that broke it.
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "granular/error.hpp"
#include "granular/packings.hpp"
#include "granular/simulation.hpp"
#include "granular/stage.hpp"

namespace granular {
namespace {

/// 400 spheres packed at rest 1.3 mm apart that fall into contact under gravity: contacts form
/// and the neighbour list is rebuilt within the first few hundred steps.
Simulation landingBed(Integrator integrator, int threads, double dt = 1.5e-4) {
  SimulationConfig cfg;
  cfg.integrator = integrator;
  cfg.timeStep = dt;
  cfg.material.friction = 0.4;
  cfg.threads = threads;
  BoxSpec box;
  Particles p = denseRandomPacking(400, 0.030, 0.035, cfg.material.density, 5, &box);
  return Simulation(std::move(p), buildWalls(box), cfg);
}

struct Observed {
  std::uint64_t hash;
  double dissipated, wallReaction;
  std::uint64_t rebuilds;
  std::size_t contacts;
};

Observed observe(const Simulation& sim) {
  double reaction = 0.0;
  for (const Wall& w : sim.walls()) reaction += w.reaction.norm();
  return {sim.stateHash(),
          sim.energy().of("dissipated_normal_J") + sim.energy().of("dissipated_tangential_J"),
          reaction, sim.counters().rebuilds, sim.counters().particleContacts};
}

void expectSame(const Observed& a, const Observed& b, const std::string& what) {
  EXPECT_EQ(a.hash, b.hash) << what;
  EXPECT_EQ(a.dissipated, b.dissipated) << what;  // exact: the same bits
  EXPECT_EQ(a.wallReaction, b.wallReaction) << what;
  EXPECT_EQ(a.rebuilds, b.rebuilds) << what;
}

TEST(BatchedSteps, RunGivesTheBitsOfOneStepAtATime) {
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    for (int threads : {1, 2}) {
      const std::string what = std::string(integrator == Integrator::Gear5 ? "gear5" : "verlet") +
                               ", " + std::to_string(threads) + " thread(s)";
      Simulation batched = landingBed(integrator, threads);
      Simulation single = landingBed(integrator, threads);
      for (std::uint64_t batch : {1u, 2u, 37u, 150u, 111u, 500u, 299u}) {
        batched.run(batch);
        for (std::uint64_t k = 0; k < batch; ++k) single.step();
        expectSame(observe(batched), observe(single),
                   what + ", after a batch of " + std::to_string(batch));
      }
      const Observed end = observe(batched);
      EXPECT_GE(end.rebuilds, 3u) << what << ": the lists should be rebuilt inside batches";
      EXPECT_GT(end.contacts, 200u) << what << ": the bed should have landed";
    }
  }
}

TEST(BatchedSteps, ABrokenStateIsCaughtInTheStepThatBrokeIt) {
  // run() checks what each step writes, the prediction it makes for the next step included, as
  // step() does: a NaN put in between two runs is reported by the first step of the next.
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    for (int threads : {1, 2}) {
      for (bool inPosition : {false, true}) {
        Simulation sim = landingBed(integrator, threads);
        sim.run(50);
        Particles& p = const_cast<Particles&>(sim.particles());
        (inPosition ? p.position : p.velocity)[7].z() = std::numeric_limits<double>::quiet_NaN();
        try {
          sim.run(10);
          ADD_FAILURE() << "a broken state stepped on silently";
        } catch (const NumericalError& e) {
          const std::string msg = e.what();
          EXPECT_NE(msg.find("step 51 "), std::string::npos) << msg;
          EXPECT_NE(msg.find("particle 7: "), std::string::npos) << msg;
        }
      }
    }
  }
}

TEST(BatchedSteps, AStageObservesTheSameStatesWhetherOrNotItsStepsAreBatched) {
  // Samples every 7 steps' worth of time and a checkpoint moment every 25 steps: between them
  // runStage batches the steps. A progress callback after every step forces one step at a time.
  StageSpec stage;
  stage.name = "landing";
  stage.end.maxTime = 300 * 1.5e-4;
  OutputSpec output;
  output.interval = 7 * 1.5e-4;
  auto record = [&](bool everyStep) {
    Simulation sim = landingBed(Integrator::Gear5, 2);
    std::vector<std::uint64_t> seen;
    StageObserver observer;
    observer.onSample = [&](const Simulation& s) { seen.push_back(s.stateHash()); };
    observer.onCheckpoint = [&](const Simulation& s, const StageProgress& at) {
      seen.push_back(s.stateHash() ^ at.steps);
    };
    observer.checkpointSteps = 25;
    if (everyStep) {
      observer.onProgress = [](const Simulation&, const StageSpec&) {};
      observer.progressSteps = 1;
    }
    const StageResult result = runStage(sim, stage, output, observer);
    EXPECT_EQ(result.steps, 300u);
    seen.push_back(sim.stateHash());
    return seen;
  };
  const std::vector<std::uint64_t> batched = record(false), single = record(true);
  EXPECT_EQ(batched.size(), 1u + 300u / 7 + 300u / 25 + 1u);  // t = 0, every 7 and 25 steps, end
  EXPECT_EQ(batched, single);
}

TEST(BatchedSteps, AnAdvanceAskedWhetherToGoOnTakesTheSameStepsAndStopsBetweenTwo) {
  // advanceTo(t, proceed) asks every kStepsBetweenAsks steps, the step before each ask not
  // predicting the next: asked and always told to go on, the same bits as advanceTo(t); told to
  // stop at the third ask, it stops after three times that many steps, short of t, and goes on
  // to t from there. Gear5 predicts in its corrector: a stop after a predicting step would leave
  // the predicted state.
  // A step of 2^-13 s and t = 400 of them: the steps advanceTo lays out are that step exactly.
  const double dt = 1.0 / 8192.0, t = 400 * dt;  // [s] contacts forming
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    const std::string what = integrator == Integrator::Gear5 ? "gear5" : "verlet";
    Simulation plain = landingBed(integrator, 1, dt);
    plain.advanceTo(t);
    Simulation asked = landingBed(integrator, 1, dt);
    int asks = 0;
    EXPECT_TRUE(asked.advanceTo(t, [&] { return ++asks > 0; })) << what;
    EXPECT_EQ(asks, int(plain.stepCount() / Simulation::kStepsBetweenAsks)) << what;
    expectSame(observe(asked), observe(plain), what + ", asked");
    EXPECT_EQ(asked.time(), t) << what;

    Simulation stopped = landingBed(integrator, 1, dt);
    asks = 0;
    EXPECT_FALSE(stopped.advanceTo(t, [&] { return ++asks < 3; })) << what;
    EXPECT_EQ(stopped.stepCount(), 3 * Simulation::kStepsBetweenAsks) << what;
    EXPECT_LT(stopped.time(), t) << what;
    EXPECT_EQ(stopped.config().timeStep, dt) << what;
    // Stopped after a corrected step: the state of a run of as many steps, which ends
    // corrected (a predicting step would leave the next step's predicted positions), and one
    // more step from there is that run's too.
    Simulation counted = landingBed(integrator, 1, dt);
    counted.run(3 * Simulation::kStepsBetweenAsks);
    EXPECT_EQ(stopped.stateHash(), counted.stateHash()) << what;
    counted.step();
    stopped.step();
    EXPECT_EQ(stopped.stateHash(), counted.stateHash()) << what;
    stopped.advanceTo(t);
    EXPECT_EQ(stopped.time(), t) << what;
  }
}

}  // namespace
}  // namespace granular
