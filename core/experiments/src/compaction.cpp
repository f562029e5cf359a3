/// runCompaction (compaction.hpp): settle or restore, then compact while sampling the box.
#include "granular/compaction.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "granular/checkpoint.hpp"
#include "granular/error.hpp"
#include "granular/run_checks.hpp"

namespace granular {
namespace {

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

double surfaceHeight(const Simulation& sim) {
  const Particles& p = sim.particles();
  const Wall& floor = sim.walls()[sim.findWall("bottom")];
  double top = floor.point.z();
  for (std::size_t i = 0; i < p.size(); ++i) top = std::max(top, p.position[i].z() + p.radius[i]);
  return top - floor.point.z();
}

/// Averages Eq. (1) over sub-samples and the wall reactions over an interval (from impulses).
class IntervalAverage {
 public:
  explicit IntervalAverage(const Simulation& sim) { restart(sim); }

  void subSample(const Simulation& sim) {
    if (sim.stepCount() == lastStep_) return;
    lastStep_ = sim.stepCount();
    const BoxContactSums now = boxContactSums(sim);
    sums_.eq1 += now.eq1;
    sums_.sideFrictionMoment += now.sideFrictionMoment;
    ++count_;
  }

  /// The sample for the interval ending now; starts the next interval.
  BoxStress close(const Simulation& sim) {
    subSample(sim);
    const double span = sim.time() - startTime_;
    std::vector<Vec3> reactions;
    for (std::size_t w = 0; w < sim.walls().size(); ++w) {
      reactions.push_back(span > 0 ? Vec3((sim.walls()[w].impulse - startImpulse_[w]) / span)
                                   : sim.walls()[w].reaction);
    }
    BoxContactSums mean = sums_;
    mean.eq1 /= count_;
    mean.sideFrictionMoment /= count_;
    const BoxStress b = measureBox(sim, reactions, &mean);
    restart(sim);
    return b;
  }

 private:
  void restart(const Simulation& sim) {
    startTime_ = sim.time();
    startImpulse_.clear();
    for (const Wall& w : sim.walls()) startImpulse_.push_back(w.impulse);
    sums_ = BoxContactSums{};
    count_ = 0;
    lastStep_ = ~std::uint64_t{0};
  }
  double startTime_ = 0;
  std::vector<Vec3> startImpulse_;
  BoxContactSums sums_;
  int count_ = 0;
  std::uint64_t lastStep_ = 0;
};

}  // namespace

CompactionResult runCompaction(const Scene& scene, const CompactionOptions& options) {
  if (scene.stages.size() != 2 || !scene.stages[1].placeTopWallOnSurface) {
    throw ConfigError(scene.sourceFile.string() +
                      ": a compaction experiment needs exactly two stages, the second placing the "
                      "top wall on the surface (place_top_wall_on_surface = true)");
  }
  const StageSpec& settleStage = scene.stages[0];
  const StageSpec& compactStage = scene.stages[1];
  CompactionResult result;

  // Stage 1: restore the settled state, or settle and checkpoint it.
  std::optional<Simulation> restored;
  if (!options.checkpoint.empty() && std::filesystem::exists(options.checkpoint)) {
    try {
      restored.emplace(readCheckpoint(options.checkpoint, options.fingerprint));
      result.settleRestored = true;
    } catch (const CheckpointError& e) {
      restored.reset();  // stale or damaged: settle again and overwrite it, saying why
      result.checkpointRefused = e.what();
    } catch (const IoError& e) {
      restored.reset();
      result.checkpointRefused = e.what();
    }
  }
  Simulation sim = restored ? std::move(*restored) : buildSimulation(scene);
  if (options.onStart) options.onStart(sim);
  // The run checks itself at every sample of both stages, as `granular run` does.
  RunChecks checks(scene.output.checks, scene.box, sim.energy().total());
  auto check = [&](const Simulation& s, const std::string& stage) {
    for (std::string& found : checks.atSample(s, stage)) {
      result.failedChecks.push_back(std::move(found));
    }
  };
  if (!result.settleRestored) {
    StageObserver observer;
    observer.onSample = [&](const Simulation& s) {
      result.settleHistory.push_back({s.time(), s.kineticEnergy()});
      check(s, settleStage.name);
      if (options.onSample) options.onSample(s, settleStage.name);
    };
    observer.onProgress = options.onProgress;
    observer.onSnapshot = options.onSettleSnapshot;
    OutputSpec output = scene.output;
    output.snapshotTimes = options.settleSnapshots;
    const auto start = std::chrono::steady_clock::now();
    result.settle = runStage(sim, settleStage, output, observer);
    result.settleWallSeconds = seconds(start);
    if (!options.checkpoint.empty()) writeCheckpoint(sim, options.checkpoint, options.fingerprint);
  } else {
    result.settle.duration = sim.time();
    result.settle.steps = sim.stepCount();
  }
  if (options.onSettled) options.onSettled(sim);
  result.settledHeight = surfaceHeight(sim);
  result.particles = sim.particles().size();
  for (double m : sim.particles().mass) result.totalMass += m;

  // Stage 2: sample the box every output interval, Eq. (1) averaged over sub-samples.
  std::optional<IntervalAverage> average;
  StageObserver observer;
  observer.onSample = [&](const Simulation& s) {
    if (!average) average.emplace(s);  // the first sample, at the start: instantaneous
    result.samples.push_back({s.time(), average->close(s)});
    check(s, compactStage.name);
    if (options.onSample) options.onSample(s, compactStage.name);
  };
  const double dt = scene.simulation.timeStep;
  const auto stepsPerInterval =
      static_cast<std::uint64_t>(std::llround(scene.output.interval / dt));
  observer.progressSteps =
      std::max<std::uint64_t>(1, stepsPerInterval / std::max(1, options.subSamples));
  std::uint64_t calls = 0;
  observer.onProgress = [&](const Simulation& s, const StageSpec& st) {
    if (average) average->subSample(s);
    if (options.onProgress && ++calls % 100 == 0) options.onProgress(s, st);
  };
  const auto start = std::chrono::steady_clock::now();
  result.compact = runStage(sim, compactStage, scene.output, observer);
  result.compactWallSeconds = seconds(start);
  const Wall& top = sim.walls()[sim.findWall("top")];
  const Wall& floor = sim.walls()[sim.findWall("bottom")];
  result.finalHeight = top.point.z() - floor.point.z();
  result.strain = (result.finalHeight - result.settledHeight) / result.settledHeight;
  return result;
}

}  // namespace granular
