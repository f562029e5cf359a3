/// The growth watch and the rollback (docs/physics.md §2.16).
#include "rollback.hpp"

#include <cmath>
#include <utility>

#include "energy_ledger.hpp"
#include "simulation_state.hpp"
#include "step_check.hpp"

namespace granular {

/// What the watch compares the ledger with since a point: its residual (EnergyBalance::total)
/// and what has flowed through it, taken from one balance.
struct LedgerReading {
  double residual = 0;  ///< EnergyBalance::total() [J]
  /// Dissipated and slip (what the contacts took), and the works, the supply and the exchange
  /// as they were then: the flow since is the difference, the works by magnitude [J].
  double taken = 0, gravityWork = 0, wallWork = 0, supplied = 0, exchanged = 0;
  double held = 0;  ///< kinetic and stored energy [J]
};

/// The state at a check whose step came from the estimate, and its ledger then.
struct RollbackPoint {
  SimulationState state;
  LedgerReading ledger;
};

RollbackSlot::RollbackSlot() = default;
RollbackSlot::~RollbackSlot() = default;
RollbackSlot::RollbackSlot(const RollbackSlot&) noexcept {}
RollbackSlot& RollbackSlot::operator=(const RollbackSlot&) noexcept {
  return *this;
}
RollbackSlot::RollbackSlot(RollbackSlot&&) noexcept = default;
RollbackSlot& RollbackSlot::operator=(RollbackSlot&&) noexcept = default;

namespace {

/// A mode grows where the residual has risen since the point by more than this share of the
/// energy that flowed through the ledger meanwhile. A stable step leaves 0–7 % on the paper's
/// stage 2 (the trapezoid rule's error on the powers, and the impacts); a growing mode's
/// energy is created and mostly dissipated, 70–100 % (bench/RESULTS.md, "The growth watch").
constexpr double kGrowthShare = 0.5;
/// ... and by more than this fraction of the kinetic and stored energy held at the point, so
/// that a bed at rest, through which almost nothing flows, does not count its rounding.
constexpr double kGrowthFloor = 1e-3;
/// The step a growing mode is taken again at, against the one it grew at: the estimate of the
/// highest frequency is raised by 1 / kRetry.
constexpr double kRetry = 0.8;

LedgerReading readLedger(const SimulationState& s) {
  const EnergyBalance b = energyBalance(s);
  LedgerReading r;
  r.residual = b.total();
  r.taken = b.sum(EnergyKind::Dissipated) + b.sum(EnergyKind::Slip);
  r.gravityWork = b.gravityWork;
  r.wallWork = b.wallWork;
  r.supplied = b.sum(EnergyKind::Supplied);
  r.exchanged = b.exchanged;
  r.held = b.kinetic() + b.sum(EnergyKind::Stored);
  return r;
}

bool grewSince(const LedgerReading& then, const LedgerReading& now) {
  const double created = now.residual - then.residual;
  const double flow =
      std::abs(now.taken - then.taken) + std::abs(now.gravityWork - then.gravityWork) +
      std::abs(now.wallWork - then.wallWork) + std::abs(now.supplied - then.supplied) +
      std::abs(now.exchanged - then.exchanged);
  return created > kGrowthShare * flow && created > kGrowthFloor * then.held;
}

/// Replaces the state by the point's, keeping what is not the run's (the threads, the study
/// switches, the step control's cost, the call's start) and the counts of growth.
void returnTo(SimulationState& s, const RollbackPoint& point) {
  const int threads = s.config.threads;
  const ThreadGovernor governor = s.governor;
  const bool rebuildEveryStep = s.rebuildEveryStep, stepLimitDisabled = s.stepLimitDisabled;
  const double estimateScale = s.estimateScale;
  const studies::StepControlCost cost = s.stepControlCost;
  const std::uint64_t callStart = s.stepsAtCallStart;
  const std::uint64_t rollbacks = s.counters.rollbacks, keptGrowths = s.counters.keptGrowths;
  s = point.state;  // the slot keeps its point (RollbackSlot)
  s.config.threads = threads;
  s.governor = governor;
  s.rebuildEveryStep = rebuildEveryStep;
  s.stepLimitDisabled = stepLimitDisabled;
  s.estimateScale = estimateScale;
  s.stepControlCost = cost;
  s.stepsAtCallStart = callStart;
  s.counters.rollbacks = rollbacks;
  s.counters.keptGrowths = keptGrowths;
}

void keepPoint(SimulationState& s) {
  std::unique_ptr<RollbackPoint>& point = s.rollback.point;
  if (!point) point = std::make_unique<RollbackPoint>();
  point->state = s;  // reuses the point's arrays where they are large enough
  point->ledger = readLedger(s);
}

}  // namespace

SteppingCall::SteppingCall(SimulationState& s) : s_(s) {
  s.stepsAtCallStart = s.steps;
  if (s.config.step.automatic && s.stepCheck.estimated && s.stepsSinceCheck == 0) {
    keepPoint(s);
  } else if (s.rollback.point && s.rollback.point->state.steps >= s.steps) {
    s.rollback.point.reset();  // kept before something changed the state between calls
  }
}

SteppingCall::~SteppingCall() {
  s_.stepsAtCallStart = kBetweenCalls;
}

double recoverFromGrowth(SimulationState& s, const StepCheck& found) {
  RollbackPoint* point = s.rollback.point.get();
  if (!point || !grewSince(point->ledger, readLedger(s))) return 0.0;
  const double grew = targetStep(s);
  // The estimate is raised unless the step that grew is shortened anyway (the contacts strike
  // now, and the accuracy floor is back), and then only the first time on one calibration:
  // a floor that comes and goes must not hide an estimate that is too low.
  const bool shortened = found.chosenStep <= kRetry * grew;
  NetworkCalibration calibration = s.calibration;
  if (s.stepsAtCallStart != kBetweenCalls && point->state.steps >= s.stepsAtCallStart) {
    // The calibration of the steps that grew, unless this check calibrated again.
    if (calibration.boundOmega != point->state.calibration.boundOmega) {
      calibration = point->state.calibration;
    }
    returnTo(s, *point);
    ++s.counters.rollbacks;
  } else {
    ++s.counters.keptGrowths;  // the caller has seen the state since the point
  }
  if (!(shortened && calibration.rollbacks == 0)) {
    // Both, so that the damping ratio stays and the step shrinks by kRetry.
    calibration.omega /= kRetry;
    calibration.damping /= kRetry;
  }
  ++calibration.rollbacks;
  s.calibration = calibration;
  return kRetry * grew;
}

const SimulationState* rollbackState(const SimulationState& s) {
  return s.rollback.point ? &s.rollback.point->state : nullptr;
}

void keepRollbackPoint(SimulationState& s) {
  if (s.stepCheck.estimated) {
    keepPoint(s);
  } else {
    s.rollback.point.reset();  // the bound allows the step: nothing to return to
  }
}

}  // namespace granular
