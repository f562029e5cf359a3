/// The closed forms of contact_theory against the paper's derived numbers (docs/physics.md §1) and
/// against a direct numerical solution of the contact ODE.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "granular/contact_theory.hpp"
#include "granular/error.hpp"

using namespace granular;

namespace {

/// RK4 on m ḧ = -max(0, k h + c ḣ) from h = 0, ḣ = v0, until h < 0 again.
ImpactPrediction integrateClampedHooke(double k, double gamma, double m, double v0) {
  const double c = gamma * m;
  auto accel = [&](double h, double hd) { return -std::max(0.0, k * h + c * hd) / m; };
  double h = 0, hd = v0, t = 0, forceEnd = -1, peak = 0;
  const double dt = 1e-7;
  while (true) {
    const double k1h = hd, k1v = accel(h, hd);
    const double k2h = hd + 0.5 * dt * k1v, k2v = accel(h + 0.5 * dt * k1h, hd + 0.5 * dt * k1v);
    const double k3h = hd + 0.5 * dt * k2v, k3v = accel(h + 0.5 * dt * k2h, hd + 0.5 * dt * k2v);
    const double k4h = hd + dt * k3v, k4v = accel(h + dt * k3h, hd + dt * k3v);
    h += dt / 6 * (k1h + 2 * k2h + 2 * k3h + k4h);
    hd += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    t += dt;
    peak = std::max(peak, h);
    if (forceEnd < 0 && hd < 0 && k * h + c * hd <= 0) forceEnd = t;
    if (h < 0) break;
  }
  return {forceEnd, t, -hd / v0, peak};
}

}  // namespace

TEST(ContactTheory, PaperDerivedNumbers) {
  const Material mat;  // the paper's Table, μ = 0
  const double rMean = 0.0325;
  // Mean mass over the uniform radius distribution: ρ 4/3 π <R³>, <R³> = (b⁴ - a⁴)/(4(b - a)).
  const double meanCube = (std::pow(0.035, 4) - std::pow(0.03, 4)) / (4 * 0.005);
  EXPECT_NEAR(mat.density * 4.0 / 3.0 * std::numbers::pi * meanCube, 0.0723, 0.0005);
  const double k = mat.normalCoefficient() * rMean / 2.0;  // mean pair, R_ij = R/2
  EXPECT_NEAR(k, 3.6e3, 0.05e3);
  const double m = 0.5 * mat.density * 4.0 / 3.0 * std::numbers::pi * std::pow(rMean, 3);
  const double omega0 = std::sqrt(k / m), beta = mat.normalDamping / 2;
  const double omegaD = std::sqrt(omega0 * omega0 - beta * beta);
  EXPECT_NEAR(std::numbers::pi / omegaD, 0.010, 0.0005);                 // unclamped duration
  EXPECT_NEAR(std::exp(-beta * std::numbers::pi / omegaD), 0.74, 0.01);  // unclamped restitution
  // The clamp ends the contact early and raises the restitution a little.
  const ImpactPrediction p = hookeDampedImpact(k, mat.normalDamping, m, 1.0);
  EXPECT_LT(p.forceDuration, std::numbers::pi / omegaD);
  EXPECT_GT(p.restitution, std::exp(-beta * std::numbers::pi / omegaD));
  EXPECT_LT(p.restitution, 0.80);
}

TEST(ContactTheory, ClampedHookeMatchesDirectIntegration) {
  for (double gamma : {0.0, 60.0, 300.0}) {
    const double k = 3.6e3, m = 0.036, v0 = 0.7;
    const ImpactPrediction closed = hookeDampedImpact(k, gamma, m, v0);
    const ImpactPrediction ode = integrateClampedHooke(k, gamma, m, v0);
    EXPECT_NEAR(closed.forceDuration, ode.forceDuration, 2e-7) << "gamma " << gamma;
    EXPECT_NEAR(closed.overlapDuration, ode.overlapDuration, 2e-7) << "gamma " << gamma;
    EXPECT_NEAR(closed.restitution, ode.restitution, 1e-5) << "gamma " << gamma;
    EXPECT_NEAR(closed.peakOverlap, ode.peakOverlap, 1e-8) << "gamma " << gamma;
  }
}

TEST(ContactTheory, OverDampedContactIsRefused) {
  EXPECT_THROW(hookeDampedImpact(1.0, 100.0, 1.0, 1.0), ConfigError);
}

TEST(ContactTheory, HertzMatchesTextbookForm) {
  // 2.87 (m*² / (R* E*² v))^(1/5) with F = (4/3) E* sqrt(R*) h^(3/2).
  const double eStar = 1.0e6, rStar = 0.02, mStar = 0.05, v = 0.8;
  const double K = 4.0 / 3.0 * eStar * std::sqrt(rStar);
  const ImpactPrediction p = hertzUndampedImpact(K, mStar, v);
  EXPECT_NEAR(p.forceDuration / (2.87 * std::pow(mStar * mStar / (rStar * eStar * eStar * v), 0.2)),
              1.0, 0.002);
  EXPECT_NEAR(p.peakOverlap, std::pow(15 * mStar * v * v / (16 * eStar * std::sqrt(rStar)), 0.4),
              1e-12);
}

TEST(ContactTheory, StiffestContactIsTheSmallestParticle) {
  Material mat;
  const ContactScale small = stiffestContact(mat, 0.03, 1.0);
  const ContactScale large = stiffestContact(mat, 0.035, 1.0);
  EXPECT_LT(small.duration, large.duration);
  mat.normalLaw = NormalLaw::Hertz;
  // Hertz: the pair of equal spheres (R/2, m/2) is shorter than the sphere on a wall.
  EXPECT_FALSE(stiffestContact(mat, 0.03, 1.0).againstWall);
  EXPECT_GT(stiffestContact(mat, 0.03, 0.1).duration, stiffestContact(mat, 0.03, 1.0).duration);
}
