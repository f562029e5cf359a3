/// Tests of runStage with a handful of particles: the end conditions (max time; kinetic energy
/// sustained below a threshold), the sampling and snapshot schedule, the top wall placed on the
/// surface, wall motions and the stage clock.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <vector>

#include "granular/checkpoint.hpp"
#include "granular/error.hpp"
#include "granular/scene.hpp"
#include "granular/stage.hpp"
#include "physics_fixtures.hpp"

namespace granular {
namespace {

constexpr double kDt = 1e-4;  // [s]; about 1/90 of the contact duration of these spheres

/// An open-topped unit box with the given particles (x, r) at rest.
Simulation smallScene(const std::vector<std::pair<Vec3, double>>& spheres,
                      const Vec3& gravity = Vec3(0, 0, -9.81)) {
  SimulationConfig config;
  config.timeStep = kDt;
  config.gravity = gravity;
  Particles particles;
  for (const auto& [x, r] : spheres) particles.add(x, r, config.material.density);
  BoxSpec box;
  box.min = Vec3::Zero();
  box.max = Vec3::Ones();
  return Simulation(std::move(particles), buildWalls(box), config);
}

/// Four spheres on the floor at rest.
Simulation fourOnTheFloor() {
  return smallScene({{Vec3(0.2, 0.2, 0.03), 0.03},
                     {Vec3(0.6, 0.2, 0.03), 0.03},
                     {Vec3(0.2, 0.6, 0.035), 0.035},
                     {Vec3(0.6, 0.6, 0.3), 0.032}});
}

StageSpec stageOf(double maxTime) {
  StageSpec stage;
  stage.name = "test";
  stage.end.maxTime = maxTime;
  return stage;
}

TEST(Stage, EndsAtMaxTime) {
  Simulation sim = fourOnTheFloor();
  const StageResult r = runStage(sim, stageOf(0.05), OutputSpec{}, StageObserver{});
  EXPECT_EQ(r.reason, StageEndReason::MaxTime);
  EXPECT_EQ(r.steps, 500u);
  EXPECT_NEAR(r.duration, 0.05, 1e-12);
  EXPECT_EQ(sim.stepCount(), 500u);
}

TEST(Stage, SampleCountIsFloorOfDurationOverIntervalPlusOne) {
  struct Case {
    double maxTime, interval;
  };
  for (const Case c : {Case{0.05, 0.01}, Case{0.05, 0.003}, Case{0.0321, 0.007}, Case{0.02, 0.05},
                       Case{0.03, 0.0001}}) {
    SCOPED_TRACE(::testing::Message() << "max time " << c.maxTime << ", interval " << c.interval);
    Simulation sim = fourOnTheFloor();
    OutputSpec output;
    output.interval = c.interval;
    std::vector<std::uint64_t> sampledSteps;
    StageObserver observer;
    observer.onSample = [&](const Simulation& s) { sampledSteps.push_back(s.stepCount()); };
    const StageResult r = runStage(sim, stageOf(c.maxTime), output, observer);
    const auto expected = std::size_t(std::floor(r.duration / c.interval + 1e-9)) + 1;
    EXPECT_EQ(sampledSteps.size(), expected);
    // Sample k at the first step at or after k·interval.
    for (std::size_t k = 0; k < sampledSteps.size(); ++k) {
      EXPECT_EQ(sampledSteps[k], std::uint64_t(std::ceil(k * c.interval / kDt - 1e-6))) << k;
    }
  }
}

TEST(Stage, KineticEnergyEndNeedsTheSustainTime) {
  // At rest without gravity the kinetic energy is 0 throughout: the stage ends exactly when
  // the sustain time has passed.
  Simulation sim = smallScene({{Vec3(0.5, 0.5, 0.5), 0.03}}, Vec3::Zero());
  StageSpec stage = stageOf(1.0);
  stage.end.kineticEnergyBelow = 1e-9;
  stage.end.sustainTime = 0.02;
  const StageResult r = runStage(sim, stage, OutputSpec{}, StageObserver{});
  EXPECT_EQ(r.reason, StageEndReason::KineticEnergy);
  EXPECT_EQ(r.steps, 200u);
}

TEST(Stage, KineticEnergyMustStayBelowContinuously) {
  // A sphere dropped onto the floor from touching: its damped bounce passes below the threshold
  // at every turning point long before it is quiet for good. The stage may end only after an
  // unbroken run below the threshold lasting the sustain time.
  Simulation sim = smallScene({{Vec3(0.5, 0.5, 0.03), 0.03}});
  StageSpec stage = stageOf(1.0);
  const double threshold = 1e-7;  // [J]
  stage.end.kineticEnergyBelow = threshold;
  stage.end.sustainTime = 0.01;
  std::vector<double> energy{sim.kineticEnergy()};
  StageObserver observer;
  observer.progressSteps = 1;
  observer.onProgress = [&](const Simulation& s, const StageSpec&) {
    energy.push_back(s.kineticEnergy());
  };
  const StageResult r = runStage(sim, stage, OutputSpec{}, observer);
  ASSERT_EQ(r.reason, StageEndReason::KineticEnergy);
  ASSERT_EQ(energy.size(), r.steps + 1);
  // The final run below the threshold covers stage times t0 .. t0 + sustain: 101 states.
  const std::size_t run = std::size_t(std::lround(stage.end.sustainTime / kDt)) + 1;
  ASSERT_GT(energy.size(), run);
  for (std::size_t i = energy.size() - run; i < energy.size(); ++i) EXPECT_LT(energy[i], threshold);
  EXPECT_GE(energy[energy.size() - run - 1], threshold);
  // And the bounce did dip below the threshold earlier without ending the stage.
  bool dippedEarlier = false;
  for (std::size_t i = 1; i + run + 1 < energy.size(); ++i) {
    dippedEarlier = dippedEarlier || (energy[i] < threshold && energy[i - 1] >= threshold);
  }
  EXPECT_TRUE(dippedEarlier);
}

TEST(Stage, KineticEnergyAboveThresholdRunsToMaxTime) {
  Simulation sim = smallScene({{Vec3(0.5, 0.5, 0.9), 0.03}});  // falls freely for 0.05 s
  StageSpec stage = stageOf(0.05);
  stage.end.kineticEnergyBelow = 1e-9;
  const StageResult r = runStage(sim, stage, OutputSpec{}, StageObserver{});
  EXPECT_EQ(r.reason, StageEndReason::MaxTime);
  EXPECT_EQ(r.steps, 500u);
}

TEST(Stage, TopWallIsPlacedOnTheSurface) {
  Simulation sim = fourOnTheFloor();
  double surface = 0.0;
  for (std::size_t i = 0; i < sim.particles().size(); ++i) {
    surface = std::max(surface, sim.particles().position[i].z() + sim.particles().radius[i]);
  }
  EXPECT_DOUBLE_EQ(surface, 0.3 + 0.032);
  StageSpec stage = stageOf(kDt);  // one step: the wall is at rest, so it stays where placed
  stage.placeTopWallOnSurface = true;
  runStage(sim, stage, OutputSpec{}, StageObserver{});
  const long top = sim.findWall("top");
  ASSERT_GE(top, 0);
  const Wall& wall = sim.walls()[std::size_t(top)];
  EXPECT_EQ(wall.point.z(), surface);
  EXPECT_EQ(wall.normal, Vec3(0, 0, -1));
  // A second placement would hide the first wall's history: refused.
  EXPECT_THROW(runStage(sim, stage, OutputSpec{}, StageObserver{}), ConfigError);
}

TEST(Stage, WallMotionsAreSetAndUnlistedWallsStop) {
  Simulation sim = fourOnTheFloor();
  StageSpec press = stageOf(10 * kDt);
  press.placeTopWallOnSurface = true;
  press.wallMotions = {{"top", Vec3(0, 0, -0.01)}};
  runStage(sim, press, OutputSpec{}, StageObserver{});
  const std::size_t top = std::size_t(sim.findWall("top"));
  EXPECT_EQ(sim.walls()[top].velocity, Vec3(0, 0, -0.01));

  runStage(sim, stageOf(10 * kDt), OutputSpec{}, StageObserver{});  // a hold stage
  EXPECT_EQ(sim.walls()[top].velocity, Vec3::Zero());

  StageSpec unknown = stageOf(kDt);
  unknown.wallMotions = {{"lid", Vec3(0, 0, -0.01)}};
  EXPECT_THROW(runStage(sim, unknown, OutputSpec{}, StageObserver{}), ConfigError);
}

TEST(Stage, ClockResetAndStageTime) {
  Simulation sim = fourOnTheFloor();
  runStage(sim, stageOf(0.01), OutputSpec{}, StageObserver{});
  EXPECT_NEAR(sim.time(), 0.01, 1e-12);

  // Without a reset the simulation clock runs on, but the stage's own time starts at 0.
  StageResult r = runStage(sim, stageOf(0.02), OutputSpec{}, StageObserver{});
  EXPECT_EQ(r.steps, 200u);
  EXPECT_NEAR(sim.time(), 0.03, 1e-12);

  StageSpec reset = stageOf(0.02);
  reset.resetClock = true;
  r = runStage(sim, reset, OutputSpec{}, StageObserver{});
  EXPECT_EQ(r.steps, 200u);
  EXPECT_NEAR(sim.time(), 0.02, 1e-12);
}

TEST(Stage, SnapshotsAndProgress) {
  Simulation sim = fourOnTheFloor();
  OutputSpec output;
  output.snapshotTimes = {0.02, 0.0, 0.5, 0.02, 0.0333};
  std::vector<double> snapshots;
  std::vector<std::uint64_t> snapshotSteps;
  int progressCalls = 0;
  StageObserver observer;
  observer.onSnapshot = [&](const Simulation& s, double t) {
    snapshots.push_back(t);
    snapshotSteps.push_back(s.stepCount());
  };
  observer.onProgress = [&](const Simulation&, const StageSpec& stage) {
    EXPECT_EQ(stage.name, "test");
    ++progressCalls;
  };
  observer.progressSteps = 100;
  runStage(sim, stageOf(0.05), output, observer);
  EXPECT_EQ(snapshots, (std::vector<double>{0.0, 0.02, 0.0333}));  // once each, in order
  EXPECT_EQ(snapshotSteps, (std::vector<std::uint64_t>{0, 200, 333}));
  EXPECT_EQ(progressCalls, 5);
}

}  // namespace
}  // namespace granular

namespace granular {
namespace {

// A stage resumed from a checkpoint taken inside it continues exactly: the same samples at the
// same times, the same end (the quiet-time condition included) and the same final state.
TEST(Stage, ResumedFromACheckpointEndsAsIfItNeverStopped) {
  StageSpec stage;
  stage.name = "settle";
  stage.end.maxTime = 2.0;
  stage.end.kineticEnergyBelow = 3e-3;  // reached and held while the bed quietens
  stage.end.sustainTime = 0.05;
  stage.placeTopWallOnSurface = true;  // set-up that must not be applied twice
  stage.resetClock = true;
  OutputSpec output;
  output.interval = 0.01;
  output.snapshotTimes = {0.05, 0.2};

  struct Record {
    std::vector<std::pair<double, std::uint64_t>> samples;
    std::vector<double> snapshots;
  };
  auto observe = [](Record& r) {
    StageObserver o;
    o.onSample = [&r](const Simulation& s) { r.samples.emplace_back(s.time(), s.stateHash()); };
    o.onSnapshot = [&r](const Simulation&, double t) { r.snapshots.push_back(t); };
    return o;
  };
  const SimulationConfig cfg = [] {
    SimulationConfig c;
    c.material.friction = 0.3;
    c.material.normalDamping = 200.0;
    c.timeStep = 1.5e-4;
    return c;
  }();

  Record whole;
  Simulation uninterrupted = testing::fallingGrid(3, 3, 2, cfg, 0.2);
  uninterrupted.run(10);
  const StageResult full = runStage(uninterrupted, stage, output, observe(whole));
  ASSERT_EQ(full.reason, StageEndReason::KineticEnergy)  // the sustain logic is exercised
      << "KE " << uninterrupted.kineticEnergy() << " J after " << full.duration << " s";

  // The same run, stopped at a checkpoint while the kinetic energy is already low.
  const auto file = std::filesystem::temp_directory_path() / "granular_test_stage_resume.ckpt";
  Record first;
  std::optional<StageProgress> saved;
  Simulation interrupted = testing::fallingGrid(3, 3, 2, cfg, 0.2);
  interrupted.run(10);
  StageObserver stopping = observe(first);
  stopping.checkpointSteps = 100;
  struct Stop {};
  stopping.onCheckpoint = [&](const Simulation& s, const StageProgress& p) {
    if (!p.belowSince) return;
    writeCheckpoint(s, file, 1);
    saved = p;
    throw Stop{};  // as a kill would
  };
  EXPECT_THROW(runStage(interrupted, stage, output, stopping), Stop);
  ASSERT_TRUE(saved.has_value());

  Simulation restored = readCheckpoint(file, 1);
  std::filesystem::remove(file);
  Record second;
  const StageResult rest = runStage(restored, stage, output, observe(second), &*saved);
  EXPECT_EQ(rest.reason, full.reason);
  EXPECT_EQ(rest.steps, full.steps);
  EXPECT_EQ(restored.stateHash(), uninterrupted.stateHash());
  EXPECT_EQ(restored.walls().size(), uninterrupted.walls().size());  // one top wall, not two
  Record joined = first;
  joined.samples.insert(joined.samples.end(), second.samples.begin(), second.samples.end());
  joined.snapshots.insert(joined.snapshots.end(), second.snapshots.begin(), second.snapshots.end());
  EXPECT_EQ(joined.samples, whole.samples);
  EXPECT_EQ(joined.snapshots, whole.snapshots);
}

}  // namespace
}  // namespace granular

namespace granular {
namespace {

TEST(Stage, AnAutomaticStepAboveItsFloorLandsOnEverySampleAndOnTheStagesEnd) {
  // A settled bed at "auto": the floor stretched, the step (the network's) is longer than
  // t_c/10, the step the stage used to assume no step exceeds. Samples every 0.01 s are
  // taken at their times exactly, and a stage with no sample inside it ends at its end.
  Simulation sim = granular::testing::settledAutomaticBed();
  const SimulationConfig& cfg = sim.config();
  const double floor = sim.contactScale().duration / cfg.step.contactResolution;
  ASSERT_GT(sim.stepCheck().chosenStep, 1.5 * floor);

  OutputSpec output;
  output.interval = 0.01;
  std::vector<double> sampled;
  StageObserver observer;
  const double start = sim.time();
  observer.onSample = [&](const Simulation& s) { sampled.push_back(s.time() - start); };
  // A kinetic-energy end (never reached here) makes the stage look after every step: a batch
  // of one step wherever the next sample is more than a floor's step away.
  StageSpec stage = stageOf(0.2);
  stage.resetClock = false;
  stage.end.kineticEnergyBelow = 1e-30;
  runStage(sim, stage, output, observer);
  ASSERT_EQ(sampled.size(), 21u);
  for (std::size_t k = 0; k < sampled.size(); ++k) {
    EXPECT_NEAR(sampled[k], 0.01 * double(k), 1e-9) << "sample " << k;
  }

  // None inside a stage of 3000 floor steps (batches of 1000): its end is the one event.
  const double duration = 3000.0 * floor;
  output.interval = 2.0 * duration;
  const double before = sim.time();
  StageSpec last = stageOf(duration);
  last.resetClock = false;
  const StageResult r = runStage(sim, last, output, StageObserver{});
  EXPECT_DOUBLE_EQ(r.duration, duration);
  EXPECT_NEAR(sim.time() - before, duration, 1e-9);
}

}  // namespace
}  // namespace granular
