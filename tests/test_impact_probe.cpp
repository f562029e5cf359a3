/// The two-sphere impact probe (impact_probe.hpp) and the convergence of both integrators on it,
/// against the closed forms of contact_theory (docs/validation.md §1): the orders expected from the
/// force's smoothness at first touch, measured as the worst error over several touch phases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "granular/impact_probe.hpp"

using namespace granular;

namespace {

constexpr Integrator kBoth[] = {Integrator::Gear5, Integrator::VelocityVerlet};
const char* name(Integrator i) {
  return i == Integrator::Gear5 ? "gear5" : "verlet";
}

PairImpactSpec hookeSpec() {
  return PairImpactSpec{};
}  // the paper's material, γn = 60 1/s

PairImpactSpec hertzSpec() {
  PairImpactSpec spec;
  spec.material.normalLaw = NormalLaw::Hertz;
  spec.material.normalDamping = 0.0;
  return spec;
}

struct WorstErrors {
  double restitution = 0;  ///< max over phases of |e - e_theory| / e_theory [-]
  double duration = 0;     ///< same for the overlap duration [-]
};

/// Worst relative errors against the closed form over `phases` touch phases at Δt = t_c/fraction.
WorstErrors worstErrors(PairImpactSpec spec, Integrator integrator, double fraction,
                        int phases = 6) {
  const ImpactPrediction theory = *predictPairImpact(spec);
  spec.integrator = integrator;
  spec.timeStep = theory.forceDuration / fraction;
  WorstErrors worst;
  for (int j = 0; j < phases; ++j) {
    spec.initialGap = gapForTouchPhase(spec, (j + 0.5) / phases);
    Simulation sim = makePairImpact(spec);
    const ImpactMeasurement m = measurePairImpact(sim, spec.approachSpeed, 1.0);
    EXPECT_TRUE(m.separated);
    worst.restitution = std::max(worst.restitution,
                                 std::abs(m.restitution - theory.restitution) / theory.restitution);
    worst.duration = std::max(worst.duration, std::abs(m.overlapDuration - theory.overlapDuration) /
                                                  theory.overlapDuration);
  }
  return worst;
}

/// Observed order p from errors at two steps: error ∝ Δt^p.
double order(double coarseError, double fineError, double refinement) {
  return std::log(coarseError / fineError) / std::log(refinement);
}

}  // namespace

TEST(ImpactProbe, ClosedFormOnlyWhereTheoryHasOne) {
  EXPECT_TRUE(predictPairImpact(hookeSpec()).has_value());
  EXPECT_TRUE(predictPairImpact(hertzSpec()).has_value());
  PairImpactSpec dampedHertz = hertzSpec();
  dampedHertz.material.normalDamping = 60.0;
  EXPECT_FALSE(predictPairImpact(dampedHertz).has_value());
}

TEST(ImpactProbe, TouchFallsInTheThirdStepAtTheAskedPhase) {
  PairImpactSpec spec = hookeSpec();
  spec.timeStep = predictPairImpact(spec)->forceDuration / 60;
  auto overlap = [](const Simulation& s) {
    const Particles& p = s.particles();
    return p.radius[0] + p.radius[1] - (p.position[1] - p.position[0]).norm();
  };
  for (double phase : {0.05, 0.5, 0.95}) {
    spec.initialGap = gapForTouchPhase(spec, phase);
    Simulation sim = makePairImpact(spec);
    sim.run(2);
    // Free flight so far: the gap left is v·Δt·phase, closed inside the third step.
    EXPECT_NEAR(overlap(sim), -spec.approachSpeed * spec.timeStep * phase,
                1e-9 * spec.approachSpeed * spec.timeStep)
        << "phase " << phase;
    sim.step();
    EXPECT_GT(overlap(sim), 0.0) << "phase " << phase;
  }
}

TEST(ImpactProbe, FineStepReproducesClosedForms) {
  for (Integrator i : kBoth) {
    for (const PairImpactSpec& spec : {hookeSpec(), hertzSpec()}) {
      const WorstErrors e = worstErrors(spec, i, 2000);
      EXPECT_LT(e.restitution, 1e-3) << name(i);
      EXPECT_LT(e.duration, 1e-3) << name(i);
    }
  }
}

TEST(ImpactProbe, DampedHookeRestitutionConvergesAtFirstOrder) {
  // The dashpot force c·v0 switches on inside a step at first touch: a jump no scheme resolves
  // better than O(Δt), whatever its formal order (Tuley et al. 2010; docs/validation.md §2).
  for (Integrator i : kBoth) {
    const WorstErrors coarse = worstErrors(hookeSpec(), i, 50);
    const WorstErrors fine = worstErrors(hookeSpec(), i, 200);
    const double p = order(coarse.restitution, fine.restitution, 4.0);
    EXPECT_GT(p, 0.7) << name(i);
    EXPECT_LT(p, 1.4) << name(i);
  }
}

TEST(ImpactProbe, UndampedHertzConvergesAtLeastAtSecondOrder) {
  // F = K h^(3/2) is continuous with a continuous first derivative at first touch, so the
  // second-order velocity Verlet keeps its order; Gear keeps at least that much.
  for (Integrator i : kBoth) {
    const WorstErrors coarse = worstErrors(hertzSpec(), i, 60);
    const WorstErrors fine = worstErrors(hertzSpec(), i, 240);
    const double pDuration = order(coarse.duration, fine.duration, 4.0);
    const double pRestitution = order(coarse.restitution, fine.restitution, 4.0);
    EXPECT_GT(pDuration, 1.7) << name(i);
    EXPECT_GT(pRestitution, 1.7) << name(i);
    if (i == Integrator::VelocityVerlet) {
      EXPECT_LT(pDuration, 2.5) << "velocity Verlet is a second-order scheme";
    }
  }
}
