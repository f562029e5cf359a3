/// Binary impacts against the closed forms of contact_theory (docs/validation.md §1): Hooke with
/// damping and the no-pull clamp, Hertz without damping, sphere on a wall, and an oblique
/// frictional impact against rigid-body impulse theory. Each at two time steps, for both
/// integrators.
#include <gtest/gtest.h>

#include <cmath>

#include "granular/contact_theory.hpp"
#include "granular/simulation.hpp"
#include "physics_fixtures.hpp"

using namespace granular;
using granular::testing::measureImpact;
using granular::testing::sphereMass;

namespace {

constexpr double kRadius = 0.03;  // the paper's smallest particle [m]

struct Case {
  Integrator integrator;
  const char* name;
};
const Case kIntegrators[] = {{Integrator::Gear5, "gear5"}, {Integrator::VelocityVerlet, "verlet"}};

/// Two equal spheres approaching head-on along x at relative speed v (no gravity).
Simulation headOnPair(const Material& mat, Integrator integrator, double dt, double v) {
  Particles p;
  p.add(Vec3(-kRadius - 1e-4, 0, 0), kRadius, mat.density, Vec3(0.5 * v, 0, 0));
  p.add(Vec3(kRadius + 1e-4, 0, 0), kRadius, mat.density, Vec3(-0.5 * v, 0, 0));
  SimulationConfig cfg;
  cfg.material = mat;
  cfg.gravity = Vec3::Zero();
  cfg.integrator = integrator;
  cfg.timeStep = dt;
  cfg.impactSpeed = v;
  return Simulation(std::move(p), {}, cfg);
}

double pairOverlap(const Simulation& s) {
  const Particles& p = s.particles();
  return p.radius[0] + p.radius[1] - (p.position[1] - p.position[0]).norm();
}

}  // namespace

TEST(Impact, HookeDampedPairMatchesClampedClosedForm) {
  const Material mat;  // paper's material, γn = 60 1/s
  const double v = 0.5;
  const double m = sphereMass(kRadius, mat.density);
  const ImpactPrediction expect =
      hookeDampedImpact(mat.normalCoefficient() * kRadius / 2, mat.normalDamping, m / 2, v);
  for (const Case& c : kIntegrators) {
    double previousError = 1e9;
    for (double fraction : {50.0, 400.0}) {
      Simulation sim = headOnPair(mat, c.integrator, expect.forceDuration / fraction, v);
      const auto got = measureImpact(sim, pairOverlap, 0.5 * v, 1, Vec3::UnitX(), 0.1);
      const double eErr = std::abs(got.restitution - expect.restitution) / expect.restitution;
      const double tErr =
          std::abs(got.overlapDuration - expect.overlapDuration) / expect.overlapDuration;
      // The force jumps to c·v0 at first touch and kinks at the clamp, so both schemes are
      // first order here: the error must shrink with Δt and be ~1/fraction.
      EXPECT_LT(eErr, 0.25 / fraction) << c.name << " dt = t_c/" << fraction;
      EXPECT_LT(tErr, 0.25 / fraction) << c.name << " dt = t_c/" << fraction;
      EXPECT_NEAR(got.peakOverlap, expect.peakOverlap, 0.25 / fraction * expect.peakOverlap);
      EXPECT_LT(eErr + tErr, previousError) << c.name;
      previousError = eErr + tErr;
    }
  }
}

TEST(Impact, HertzUndampedPairMatchesHertzTheory) {
  Material mat;
  mat.normalLaw = NormalLaw::Hertz;
  mat.normalDamping = 0.0;
  const double v = 0.5;
  const double m = sphereMass(kRadius, mat.density);
  const double hertzK = mat.normalCoefficient() * std::sqrt(kRadius / 2);
  const ImpactPrediction expect = hertzUndampedImpact(hertzK, m / 2, v);
  for (const Case& c : kIntegrators) {
    double previousError = 1e9;
    for (double fraction : {50.0, 400.0}) {
      Simulation sim = headOnPair(mat, c.integrator, expect.forceDuration / fraction, v);
      const auto got = measureImpact(sim, pairOverlap, 0.5 * v, 1, Vec3::UnitX(), 0.1);
      const double tErr =
          std::abs(got.overlapDuration - expect.overlapDuration) / expect.overlapDuration;
      const double hErr = std::abs(got.peakOverlap - expect.peakOverlap) / expect.peakOverlap;
      EXPECT_LT(tErr, 0.05 / fraction) << c.name << " dt = t_c/" << fraction;
      EXPECT_LT(hErr, 0.05 / fraction) << c.name << " dt = t_c/" << fraction;
      EXPECT_NEAR(got.restitution, 1.0, 0.05 / fraction) << c.name;  // no damping: elastic
      EXPECT_LT(tErr + hErr, previousError) << c.name;
      previousError = tErr + hErr;
    }
  }
}

TEST(Impact, SphereOnWallMatchesClosedForm) {
  // The wall is a body of infinite radius and mass: R_ij = R, m_ij = m.
  const Material mat;
  const double v = 0.4;
  const double m = sphereMass(kRadius, mat.density);
  const ImpactPrediction expect =
      hookeDampedImpact(mat.normalCoefficient() * kRadius, mat.normalDamping, m, v);
  for (const Case& c : kIntegrators) {
    Particles p;
    p.add(Vec3(0, 0, kRadius + 1e-4), kRadius, mat.density, Vec3(0, 0, -v));
    SimulationConfig cfg;
    cfg.material = mat;
    cfg.gravity = Vec3::Zero();
    cfg.integrator = c.integrator;
    cfg.timeStep = expect.forceDuration / 400;
    Wall floor{"bottom", Vec3::Zero(), Vec3::UnitZ()};
    Simulation sim(std::move(p), {floor}, cfg);
    auto overlap = [](const Simulation& s) {
      return s.particles().radius[0] - s.particles().position[0].z();
    };
    const auto got = measureImpact(sim, overlap, v, 0, Vec3::UnitZ(), 0.1);
    EXPECT_NEAR(got.restitution, expect.restitution, 0.005 * expect.restitution) << c.name;
    EXPECT_NEAR(got.overlapDuration, expect.overlapDuration, 0.005 * expect.overlapDuration)
        << c.name;
  }
}

TEST(Impact, ObliqueFrictionalImpactFollowsImpulseTheory) {
  // Gross sliding throughout the contact: the tangential impulse is μ times the normal one, so
  //   Δv_t = -μ (v_n,in + v_n,out),   Δω = R μ m (v_n,in + v_n,out) / I.
  // A stiff material keeps the overlap (and so the lever arm R - h/2) within 0.2 % of R.
  Material mat;
  mat.youngModulus *= 100;
  mat.shearModulus *= 100;
  mat.friction = 0.3;
  const double vn = 0.5, vt = 2.0;  // vt > 3.5 μ (1+e) vn: sliding never stops
  for (const Case& c : kIntegrators) {
    Particles p;
    p.add(Vec3(0, 0, kRadius + 1e-4), kRadius, mat.density, Vec3(vt, 0, -vn));
    SimulationConfig cfg;
    cfg.material = mat;
    cfg.gravity = Vec3::Zero();
    cfg.integrator = c.integrator;
    cfg.timeStep = stiffestContact(mat, kRadius, 1.0).duration / 200;
    Wall floor{"bottom", Vec3::Zero(), Vec3::UnitZ()};
    Simulation sim(std::move(p), {floor}, cfg);
    auto overlap = [](const Simulation& s) {
      return s.particles().radius[0] - s.particles().position[0].z();
    };
    const auto got = measureImpact(sim, overlap, vn, 0, Vec3::UnitZ(), 0.1);
    const double normalImpulse = vn + got.velocityAfter.z();  // per unit mass
    ASSERT_GT(got.velocityAfter.z(), 0.0) << c.name;
    EXPECT_NEAR(got.velocityAfter.x(), vt - mat.friction * normalImpulse,
                0.005 * mat.friction * normalImpulse)
        << c.name;
    // I = (2/5) m R², so Δω_y = (5/2) μ J / (m R); +y spin is rolling for +x motion.
    const double expectSpin = 2.5 * mat.friction * normalImpulse / kRadius;
    EXPECT_NEAR(got.angularVelocityAfter.y(), expectSpin, 0.005 * expectSpin) << c.name;
    EXPECT_NEAR(got.angularVelocityAfter.x(), 0.0, 1e-9);
    EXPECT_NEAR(got.velocityAfter.y(), 0.0, 1e-12);
  }
}
