/// runStage: a stage's set-up (clock, top wall, wall velocities), then stepping to its end
/// condition while calling the observer at the output interval and at snapshot times.
///
/// Time inside a stage is n·Δt, n the steps taken since the stage began: it starts at 0 whether
/// or not the simulation's clock was reset, and it does not collect the round-off of a running
/// sum. Comparisons against it carry a tolerance of 1e-6·Δt, so that a sample due at exactly
/// k·interval is taken at the step that lands there and not one step late.
#include "granular/stage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "granular/error.hpp"
#include "granular/stage_exchange.hpp"

namespace granular {

namespace {

/// The top wall of the paper's stage 2: a plane touching the highest particle, normal down.
void placeTopWall(Simulation& sim, const StageSpec& stage) {
  if (sim.findWall("top") >= 0) {
    throw ConfigError("stage '" + stage.name +
                      "': cannot place the top wall on the surface: a wall named 'top' exists");
  }
  // The highest particle over the ranks of a split run (each looks at its own).
  const Particles& particles = sim.particles();
  double surface = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (sim.owns(i)) surface = std::max(surface, particles.position[i].z() + particles.radius[i]);
  }
  if (const Communicator* ranks = sim.ranks()) surface = ranks->maxOverRanks(surface);
  if (!std::isfinite(surface)) {
    throw ConfigError("stage '" + stage.name + "': no particles to place the top wall on");
  }
  Wall top;
  top.name = "top";
  top.point = Vec3(0.0, 0.0, surface);
  top.normal = -Vec3::UnitZ();
  sim.addWall(top);
}

/// Every wall not named by the stage is at rest during it: a stage describes the whole wall
/// motion, so a hold stage after a compaction does not inherit the compaction's velocity.
/// Each wall's velocity is set once (a change re-chooses an automatic step).
void applyWallMotions(Simulation& sim, const StageSpec& stage) {
  std::vector<Vec3> velocity(sim.walls().size(), Vec3::Zero());
  for (const WallMotion& motion : stage.wallMotions) {
    const long index = sim.findWall(motion.wall);
    if (index < 0) {
      throw ConfigError("stage '" + stage.name + "': no wall named '" + motion.wall + "' to move");
    }
    velocity[std::size_t(index)] = motion.velocity;
  }
  for (std::size_t w = 0; w < velocity.size(); ++w) sim.setWallVelocity(w, velocity[w]);
}

/// Fires onSample every output interval and onSnapshot once per snapshot time (the stage's own
/// times where it lists them, else the output's).
class StageClock {
 public:
  StageClock(const OutputSpec& output, const StageSpec& stage, const StageObserver& observer,
             double timeStep)
      : output_(output),
        observer_(observer),
        tolerance_(1e-6 * timeStep),
        snapshots_(stage.snapshotTimes.value_or(output.snapshotTimes)) {
    std::sort(snapshots_.begin(), snapshots_.end());
    snapshots_.erase(std::unique(snapshots_.begin(), snapshots_.end()), snapshots_.end());
  }

  /// Continuing a stage at stage time t whose samples and snapshots up to t were all taken.
  void resumeAt(double t) {
    nextSample_ = std::uint64_t(std::floor((t + tolerance_) / output_.interval)) + 1;
    while (nextSnapshot_ < snapshots_.size() && snapshots_[nextSnapshot_] <= t + tolerance_) {
      ++nextSnapshot_;
    }
  }

  /// The stage time of the next sample or snapshot [s].
  double nextEvent() const {
    double t = double(nextSample_) * output_.interval;
    if (nextSnapshot_ < snapshots_.size()) t = std::min(t, snapshots_[nextSnapshot_]);
    return t;
  }

  /// Whether observe(sim, t) would call an observer.
  bool due(double t) const {
    return t + tolerance_ >= double(nextSample_) * output_.interval ||
           (nextSnapshot_ < snapshots_.size() && snapshots_[nextSnapshot_] <= t + tolerance_);
  }

  /// Called at the stage start (t = 0) and after every step with the stage time t [s].
  void observe(const Simulation& sim, double t) {
    // The sample index is an integer: k·interval is compared, never a running sum of intervals.
    if (t + tolerance_ >= double(nextSample_) * output_.interval) {
      if (observer_.onSample) observer_.onSample(sim);
      nextSample_ = std::uint64_t(std::floor((t + tolerance_) / output_.interval)) + 1;
    }
    while (nextSnapshot_ < snapshots_.size() && snapshots_[nextSnapshot_] <= t + tolerance_) {
      if (observer_.onSnapshot) observer_.onSnapshot(sim, snapshots_[nextSnapshot_]);
      ++nextSnapshot_;
    }
  }

 private:
  const OutputSpec& output_;
  const StageObserver& observer_;
  double tolerance_;
  std::vector<double> snapshots_;
  std::uint64_t nextSample_ = 0;
  std::size_t nextSnapshot_ = 0;
};

/// The quasistatic end: the kinetic energy below the stage's threshold from `belowSince` on, for
/// its sustain time (stage clock, with `tolerance`). The initial state counts towards the
/// sustain time but cannot end the stage.
class QuietEnd {
 public:
  QuietEnd(const StageSpec& stage, double tolerance, const StageProgress* resume)
      : stage_(stage), tolerance_(tolerance) {
    if (resume) belowSince_ = resume->belowSince;
  }
  /// At stage time t, with `sim` in the state of that time: whether the stage ends. A stage
  /// that inserts particles is not quiet before its inserts are done (an empty silo is).
  bool reached(const Simulation& sim, double t, const StageExchange& exchange) {
    if (!stage_.end.kineticEnergyBelow || !exchange.insertsDone(sim) ||
        sim.kineticEnergy() >= *stage_.end.kineticEnergyBelow) {
      belowSince_.reset();
      return false;
    }
    if (!belowSince_) belowSince_ = t;
    return t - *belowSince_ + tolerance_ >= stage_.end.sustainTime;
  }
  const std::optional<double>& belowSince() const { return belowSince_; }

 private:
  const StageSpec& stage_;
  double tolerance_;
  std::optional<double> belowSince_;
};

/// runStage with an automatic step: the simulation advances to each sample, snapshot and the
/// end exactly (Simulation::advanceTo), and between them in runs of whole steps where no event
/// can fall inside (the longest step the control may choose is its accuracy floor).
StageResult runStageAutomatic(Simulation& sim, const StageSpec& stage, const OutputSpec& output,
                              const StageObserver& observer, const StageProgress* resume) {
  const double tolerance = 1e-9 * output.interval;
  const double resumedAt = resume ? resume->time.value_or(0.0) : 0.0;
  // The stage's t = 0 on the simulation's clock.
  const double origin = resume && resume->origin ? *resume->origin : sim.time() - resumedAt;
  StageClock clock(output, stage, observer, 1e-3 * output.interval);
  StageExchange exchange(stage, 1e-3 * output.interval);
  if (resume) {
    clock.resumeAt(resumedAt);
    exchange.resumeAt(resumedAt);
  } else {
    clock.observe(sim, 0.0);
  }
  QuietEnd quiet(stage, tolerance, resume);
  if (!resume) quiet.reached(sim, 0.0, exchange);

  StageResult result;
  std::uint64_t n = resume ? resume->steps : 0;
  const std::uint64_t start = sim.stepCount() - n;
  std::uint64_t lastProgress = n, lastCheckpoint = n;
  double t = resumedAt;
  // With a kinetic-energy end the state is looked at after every step, as with a fixed step.
  const std::uint64_t run =
      stage.end.kineticEnergyBelow
          ? 1
          : std::max<std::uint64_t>(
                1,
                std::min(observer.progressSteps > 0 && observer.onProgress ? observer.progressSteps
                                                                           : std::uint64_t(1000),
                         observer.checkpointSteps > 0 && observer.onCheckpoint
                             ? observer.checkpointSteps
                             : std::uint64_t(1000)));
  // The longest step the control may choose while contacts strike: its accuracy floor.
  const double longest = sim.contactScale().duration / sim.config().step.contactResolution;
  while (t + tolerance < stage.end.maxTime) {
    const double event = std::min({stage.end.maxTime, clock.nextEvent(), exchange.next()});
    if (event - t > double(run) * longest) {
      // Whole steps, none reaching the event: the floor stretched, the step may grow past it
      // at any check, so each is measured against the event before it is taken. Where the
      // next would reach it, the landing steps.
      if (sim.runBefore(run, origin + event - tolerance) == 0) sim.advanceTo(origin + event);
    } else {
      sim.advanceTo(origin + event);  // the stretch to the event in equal steps
    }
    n = sim.stepCount() - start;
    t = sim.time() - origin;
    if (std::abs(t - event) <= tolerance) t = event;
    exchange.apply(sim, t);  // before the samples, which then see the particles it leaves
    clock.observe(sim, t);
    if (observer.onProgress && observer.progressSteps > 0 &&
        n - lastProgress >= observer.progressSteps) {
      observer.onProgress(sim, stage);
      lastProgress = n;
    }
    if (quiet.reached(sim, t, exchange)) {
      result.reason = StageEndReason::KineticEnergy;
      break;
    }
    if (observer.onCheckpoint && observer.checkpointSteps > 0 &&
        n - lastCheckpoint >= observer.checkpointSteps) {
      observer.onCheckpoint(sim, StageProgress{n, quiet.belowSince(), t, origin});
      lastCheckpoint = n;
    }
  }
  result.steps = n;
  result.duration = t;
  return result;
}

}  // namespace

void beginStage(Simulation& sim, const StageSpec& stage) {
  if (stage.resetClock) sim.setTime(0.0);
  if (stage.placeTopWallOnSurface) placeTopWall(sim, stage);
  for (const std::string& name : stage.removeWalls) {
    const long index = sim.findWall(name);
    if (index < 0) {
      throw ConfigError("stage '" + stage.name + "': no wall named '" + name + "' to remove");
    }
    sim.removeWall(std::size_t(index));
  }
  applyWallMotions(sim, stage);
}

StageResult runStage(Simulation& sim, const StageSpec& stage, const OutputSpec& output,
                     const StageObserver& observer, const StageProgress* resume) {
  if (!(output.interval > 0.0)) throw ConfigError("output interval must be > 0");
  if (!(stage.end.maxTime > 0.0)) {
    throw ConfigError("stage '" + stage.name + "': max time must be > 0");
  }
  if (!resume) beginStage(sim, stage);
  if (sim.config().step.automatic) return runStageAutomatic(sim, stage, output, observer, resume);

  const double dt = sim.config().timeStep;
  const double tolerance = 1e-6 * dt;
  StageClock clock(output, stage, observer, dt);
  StageExchange exchange(stage, tolerance);
  if (resume) {
    clock.resumeAt(double(resume->steps) * dt);
    exchange.resumeAt(double(resume->steps) * dt);
  } else {
    clock.observe(sim, 0.0);
  }

  QuietEnd quiet(stage, tolerance, resume);
  // The initial state counts towards the sustain time, but cannot end the stage.
  if (!resume) quiet.reached(sim, 0.0, exchange);

  StageResult result;
  std::uint64_t n = resume ? resume->steps : 0;
  auto progressDue = [&](std::uint64_t m) {
    return observer.onProgress && observer.progressSteps > 0 && m % observer.progressSteps == 0;
  };
  auto checkpointDue = [&](std::uint64_t m) {
    return observer.onCheckpoint && observer.checkpointSteps > 0 &&
           m % observer.checkpointSteps == 0;
  };
  // Whether anything looks at the state after step m: the steps before such a step run as one
  // batch (Simulation::run, whose steps predict the next one in their corrector's loop).
  auto seen = [&](std::uint64_t m) {
    const double t = double(m) * dt;
    return !(t + tolerance < stage.end.maxTime) || stage.end.kineticEnergyBelow.has_value() ||
           clock.due(t) || exchange.due(t) || progressDue(m) || checkpointDue(m);
  };
  while (double(n) * dt + tolerance < stage.end.maxTime) {
    std::uint64_t batch = 1;
    while (!seen(n + batch)) ++batch;
    sim.run(batch);
    n += batch;
    const double t = double(n) * dt;
    exchange.apply(sim, t);  // before the samples, which then see the particles it leaves
    clock.observe(sim, t);
    if (progressDue(n)) observer.onProgress(sim, stage);
    if (quiet.reached(sim, t, exchange)) {
      result.reason = StageEndReason::KineticEnergy;
      break;
    }
    if (checkpointDue(n))
      observer.onCheckpoint(sim, StageProgress{n, quiet.belowSince(), std::nullopt, std::nullopt});
  }
  result.steps = n;
  result.duration = double(n) * dt;
  return result;
}

}  // namespace granular
