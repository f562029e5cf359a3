#pragma once
/// Running a stage: stepping until its end condition, sampling at the output interval.
#include <cstdint>
#include <functional>
#include <optional>

#include "granular/scene.hpp"

namespace granular {

enum class StageEndReason {
  MaxTime,        ///< the stage's time cap was reached
  KineticEnergy,  ///< the kinetic energy stayed below the threshold for the sustain time
};

struct StageResult {
  StageEndReason reason = StageEndReason::MaxTime;
  double duration = 0.0;  ///< simulated time the stage took [s]
  std::uint64_t steps = 0;
};

/// How far a stage has run: with the simulation's own state (a checkpoint), enough to continue
/// the stage exactly where it was.
struct StageProgress {
  std::uint64_t steps = 0;           ///< steps taken since the stage began
  std::optional<double> belowSince;  ///< stage time since which the kinetic energy is low [s]
  /// The stage time [s] with an automatic step (a fixed one's is steps · Δt).
  std::optional<double> time;
  /// The simulation clock at the stage's t = 0 [s] (automatic step): the resumed stage aims its
  /// steps at the same clock times to the bit (the clock less the stage time may round).
  std::optional<double> origin;
};

/// Callbacks of a running stage; any may be empty.
struct StageObserver {
  /// At the stage start and every output interval of simulated time (stage clock).
  std::function<void(const Simulation&)> onSample;
  /// When the stage clock passes a snapshot time.
  std::function<void(const Simulation&, double snapshotTime)> onSnapshot;
  /// Every `progressSteps` steps (for progress lines; the core itself never prints). With an
  /// automatic step: after the first step that completes `progressSteps` more (likewise for
  /// checkpoints).
  std::function<void(const Simulation&, const StageSpec&)> onProgress;
  std::uint64_t progressSteps = 1000;
  /// Every `checkpointSteps` steps (0: never), after the step's samples: a moment at which the
  /// simulation and `progress` can be saved and the stage resumed from them.
  std::function<void(const Simulation&, const StageProgress& progress)> onCheckpoint;
  std::uint64_t checkpointSteps = 0;
};

/// Applies the stage's set-up only: clock reset, top wall on the surface, wall velocities (every
/// wall the stage does not name is at rest). For a front end that steps a stage itself. Throws
/// ConfigError on a wall it cannot place or find.
void beginStage(Simulation& sim, const StageSpec& stage);

/// Applies the stage's set-up (beginStage) and steps to its end.
/// With `resume`, the simulation is a checkpoint taken inside this stage: the set-up is already
/// in it, and the stage continues from `resume` as if it had never stopped (same samples, same
/// end, bit for bit).
StageResult runStage(Simulation& sim, const StageSpec& stage, const OutputSpec& output,
                     const StageObserver& observer, const StageProgress* resume = nullptr);

}  // namespace granular
