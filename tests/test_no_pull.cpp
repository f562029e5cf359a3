/// The no-pull clamp switched off (Material::noPull, scene key material.no_pull): the normal
/// force may pull while overlapping spheres separate, as in codes that allow it. Checked
/// against the damped oscillator's closed form, the energy balance and the Coulomb limit μ|F_n|.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "granular/checkpoint.hpp"
#include "granular/impact_probe.hpp"
#include "physics_fixtures.hpp"

using namespace granular;

TEST(EnergyNoPull, HookeImpactRunsTheDampedOscillatorUntilTheOverlapCloses) {
  // Two of the paper's smallest spheres meet head-on at 0.5 m/s, γn = 60 1/s. With the clamp
  // the force ends when k h + c ḣ reaches 0 (restitution 0.770); without it the oscillation
  // h = (v0/ωd) e^(−βt) sin(ωd t) runs to h = 0 at π/ωd, the dashpot pulling at the end:
  // restitution e^(−βπ/ωd) = 0.758. At t_c/400 both match their closed forms to 1e-3, and the
  // balance holds: the pull's extra dissipation is in the normal dashpot's column. Clamped, the
  // force is continuous at the separation and the balance closes to 1e-5 of the kinetic energy;
  // pulling, it jumps there from γn m ḣ to 0, an error of first order, at most γn Δt.
  double restitution[2] = {};
  for (bool noPull : {true, false}) {
    PairImpactSpec spec;
    spec.material.noPull = noPull;
    const ImpactPrediction expect = *predictPairImpact(spec);
    spec.timeStep = expect.forceDuration / 400;
    Simulation sim = makePairImpact(spec);
    const double start = sim.energy().total(), kinetic = sim.kineticEnergy();
    const ImpactMeasurement m = measurePairImpact(sim, spec.approachSpeed, 0.1);
    ASSERT_TRUE(m.separated);
    const std::string what = noPull ? "clamped" : "pulling";
    EXPECT_NEAR(m.restitution, expect.restitution, 1e-3 * expect.restitution) << what;
    EXPECT_NEAR(m.overlapDuration, expect.overlapDuration, 1e-3 * expect.overlapDuration) << what;
    const double tolerance = noPull ? 1e-5 : spec.material.normalDamping * spec.timeStep;
    EXPECT_LT(std::abs(sim.energy().total() - start), tolerance * kinetic) << what;
    EXPECT_NEAR(sim.energy().of("dissipated_normal_J"),
                kinetic * (1 - m.restitution * m.restitution), tolerance * kinetic)
        << what;
    restitution[noPull ? 0 : 1] = m.restitution;
  }
  // The closed form without the clamp, from k = κ R/2 and m* = m/2 directly.
  const PairImpactSpec spec;
  const double k = spec.material.normalCoefficient() * pairReducedRadius(spec);
  const double beta = 0.5 * spec.material.normalDamping;
  const double omegaD = std::sqrt(k / pairReducedMass(spec) - beta * beta);
  EXPECT_NEAR(restitution[1], std::exp(-beta * std::numbers::pi / omegaD), 1e-3);
  EXPECT_GT(restitution[0], restitution[1] + 0.005);  // the clamp spares the end's dissipation
}

TEST(EnergyNoPull, SlidingWhilePullingIsStillFriction) {
  // An oblique impact that slides throughout (tangential 2 m/s, normal 0.5 m/s, μ = 0.3): the
  // Coulomb limit is μ |F_n| when F_n pulls, and the friction force opposes the slip at every
  // step (with μ F_n < 0 as the limit it would push the spheres along their slip).
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.material.noPull = false;
  cfg.gravity = Vec3::Zero();
  cfg.threads = 1;
  cfg.timeStep = stiffestContact(cfg.material, 0.03, 1.0).duration / 200;
  Particles p;
  p.add(Vec3(-0.03005, 0, 0), 0.03, cfg.material.density, Vec3(0.25, 1.0, 0));
  p.add(Vec3(0.03005, 0, 0), 0.03, cfg.material.density, Vec3(-0.25, -1.0, 0));
  Simulation sim(std::move(p), {}, cfg);
  const double start = sim.energy().total(), kinetic = sim.kineticEnergy();
  int pulling = 0, steps = 0;
  while (sim.time() < 0.02) {
    sim.step();
    sim.forEachContact([&](const ContactView& c) {
      if (c.particle != 0) return;
      const Particles& q = sim.particles();
      const Vec3 n = (q.position[1] - q.position[0]).normalized();
      const double fn = -c.force.dot(n);  // the push on 0, along −n; negative: a pull
      const Vec3 ft = c.force + fn * n;
      const double arm = (c.point - q.position[0]).norm();
      const Vec3 slip = q.velocity[0] - q.velocity[1] +
                        (arm * (q.angularVelocity[0] + q.angularVelocity[1])).cross(n);
      const Vec3 slipT = slip - slip.dot(n) * n;
      ++steps;
      if (fn < 0) ++pulling;
      EXPECT_LE(ft.norm(), 0.3 * std::abs(fn) * (1 + 1e-9) + 1e-15) << "step " << sim.stepCount();
      EXPECT_LE(ft.dot(slipT), 0.0) << "step " << sim.stepCount() << ", F_n = " << fn;
    });
  }
  EXPECT_GT(pulling, 0) << "the impact never pulled: it does not test the pull";
  EXPECT_GT(steps, pulling);
  EXPECT_LT(std::abs(sim.energy().total() - start), 1e-5 * kinetic);
}

TEST(EnergyNoPull, TheSwitchTravelsWithTheCheckpoint) {
  PairImpactSpec spec;
  spec.material.noPull = false;
  spec.timeStep = 2e-5;
  Simulation sim = makePairImpact(spec);
  const auto file = std::filesystem::temp_directory_path() / "granular_no_pull.ckpt";
  writeCheckpoint(sim, file, 0);
  EXPECT_FALSE(readCheckpoint(file).config().material.noPull);
  std::filesystem::remove(file);
}
