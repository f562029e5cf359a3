#pragma once
/// Running a stage: stepping until its end condition, sampling at the output interval.
#include <cstdint>
#include <functional>

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

/// Callbacks of a running stage; any may be empty.
struct StageObserver {
  /// At the stage start and every output interval of simulated time (stage clock).
  std::function<void(const Simulation&)> onSample;
  /// When the stage clock passes a snapshot time.
  std::function<void(const Simulation&, double snapshotTime)> onSnapshot;
  /// Every `progressSteps` steps (for progress lines; the core itself never prints).
  std::function<void(const Simulation&, const StageSpec&)> onProgress;
  std::uint64_t progressSteps = 1000;
};

/// Applies the stage's set-up (clock reset, top wall, wall velocities) and steps to its end.
StageResult runStage(Simulation& sim, const StageSpec& stage, const OutputSpec& output,
                     const StageObserver& observer);

}  // namespace granular
