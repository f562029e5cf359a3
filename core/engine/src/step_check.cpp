/// The step against the contact network (StepControl, docs/physics.md §2.16): a fixed step
/// refused or watched, an automatic one chosen; and the clock it runs.
#include "step_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "config_validation.hpp"
#include "granular/error.hpp"
#include "network_bound.hpp"
#include "rollback.hpp"

namespace granular {
namespace {

/// The fewest steps between two checks of the step that a rebuild starts.
/// An automatic step follows the contacts closely; a fixed one is only watched, at less cost
/// (every impact of a Gear5 step at t_c/50 spans two such checks).
constexpr std::uint64_t kStepsBetweenChecks = 10, kStepsBetweenFixedChecks = 25;

/// The longest step an impact of the contact `scale` may take with `integrator`: t_c / N, and
/// for Gear5 its binary limit (t_c/50) where that is shorter: contacts that open and close
/// inside a step kick its higher derivatives, and beds gain energy above t_c/40
/// (bench/RESULTS.md, "Gear in a bed").
double impactStep(const SimulationState& s, Integrator integrator, const ContactScale& scale) {
  const double floor = scale.duration / s.config.step.contactResolution;
  return integrator == Integrator::Gear5 ? std::min(floor, maxStableStep(scale, integrator))
                                         : floor;
}

/// Whether `dt` [s] lies above the accuracy floor at the expected impact speed: an automatic
/// step there is stretched (its contacts move with the network, no impact).
bool aboveFloor(const SimulationState& s, double dt) {
  return dt > impactStep(s, s.config.integrator, s.contactScale);
}

/// A check leaves an automatic step still where it moves it by no more than this fraction: the
/// checks at rebuilds then come further apart (nextCheckGap).
constexpr double kStillStep = 0.01;

/// An automatic step its floor sets is checked as seldom as a fixed one where the network
/// allows this many times the floor (nextCheckGap): a contact that forms between two checks
/// stiffens the network by less.
constexpr double kFloorMargin = 1.25;

/// Contacts whose relative motion holds less kinetic energy than this fraction of what their
/// springs store move with the network: no impact.
constexpr double kSlowMotion = 0.01;

/// The energy the contacts' springs store now (the Stored accounts of the last force pass) [J].
double storedEnergy(const SimulationState& s) {
  double stored = 0.0;
  for (std::size_t slot = 0; slot < kEnergySlots; ++slot) {
    if (kEnergySlotTable[slot].kind == EnergyKind::Stored) stored += s.powers.energy[slot];
  }
  return stored;
}

/// The accuracy floor of the stiffest contact (impactStep: t_c / N, Gear5's t_c/50), from what
/// the check `f` measured: a Hertz contact is shorter at a higher speed, so the floor follows
/// the run's fastest approach wherever it exceeds the expected one (config.impactSpeed);
/// Hooke's does not depend on it. The floor is for impacts: where the kinetic energy of the
/// contacts' relative motion K is under kSlowMotion of the energy E their springs store, the
/// contacts move with the network, whose step governs, and the floor stretches as
/// kSlowMotion E / K (to +∞ at rest): an impact misses energy first order in the step and in
/// proportion to its own, so what the impacts miss stays what they would at the threshold
/// (docs/physics.md §2.16). Gear5's binary limit stretches with it: it is for contacts that
/// open and close inside a step, and the network's own interval for Gear5 (§2.15, the damping
/// that made beds gain energy above t_c/40) bounds the step wherever the floor does not.
double accuracyFloor(const SimulationState& s, Integrator integrator, const NetworkFrequency& f,
                     double stored) {
  const bool faster =
      s.config.material.normalLaw == NormalLaw::Hertz && f.fastestApproach > s.config.impactSpeed;
  const ContactScale scale =
      faster ? stiffestContact(s.config.material, s.contactScale.radius, f.fastestApproach)
             : s.contactScale;
  double floor = impactStep(s, integrator, scale);
  const double slow = kSlowMotion * stored, moving = f.relativeKinetic;
  if (f.contacts > 0 && moving < slow) {
    floor = moving > 0.0 ? floor * (slow / moving) : std::numeric_limits<double>::infinity();
  }
  return floor;
}

/// How far ahead a contact about to form counts [s]: those that form within two check intervals.
/// An automatic step may grow to its floor at the expected speed before the next check, so the
/// interval is measured in that, or in the step `dt` it takes where that is longer (the floor
/// stretched: no contact an impact).
double lookaheadOf(const SimulationState& s, Integrator integrator, double dt) {
  const StepControl& control = s.config.step;
  const double longest =
      control.automatic ? std::max(dt, accuracyFloor(s, integrator, NetworkFrequency{}, 0.0)) : dt;
  return 2.0 * static_cast<double>(control.recheckSteps) * longest;
}

/// How far the bound may move from its calibration's before the estimate is made again.
constexpr double kCalibratedOmega = 0.05, kCalibratedDamping = 0.10;

/// Whether `c` holds for the bound `f`: made, and the bound within its reach since.
bool calibrated(const NetworkCalibration& c, const NetworkFrequency& f) {
  if (!(c.boundOmega > 0.0) || !(c.omega > 0.0)) return false;
  if (std::abs(f.omegaMax / c.boundOmega - 1.0) > kCalibratedOmega) return false;
  if (!(c.boundDamping > 0.0)) return f.dampingRate == 0.0;
  return std::abs(f.dampingRate / c.boundDamping - 1.0) <= kCalibratedDamping;
}

/// The estimate's ω_max and Γ for the bound `f` (NetworkCalibration), calibrated again in `c`
/// where it does not hold. A cold Lanczos start each time: what it gives depends on the state
/// alone, so that a resumed run and a split one choose the same steps.
NetworkFrequency estimated(const SimulationState& s, const NetworkFrequency& f, double lookahead,
                           NetworkCalibration& c) {
  if (!calibrated(c, f)) {
    const NetworkSpectrum e = networkSpectrumEstimate(s, lookahead, f, nullptr, 40, 1e-2);
    c.boundOmega = f.omegaMax;
    c.boundDamping = f.dampingRate;
    c.omega = e.omegaMax;
    c.damping = e.dampingRate;
  }
  NetworkFrequency g = f;
  const double omega = s.estimateScale * c.omega, damping = s.estimateScale * c.damping;
  if (c.omega > 0.0) g.omegaMax = std::min(f.omegaMax, f.omegaMax * (omega / c.boundOmega));
  if (c.boundDamping > 0.0) {
    g.dampingRate = std::min(f.dampingRate, f.dampingRate * (damping / c.boundDamping));
  }
  g.dampingRatio = g.omegaMax > 0.0 ? g.dampingRate / (2.0 * g.omegaMax) : 0.0;
  return g;
}

/// The network's stable step for `integrator` now, counting the contacts that may form within
/// two check intervals at step `dt` (docs/physics.md §2.16), and the accuracy floor. Where the
/// bound refuses what is needed (the step asked for, or the floor an automatic step would
/// take), the step comes from the estimate (NetworkCalibration) kept in `calibration` (null:
/// made for this check alone), for either integrator at its own interval (§2.15).
StepCheck measureStep(const SimulationState& s, Integrator integrator, double dt,
                      NetworkCalibration* calibration) {
  const StepControl& control = s.config.step;
  const double lookahead = lookaheadOf(s, integrator, dt);
  StepCheck c;
  const double stored = storedEnergy(s);
  // The power sweeps only tighten the bound, so they stop once it allows what is needed: a
  // fixed step, or kFloorMargin × the accuracy floor an automatic step cannot exceed anyway
  // (with no contact an impact, the 8 sweeps' bound: the floor is then lifted; the margin lets
  // the checks of a step its floor sets come further apart, nextCheckGap). An automatic step
  // takes at most 8 sweeps (within 1.5 % of 32 on the paper's beds, at a fifth of the cost), a
  // fixed one 32 before it is judged above the network's.
  const NetworkFrequency f = networkFrequencyBound(
      s, control.automatic ? 8 : 32, lookahead, [&](const NetworkFrequency& g) {
        const double needed =
            control.automatic
                ? kFloorMargin * accuracyFloor(s, integrator, g, stored) / control.safety
                : dt;
        return needed <= networkStepOf(integrator, g);
      });
  c.approachSpeed = f.fastestApproach;
  c.accuracyStep = accuracyFloor(s, integrator, f, stored);
  c.time = clockNow(s);
  c.particle = f.particle;
  c.contacts = f.contacts + f.approaching;
  const double needed = control.automatic ? c.accuracyStep / control.safety : dt;
  NetworkFrequency used = f;
  if (c.contacts > 0 && needed > networkStepOf(integrator, f)) {
    NetworkCalibration alone;
    used = estimated(s, f, lookahead, calibration ? *calibration : alone);
    c.estimated = true;
  }
  c.omegaMax = used.omegaMax;
  c.dampingRatio = used.dampingRatio;
  c.networkStep = networkStepOf(integrator, used);
  c.chosenStep = control.automatic ? std::min(control.safety * c.networkStep, c.accuracyStep) : dt;
  return c;
}

/// Why `dt` is above the network's step `c` (a fixed step's refusal or stop).
std::string aboveNetworkStep(double dt, const StepCheck& c, Integrator integrator) {
  const bool gear = integrator == Integrator::Gear5;
  std::ostringstream msg;
  msg.precision(4);
  msg << "the time step " << dt << " s is above the step the contact network allows, "
      << c.networkStep << " s (" << dt / c.networkStep
      << " × it): " << (gear ? "gear5" : "velocity Verlet")
      << " is stable for ω Δt <= " << c.networkStep * c.omegaMax
      << " at the network's damping ratio " << c.dampingRatio
      << " (physics.md §2.15), and the network's highest frequency is "
      << (c.estimated ? "about " : "at most ") << c.omegaMax << " rad/s ("
      << (c.estimated ? "estimated" : "bounded") << " from " << c.contacts << " contacts; particle "
      << c.particle << "'s row sets the bound)";
  return msg.str();
}

/// The fewest steps from this check to the next at a rebuild (SimulationState::checkGap) for
/// the automatic step `c` chose, which follows `before`.
/// - Above its floor: twice the last, up to the longest run between checks, where the step stays
///   within kStillStep of the last check's; else the least. A still step changes slowly: the
///   network it follows moves little between checks (the paper's stage 2: its bound by 0.6 %
///   over the stage). An impact still brings a check at the next rebuild through the scan, a
///   growing mode is still undone (the point is kept at each check, however far apart).
/// - Set by its floor, the network allowing kFloorMargin × more: a fixed step's gap,
///   kStepsBetweenFixedChecks. The floor holds the step still while the contacts strike (a
///   settling bed rebuilds its list every few steps, and a check at every tenth step took
///   12-16 % of the paper's runs); the scan at each rebuild still brings a check where an
///   approach faster than the last check's shortens the floor (Hertz), and a contact that
///   forms meanwhile stiffens the network by less than the margin.
/// - Set by the network, or its floor within the margin of it: the least.
std::uint64_t nextCheckGap(const SimulationState& s, const StepCheck& c, double before) {
  const StepControl& control = s.config.step;
  const double chosen = c.chosenStep;
  if (!aboveFloor(s, chosen)) {
    const bool margin =
        chosen == c.accuracyStep && control.safety * c.networkStep >= kFloorMargin * chosen;
    return margin ? kStepsBetweenFixedChecks : 0;
  }
  if (!(before > 0.0) || !(std::abs(chosen / before - 1.0) <= kStillStep)) return 0;
  return std::min(2 * std::max(s.checkGap, kStepsBetweenFixedChecks), control.recheckSteps);
}

}  // namespace

double targetStep(const SimulationState& s) {
  return s.targetStep > 0.0 ? s.targetStep : s.config.timeStep;
}

void changeStep(SimulationState& s, double dt) {
  if (dt == s.config.timeStep) return;
  s.timeOrigin += static_cast<double>(s.stepsSinceOrigin) * s.config.timeStep;
  s.stepsSinceOrigin = 0;
  s.config.timeStep = dt;
}

double clockNow(const SimulationState& s) {
  return s.timeOrigin + static_cast<double>(s.stepsSinceOrigin) * s.config.timeStep;
}

StepCheck requireAllowedStep(const SimulationState& s, double dt, Integrator integrator) {
  const StepCheck c = measureStep(s, integrator, dt, nullptr);
  if (c.contacts == 0 || integrator == Integrator::Gear5) {
    // Nothing to bound yet: the stiffest binary contact's fraction, set from the worst bed
    // measured (bench/RESULTS.md, "Gear in a bed"), stands in until contacts form.
    requireStableStep(dt, s.contactScale, integrator);
    requireStableTangentialDamping(s.config.material, dt, integrator);
    if (c.contacts == 0) return c;
  }
  if (!(dt <= c.networkStep)) {
    throw TimeStepError(aboveNetworkStep(dt, c, integrator) + "; use at most " +
                        shortNumber(c.networkStep) + " s, or time_step = \"auto\"");
  }
  return c;
}

void checkStep(SimulationState& s) {
  s.stepsSinceCheck = 0;
  ++s.counters.stepChecks;
  const double target = targetStep(s);
  const double calibratedAt = s.calibration.boundOmega;
  StepCheck c = measureStep(s, s.config.integrator, target, &s.calibration);
  if (s.calibration.boundOmega != calibratedAt) ++s.stepControlCost.calibrations;

  if (s.config.step.automatic) {
    if (!(c.chosenStep > 0.0) || !std::isfinite(c.chosenStep)) {
      std::ostringstream msg;
      msg << "step " << s.steps << " (t = " << c.time << " s): the contact network allows no "
          << "step (its bound: " << c.omegaMax << " rad/s at damping ratio " << c.dampingRatio
          << ", particle " << c.particle << "); the run stops";
      throw NumericalError(msg.str());
    }
    const double before = targetStep(s);
    const double longest = recoverFromGrowth(s, c);
    if (longest > 0.0) {
      // The state may be the point's now, the estimate raised: the step is measured again, and
      // the shortest taken.
      const StepCheck again = measureStep(s, s.config.integrator, targetStep(s), &s.calibration);
      const double step = std::min({c.chosenStep, again.chosenStep, longest});
      c = again;
      c.chosenStep = step;
    }
    s.stepCheck = c;
    s.counters.fastestApproach = std::max(s.counters.fastestApproach, c.approachSpeed);
    s.checkGap = longest > 0.0 ? 0 : nextCheckGap(s, c, before);
    s.targetStep = c.chosenStep;
    changeStep(s, c.chosenStep);
    keepRollbackPoint(s);
    return;
  }
  s.stepCheck = c;
  s.counters.fastestApproach = std::max(s.counters.fastestApproach, c.approachSpeed);
  if (s.stepLimitDisabled || c.contacts == 0 || target <= c.networkStep) return;
  if (s.config.step.onUnstable == OnUnstable::Warn) {
    ++s.counters.unstableChecks;
    s.counters.worstStepRatio = std::max(s.counters.worstStepRatio, target / c.networkStep);
    return;
  }
  std::ostringstream msg;
  msg.precision(9);
  msg << "step " << s.steps << " (t = " << c.time
      << " s): " << aboveNetworkStep(target, c, s.config.integrator)
      << "; the run stops before it gains energy (on_unstable = \"stop\"): use a smaller "
         "time_step, time_step = \"auto\", or on_unstable = \"warn\"";
  throw NumericalError(msg.str());
}

StepReview stepCheckDue(const SimulationState& s, bool rebuilt) {
  const std::uint64_t since = s.stepsSinceCheck + 1;
  const StepControl& control = s.config.step;
  if (!control.automatic && s.stepLimitDisabled) return StepReview::None;
  // An automatic step above its floor (stretched: the contacts move with the network, which
  // changes slowly) is checked at a rebuild as seldom as a fixed one, and the more seldom the
  // longer it holds still (checkGap); it looks at the rebuilds between whether the new list
  // holds a particle about to strike, which brings the floor back before it touches. One that
  // its floor sets is checked as a fixed one (checkGap again).
  const bool stretched = control.automatic && aboveFloor(s, s.config.timeStep);
  const std::uint64_t gap = !control.automatic ? kStepsBetweenFixedChecks
                            : stretched        ? std::max(s.checkGap, kStepsBetweenFixedChecks)
                                               : std::max(s.checkGap, kStepsBetweenChecks);
  if (since >= control.recheckSteps || (rebuilt && since >= gap)) return StepReview::Check;
  // A Hertz floor is shorter at a faster approach: one its floor sets is scanned too.
  const bool hertz = s.config.material.normalLaw == NormalLaw::Hertz;
  const bool scanned = control.automatic && (stretched || (hertz && s.checkGap > 0));
  return rebuilt && scanned ? StepReview::Scan : StepReview::None;
}

void scanStep(SimulationState& s) {
  const Integrator integrator = s.config.integrator;
  const NetworkFrequency f = networkMotion(s, lookaheadOf(s, integrator, targetStep(s)));
  if (accuracyFloor(s, integrator, f, storedEnergy(s)) < targetStep(s)) {
    checkStep(s);
    return;
  }
  ++s.stepsSinceCheck;
}

}  // namespace granular
