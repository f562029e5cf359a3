/// The integrators' stability on a damped oscillator x'' = −ω² x − 2ζω x', as they are
/// implemented (Gear5::predict/correct with c0 = 3/20, velocity Verlet with the dashpot at the
/// predicted velocity): one step is a linear map of the state (x, v, a[, x''', x'''', x''''']);
/// its spectral radius ρ (stepSpectralRadius, granular/network_step.hpp) says whether errors
/// grow. docs/physics.md §2.15 tabulates the largest stable ω Δt against ζ.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "granular/network_step.hpp"

using namespace granular;

namespace {

/// ρ of one step of `scheme` at ω Δt = `w` (ω = 1), damping ratio ζ.
double spectralRadius(Integrator scheme, double w, double zeta) {
  return stepSpectralRadius(scheme, w, zeta);
}

/// The largest ω Δt (to 10⁻³) below which ρ <= 1 + 10⁻⁹ throughout.
double stableLimit(Integrator scheme, double zeta) {
  double last = 0.0;
  for (double w = 1e-3; w < 4.0; w += 1e-3) {
    if (spectralRadius(scheme, w, zeta) > 1.0 + 1e-9) break;
    last = w;
  }
  return last;
}

}  // namespace

TEST(IntegratorStability, UndampedVerletIsStableUpToOmegaDtOfTwo) {
  // The central-difference limit: ω Δt < 2, with |eigenvalues| = 1 exactly below it.
  EXPECT_NEAR(stableLimit(Integrator::VelocityVerlet, 0.0), 2.0, 2e-3);
  EXPECT_NEAR(spectralRadius(Integrator::VelocityVerlet, 1.0, 0.0), 1.0, 1e-12);
}

TEST(IntegratorStability, DampingShrinksVerletsIntervalAsTheClosedFormSays) {
  // With the dashpot at the half-step velocity, p = Δt v_½ and x map by [[1, 1], [−w², 1 − c −
  // w²]] (w = ω Δt, c = 2ζw): det 1 − c, trace 2 − c − w², and the Jury conditions give
  // w < 2 (√(ζ² + 1) − ζ): strongly damped, the dashpot's own limit 2ζω Δt → 2.
  double previous = 2.0;
  for (double zeta : {0.1, 0.3, 0.5, 1.0, 2.0}) {
    const double limit = stableLimit(Integrator::VelocityVerlet, zeta);
    EXPECT_LT(limit, previous) << zeta;
    EXPECT_NEAR(limit, 2.0 * (std::sqrt(zeta * zeta + 1.0) - zeta), 2e-3) << zeta;
    previous = limit;
  }
}

TEST(IntegratorStability, GearHoldsADamperForRateTimesDtUpToAbout0163) {
  // The rule the engine's tangential-damping limit uses (docs/scenes.md): 2ζω Δt <= 0.163.
  for (double zeta : {0.5, 1.0, 2.0}) {
    const double limit = stableLimit(Integrator::Gear5, zeta);
    EXPECT_NEAR(2.0 * zeta * limit, 0.160, 0.006) << zeta;
  }
}

TEST(IntegratorStability, UndampedGearGrowsSlowlyAndTheStepOfTcOver50KeepsItNegligible) {
  // Gear's predictor-corrector is never exactly stable on an undamped oscillator: ρ exceeds 1 by
  // a power of ω Δt. At the paper's step (t_c/50, ω Δt = π/50) that is below 10⁻¹⁰ a step, so
  // 10⁵ steps grow an error by less than 10⁻⁵; at t_c/10 (ω Δt = π/10), 10⁻⁵ a step: e^0.6 over
  // 10⁵ steps.
  const double atTcOver50 = spectralRadius(Integrator::Gear5, std::numbers::pi / 50, 0.0) - 1.0;
  const double atTcOver10 = spectralRadius(Integrator::Gear5, std::numbers::pi / 10, 0.0) - 1.0;
  EXPECT_LT(atTcOver50, 1e-10);
  EXPECT_GT(atTcOver10, 1e-6);
  EXPECT_LT(atTcOver10, 1e-4);
}
