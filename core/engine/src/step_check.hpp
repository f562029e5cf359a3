#pragma once
/// The step against the contact network (StepControl, docs/physics.md §2.16): a fixed step
/// refused or watched, an automatic one chosen; and the clock it runs.
#include "simulation_state.hpp"

namespace granular {

/// The time now: timeOrigin + stepsSinceOrigin·Δt [s].
double clockNow(const SimulationState& s);
/// The step asked for or chosen (StepControl), which a landing step may shorten [s].
double targetStep(const SimulationState& s);
/// The next step's Δt; the clock, timeOrigin + stepsSinceOrigin·Δt, is folded into its origin
/// first so that it runs on unbroken.
void changeStep(SimulationState& s, double dt);
/// A fixed step at the start, or after a change of step, integrator or material: refused
/// (ConfigError) above the network's step; with no contact yet, above the binary fallback,
/// which Gear5 keeps throughout. Returns the measurement it judged by.
StepCheck requireAllowedStep(const SimulationState& s, double dt, Integrator integrator);
/// The check of the step against the network: with step.automatic the step is chosen, else a
/// fixed step above the network's stops the run (NumericalError) or is counted.
void checkStep(SimulationState& s);
/// What the step that is running does about the step once corrected.
enum class StepReview {
  None,
  /// The contacts' motion alone (networkMotion), for a particle about to strike: it brings the
  /// accuracy floor back, with a check.
  Scan,
  Check,  ///< checkStep
};
/// What the step that is running does once corrected: a check after a rebuild, at most every 10
/// steps where the network sets an automatic step (a fixed step every 25: a settling bed
/// rebuilds every few steps), and at least every recheckSteps steps; with an automatic step its
/// floor sets, the network allowing 1.25 × more, at most every 25 (SimulationState::checkGap),
/// a Hertz one scanned at the rebuilds between; with one above its floor (stretched: no contact
/// an impact), at most every 25 steps and twice as far apart at each check that leaves it
/// within 1 % (checkGap), up to recheckSteps, and a scan at the rebuilds between.
StepReview stepCheckDue(const SimulationState& s, bool rebuilt);
/// The scan (StepReview::Scan): a check where the contacts' motion brings the floor below the
/// step, else nothing but the count of steps since the check.
void scanStep(SimulationState& s);

}  // namespace granular
