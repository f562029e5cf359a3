#pragma once
/// Switches for tests, benchmarks and numerical studies, kept out of Simulation's public API: a
/// program built on granular has no use for them, and one of them lets the engine produce
/// garbage. Neither is checkpointed: a restored Simulation starts with both off.
#include <cstdint>

#include "granular/simulation.hpp"

namespace granular::studies {

/// With `on`, the neighbour list is rebuilt at every step instead of when particles or walls
/// have moved more than the skin allows: the contact forces are the same (the tests check that
/// the contact history survives rebuilds), only the cost changes (benchmarks time a rebuild).
void setRebuildEveryStep(Simulation& sim, bool on);

/// With `off`, time steps above maxStableStep and tangential damping above maxTangentialDamping
/// are accepted from now on (setTimeStep, setMaterial, setIntegrator); results may then be
/// garbage. For the stability studies that measure those limits
/// (bench/bench_gear_stability.cpp) and the tests that go past them on purpose.
void disableStepLimit(Simulation& sim, bool off);

/// What the step control's reviews inside the steps cost since the Simulation was made or
/// restored (wall clock, not checkpointed): the full checks against the network, the scans of
/// the contacts' motion alone, and their time [s]. For the benchmarks that weigh it against the
/// run (bench/peer/peer_stage2.cpp).
struct StepControlCost {
  std::uint64_t checks = 0, scans = 0;
  /// The checks that made the spectrum's estimate (NetworkCalibration), a cold Lanczos run each.
  std::uint64_t calibrations = 0;
  double seconds = 0.0;
};
StepControlCost stepControlCost(const Simulation& sim);

/// The spectrum's estimate of ω_max and Γ (NetworkCalibration) taken × `factor` (> 0) from the
/// next check on, which takes its step × 1 / factor (never above the bound's): below 1, an
/// estimate too low, whose steps grow and must be caught and undone
/// (docs/physics.md §2.16; the rollback's tests and bench/RESULTS.md, "The growth watch").
void scaleSpectrumEstimate(Simulation& sim, double factor);

}  // namespace granular::studies
