#pragma once
/// Checks a run makes of itself at its samples, so that a broken run says so instead of ending
/// quietly with exit 0: the energy balance ("energy never grows without work") and particles
/// that have left the box. Cheap: the ledger (Simulation::energy) and one pass over the
/// positions, at the output interval, not every step.
#include <cstdint>
#include <string>
#include <vector>

#include "granular/error.hpp"
#include "granular/scene.hpp"

namespace granular {

/// A check that failed under CheckAction::Stop: the run stops as for a broken state.
class RunCheckError : public NumericalError {
 public:
  using NumericalError::NumericalError;
};

class RunChecks {
 public:
  /// `referenceTotal`: EnergyBalance::total() at the start of the run (kept across a resume).
  RunChecks(const RunCheckSpec& spec, const BoxSpec& box, double referenceTotal);

  /// Checks the state at a sample of stage `stage`. Returns what failed for the first time in
  /// this run (each check reports once), as messages without a "warning: " prefix; under
  /// CheckAction::Stop throws RunCheckError with the message instead (both, joined by "; and ",
  /// when both fail at once).
  std::vector<std::string> atSample(const Simulation& sim, const std::string& stage);

  double referenceTotal() const { return referenceTotal_; }

  /// The energy that went through the run, against which the drift is measured [J]: the energy
  /// stored at the start plus the magnitudes of the work of gravity, of the walls and of the
  /// tangential stiffness, and everything dissipated.
  static double workDone(const EnergyBalance& e, double referenceTotal);

 private:
  std::string energyDrift(const Simulation& sim, const std::string& stage) const;
  std::string outsideBox(const Simulation& sim, const std::string& stage) const;

  RunCheckSpec spec_;
  BoxSpec box_;
  double referenceTotal_;
  bool driftReported_ = false;
  bool outsideReported_ = false;
};

}  // namespace granular
