/// Energy balance (docs/validation.md §3): stored + dissipated - work put in is constant up to the
/// integrator's truncation error. Many-particle runs: 150 particles falling into a box.
#include <gtest/gtest.h>

#include <cmath>

#include "physics_fixtures.hpp"

using namespace granular;
using granular::testing::fallingGrid;

namespace {

struct Drift {
  double absolute = 0;  ///< max |total(t) - total(0)| [J]
  double scale = 0;     ///< energy scale the drift is relative to [J]
  double relative() const { return absolute / scale; }
};

/// Runs `duration` seconds and returns the largest drift of the balance. The scale is the largest
/// mechanical energy in motion (kinetic + elastic) for a conservative run, or the work of gravity
/// for a dissipative one (all of which ends up dissipated).
Drift runBalance(SimulationConfig cfg, double stepFraction, double duration, bool dissipative) {
  cfg.timeStep = stiffestContact(cfg.material, 0.03, cfg.impactSpeed).duration / stepFraction;
  Simulation sim = fallingGrid(5, 5, 6, cfg, 0.3);
  const double start = sim.energy().total();
  Drift d;
  while (sim.time() < duration) {
    sim.step();
    const EnergyBalance e = sim.energy();
    d.absolute = std::max(d.absolute, std::abs(e.total() - start));
    d.scale = std::max(
        d.scale, dissipative ? std::abs(e.gravityWork) : e.kinetic() + e.of("elastic_normal_J"));
  }
  return d;
}

SimulationConfig conservative(NormalLaw law, Integrator integrator) {
  SimulationConfig cfg;
  cfg.material.normalLaw = law;
  cfg.material.normalDamping = 0;
  cfg.material.tangentialDamping = 0;
  cfg.material.friction = 0;
  cfg.integrator = integrator;
  cfg.impactSpeed = 3.0;  // a 0.6 m fall with 0.3 m/s initial speed, head-on
  // Undamped Gear at t_c/50 is at the edge of its growth budget on the network's bound (which
  // is above the exact ω_max): these tests measure the truncation error, so the run goes on.
  cfg.step.onUnstable = OnUnstable::Warn;
  return cfg;
}

}  // namespace

TEST(Energy, ConservativeHertzRunClosesToOnePartPerMillion) {
  // No damping, no friction, Hertz (smooth at first touch): Gear at t_c/200.
  const Drift d = runBalance(conservative(NormalLaw::Hertz, Integrator::Gear5), 200, 1.0, false);
  EXPECT_LT(d.relative(), 1e-6) << "drift " << d.absolute << " J of " << d.scale << " J";
}

TEST(Energy, ConservativeHookeRunConvergesAtSecondOrder) {
  // Hooke's force has a kink at first touch, so neither scheme reaches its formal order
  // (Tuley et al. 2010); both converge at about second order. 1e-6 needs about t_c/400.
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    const Drift coarse = runBalance(conservative(NormalLaw::Hooke, integrator), 50, 1.0, false);
    const Drift fine = runBalance(conservative(NormalLaw::Hooke, integrator), 200, 1.0, false);
    EXPECT_GT(coarse.relative() / fine.relative(), 8.0);  // order > 1.5 over a factor 4 in Δt
    EXPECT_LT(fine.relative(), 2e-5);
  }
}

TEST(Energy, DissipativeSettlingBalanceConvergesAndIsBoundedAtProductionStep) {
  // Paper material with μ = 0.3: every column (dashpots, sliding, spring stiffness work) in use.
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.impactSpeed = 3.0;
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    cfg.integrator = integrator;
    const Drift production = runBalance(cfg, 50, 1.5, true);
    const Drift fine = runBalance(cfg, 200, 1.5, true);
    const bool gear = integrator == Integrator::Gear5;
    // Gear: order > 1 (non-smooth forces); Verlet: second order.
    EXPECT_GT(production.relative() / fine.relative(), gear ? 4.0 : 10.0);
    // At the production step t_c/50 the balance closes to 1e-4 (Gear) and 1e-3 (Verlet) of the
    // energy gravity put in.
    EXPECT_LT(production.relative(), gear ? 1e-4 : 1e-3);
  }
}

TEST(Energy, ConstantTangentialStiffnessDoesNoStiffnessWorkAndTheBalanceCloses) {
  // The constant law's k_t never changes at fixed ξ, so the stiffness-work column stays exactly
  // zero and the balance closes with the stored ½ k_t |ξ|², sliding and the dashpots alone, as
  // tightly as with Mindlin's spring (the test above).
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.material.tangentialLaw = TangentialLaw::Constant;
  cfg.material.tangentialStiffness = 500.0;  // about Mindlin's k_t in a settled paper bed
  cfg.impactSpeed = 3.0;
  const Drift production = runBalance(cfg, 50, 1.5, true);
  const Drift fine = runBalance(cfg, 200, 1.5, true);
  EXPECT_GT(production.relative() / fine.relative(), 4.0);
  EXPECT_LT(production.relative(), 1e-4);
  cfg.timeStep = stiffestContact(cfg.material, 0.03, cfg.impactSpeed).duration / 50;
  Simulation sim = fallingGrid(5, 5, 6, cfg, 0.3);
  while (sim.time() < 1.0) sim.step();
  const EnergyBalance e = sim.energy();
  EXPECT_EQ(e.of("tangential_stiffness_work_J"), 0.0);
  EXPECT_GT(e.of("elastic_tangential_J"), 0.0);
  EXPECT_GT(e.of("dissipated_friction_J"), 0.0);
}

TEST(Energy, FrictionlessPathDoesNoTangentialOrRotationalWork) {
  SimulationConfig cfg;  // μ = 0, γt = 10: the tangential force is capped at zero
  cfg.timeStep = 1e-4;
  Simulation sim = fallingGrid(4, 4, 3, cfg, 0.3);
  sim.run(5000);
  EXPECT_FALSE(sim.frictional());
  EXPECT_EQ(sim.counters().tangentialEvaluations, 0u);
  const EnergyBalance e = sim.energy();
  EXPECT_EQ(e.kineticRotational, 0.0);
  EXPECT_EQ(e.of("elastic_tangential_J"), 0.0);
  EXPECT_EQ(e.of("dissipated_tangential_J"), 0.0);
  EXPECT_EQ(e.of("dissipated_friction_J"), 0.0);
  EXPECT_EQ(e.of("tangential_stiffness_work_J"), 0.0);
  for (const Vec3& w : sim.particles().angularVelocity) EXPECT_EQ(w.squaredNorm(), 0.0);
  EXPECT_GT(e.of("dissipated_normal_J"), 0.0);
  EXPECT_GT(sim.counters().particleContacts, 0u);
}

TEST(Energy, MovingWallWorkEntersTheBalance) {
  // Settle a frictional bed, then push a top wall into it: the wall's work must appear in the
  // balance (a wrong relative velocity at a moving wall breaks it).
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.timeStep = stiffestContact(cfg.material, 0.03, 1.0).duration / 100;
  Simulation sim = fallingGrid(4, 4, 3, cfg, 0.3);
  while (sim.time() < 1.0) sim.step();
  double top = 0;
  const Particles& p = sim.particles();
  for (std::size_t i = 0; i < p.size(); ++i) top = std::max(top, p.position[i].z() + p.radius[i]);
  const std::size_t wall = sim.addWall(Wall{"top", Vec3(0, 0, top), Vec3(0, 0, -1)});
  sim.setWallVelocity(wall, Vec3(0, 0, -0.05));
  const EnergyBalance before = sim.energy();
  while (sim.time() < 1.4) sim.step();
  const EnergyBalance after = sim.energy();
  const double wallWork = after.wallWork - before.wallWork;
  EXPECT_GT(wallWork, 0.0);  // the wall pushes the particles along its motion
  EXPECT_LT(std::abs(after.total() - before.total()), 1e-3 * wallWork);
}
