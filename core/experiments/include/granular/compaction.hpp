#pragma once
/// The paper's numerical experiment (Sections 3.2-3.3) for one scene of two stages: stage 1
/// settles the particles under gravity (or is restored from its checkpoint); stage 2 starts a new
/// clock, places the top wall on the surface and moves it, while the box stresses of Eq. (1) and
/// Eq. (2) and the wall reactions are sampled.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "granular/checkpoint.hpp"
#include "granular/scene.hpp"
#include "granular/stage.hpp"
#include "granular/stress.hpp"

namespace granular {

struct CompactionOptions {
  /// Settled-state checkpoint: restored when it exists and matches `fingerprint`, written after
  /// stage 1 otherwise. Empty: always settle, write nothing.
  std::filesystem::path checkpoint;
  SceneFingerprint fingerprint;  ///< identifies the scene (fingerprintScene)
  /// Eq. (1) evaluations averaged over each output interval of stage 2 (the wall reactions are
  /// averaged exactly, from their impulses).
  int subSamples = 10;
  /// Called once the simulation exists (built, or restored from the checkpoint).
  std::function<void(const Simulation&)> onStart;
  /// Called at every output interval of both stages (for time-series files), with the stage name.
  std::function<void(const Simulation&, const std::string& stage)> onSample;
  /// Stage-1 clock times at which `onSettleSnapshot` is called (only when stage 1 runs).
  std::vector<double> settleSnapshots;
  std::function<void(const Simulation&, double time)> onSettleSnapshot;
  /// Called once with the settled state (after stage 1, or when restored), before stage 2.
  std::function<void(const Simulation&)> onSettled;
  /// Called every few hundred steps (for progress lines).
  std::function<void(const Simulation&, const StageSpec&)> onProgress;
};

struct SettleSample {
  double time = 0;     ///< stage-1 clock [s]
  double kinetic = 0;  ///< kinetic energy, translational + rotational [J]
};

struct CompactionSample {
  double time = 0;  ///< stage-2 clock at the end of the averaging interval [s]
  /// Wall reactions and Eq. (1) averaged over the output interval ending at `time` (the first
  /// sample, at t = 0, is instantaneous); Eq. (2) and the balance use the averaged reactions.
  BoxStress box;
};

struct CompactionResult {
  StageResult settle;
  bool settleRestored = false;  ///< stage 1 came from the checkpoint
  /// Why an existing checkpoint was not restored (stale, damaged or unreadable: it is settled
  /// again and overwritten); empty when it was, or when there was none.
  std::string checkpointRefused;
  double settleWallSeconds = 0;             ///< wall-clock time of stage 1 (0 when restored) [s]
  std::vector<SettleSample> settleHistory;  ///< empty when restored
  double settledHeight = 0;  ///< highest particle surface above the floor after stage 1 [m]
  StageResult compact;
  double compactWallSeconds = 0;
  std::vector<CompactionSample> samples;
  double finalHeight = 0;  ///< top wall above the floor at the end of stage 2 [m]
  double strain = 0;       ///< (finalHeight - settledHeight) / settledHeight [-]
  std::size_t particles = 0;
  double totalMass = 0;  ///< [kg]
  /// What the run checks (run_checks.hpp: the energy balance, particles outside the box) found
  /// at the samples of both stages, each check once, in order; empty when every check passed.
  /// A restored stage 1 is checked from the state restored.
  std::vector<std::string> failedChecks;
};

/// Runs both stages of `scene`, which must have exactly two: a settling stage, then one that
/// places the top wall on the surface. Throws ConfigError otherwise, and RunCheckError at the
/// first failed run check under the scene's on_failed_check = "stop".
CompactionResult runCompaction(const Scene& scene, const CompactionOptions& options);

}  // namespace granular
