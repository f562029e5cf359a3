#pragma once
/// The growth watch and the rollback (docs/physics.md §2.16). An automatic step taken from the
/// spectrum's estimate rather than the bound (StepCheck::estimated) may lie above the network's
/// real edge: Lanczos approaches the highest frequency from below. So each check that chooses
/// such a step keeps the state as a point to return to, and the next check reads the energy
/// ledger: where it finds a growing mode, the state returns to the point and the steps since
/// are taken again at a shorter step. A growing mode creates energy, which shows in the ledger's
/// residual (EnergyBalance::total) long before it shows in a stress.
#include <cstdint>
#include <limits>
#include <memory>

namespace granular {

struct SimulationState;
struct StepCheck;
struct RollbackPoint;

/// SimulationState::stepsAtCallStart outside a stepping call.
inline constexpr std::uint64_t kBetweenCalls = std::numeric_limits<std::uint64_t>::max();

/// Holds a state's RollbackPoint. A point belongs to the state that kept it: a copy of the
/// state (a point itself, wholeState) starts without one, and a state assigned another's (the
/// return to a point) keeps its own.
class RollbackSlot {
 public:
  RollbackSlot();
  ~RollbackSlot();
  RollbackSlot(const RollbackSlot&) noexcept;
  RollbackSlot& operator=(const RollbackSlot&) noexcept;
  RollbackSlot(RollbackSlot&&) noexcept;
  RollbackSlot& operator=(RollbackSlot&&) noexcept;

  std::unique_ptr<RollbackPoint> point;
};

/// The span of a stepping call (Simulation::run, runBefore, advanceTo): a growing mode found
/// inside it may return to a point kept within it or at its start, never to one before, since
/// the caller has seen the state since (a sample written is never undone); one found between
/// calls (a setter's check) returns to none. At its start, where the state is at a check that
/// chose a step from the estimate (one that ended the last call, or a setter's), that check's
/// point is kept again: the same point a run restored from a checkpoint there keeps, so that
/// both go on alike.
class SteppingCall {
 public:
  explicit SteppingCall(SimulationState& s);
  ~SteppingCall();
  SteppingCall(const SteppingCall&) = delete;
  SteppingCall& operator=(const SteppingCall&) = delete;

 private:
  SimulationState& s_;
};

/// At a check of an automatic step, once `found` is measured (collective in a split run):
/// whether the ledger shows a growing mode since the point kept at the last check. If it does,
/// the state returns to the point where this call may (counted in StepCounters::rollbacks),
/// else it stays (StepCounters::keptGrowths); either way the spectrum's estimate is raised for
/// the steps to come (NetworkCalibration::rollbacks) unless `found` already shortens the step
/// that grew. Returns the longest step to take from there, 0.8 × the step that grew (so that
/// the steps shrink even where the estimate has reached the bound); 0, changing nothing, where
/// no mode grew.
double recoverFromGrowth(SimulationState& s, const StepCheck& found);

/// The state kept to return to; null where none is.
const SimulationState* rollbackState(const SimulationState& s);

/// After a check of an automatic step has chosen it: the state kept as the point to return to
/// where the step came from the estimate; none is needed where the bound allows it.
void keepRollbackPoint(SimulationState& s);

}  // namespace granular
