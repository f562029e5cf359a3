/// Rolling resistance (contact_terms/rolling_resistance.hpp, the EPSD model of Ai et al. 2011)
/// against closed forms. A sphere rolling without slip on a plane under the constant resisting
/// moment μ_r R m g decelerates at a = (5/7) μ_r g: m a = F_t and I a/R = F_t R − μ_r R m g
/// with I = (2/5) m R². On a slope of angle α (gravity tilted, the floor kept) the weight's
/// moment about the contact point, m g sin α R, is held with no creep while tan α <= μ_r; above,
/// the sphere rolls at a = (5/7) g (sin α − μ_r cos α). Exactly, the friction force acts at the
/// lever arm a = R − h/2 (h: the static overlap) while the cap is μ_r R F_n, so the tests use
/// a = g (sin α − μ_r (R/a) cos α)/(1 + (2/5)(R/a)²), which the (5/7) forms approach as h → 0
/// (they differ by 0.06 % on the flat, 0.7 % on the slope at tan α = 1.2 μ_r, where the
/// difference of two near numbers magnifies it). The energy ledger closes with the rolling
/// accounts; a checkpoint carries the rolling springs.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "granular/checkpoint.hpp"
#include "granular/contact_model.hpp"
#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "physics_fixtures.hpp"

using namespace granular;
using granular::testing::fallingGrid;

namespace {

constexpr double kR = 0.03;   // [m]
constexpr double kG = 9.81;   // [m/s²]
constexpr double kMu = 0.5;   // Coulomb friction: the sphere sticks to the plane and rolls
constexpr double kMuR = 0.1;  // rolling friction

Material rollingMaterial(double rollingFriction) {
  Material m;
  m.friction = kMu;
  m.rollingFriction = rollingFriction;
  return m;
}

/// The static overlap of the sphere under the normal load `load` [N] on the floor (Hooke).
double staticOverlap(const Material& material, double load) {
  return load / (material.normalCoefficient() * kR);
}

/// The acceleration along the slope of a sphere rolling without slip against the rolling cap,
/// gravity g at α from the floor's normal (α = 0: the flat, a deceleration of −this).
double rollingAcceleration(const Material& material, double alpha) {
  const double m = granular::testing::sphereMass(kR, material.density);
  const double arm = kR - 0.5 * staticOverlap(material, m * kG * std::cos(alpha));
  const double ratio = kR / arm;
  return kG * (std::sin(alpha) - kMuR * ratio * std::cos(alpha)) / (1.0 + 0.4 * ratio * ratio);
}

/// One sphere resting on the floor (z = 0) at its static overlap under gravity `gravity`,
/// moving at `speed` along x and spinning so that it rolls without slip: its contact point, at
/// the lever arm R − h/2, is at rest.
Simulation sphereOnFloor(const Material& material, const Vec3& gravity, double speed,
                         Integrator integrator = Integrator::Gear5) {
  SimulationConfig cfg;
  cfg.material = material;
  cfg.gravity = gravity;
  cfg.integrator = integrator;
  cfg.threads = 1;
  const double fraction = integrator == Integrator::Gear5 ? 50.0 : 10.0;
  cfg.timeStep = stiffestContact(cfg.material, kR, 1.0).duration / fraction;
  const double m = granular::testing::sphereMass(kR, material.density);
  const double overlap = staticOverlap(material, m * -gravity.z());
  Particles p;
  p.add(Vec3(0, 0, kR - overlap), kR, material.density, Vec3(speed, 0, 0));
  p.angularVelocity[0] = Vec3(0, speed / (kR - 0.5 * overlap), 0);  // v − a ω_y = 0
  return Simulation(std::move(p), {Wall{"floor", Vec3::Zero(), Vec3::UnitZ()}}, cfg);
}

void runUntil(Simulation& sim, double t) {
  while (sim.time() < t) sim.step();
}

}  // namespace

TEST(RollingResistance, ARollingSphereDeceleratesAtFiveSeventhsMuRGAndStopsWhereTheClosedFormSays) {
  // Without the rolling dashpot: it acts only below the cap, where a sphere spinning at 17 rad/s
  // spends its first steps while the spring winds up from zero (4 steps here), and there its
  // torque C_r ω (18 × the cap) takes 7 % of the spin, a kick the closed form does not have.
  Material material = rollingMaterial(kMuR);
  material.rollingDamping = 0.0;
  const double v0 = 0.5, a = -rollingAcceleration(material, 0.0);
  EXPECT_NEAR(a, 5.0 / 7.0 * kMuR * kG, 1e-3 * a);  // the (5/7) μ_r g of the rigid sphere
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    SCOPED_TRACE(integrator == Integrator::Gear5 ? "gear5" : "verlet");
    Simulation sim = sphereOnFloor(material, Vec3(0, 0, -kG), v0, integrator);
    // The torque appears at once at t = 0 and the tangential spring rings for a while (γt: e^−17
    // a second): the closed form is checked from t = 0.4 s, when that is gone (e^−6.8).
    runUntil(sim, 0.4);
    const double t1 = sim.time(), v1 = sim.particles().velocity[0].x();
    const double x1 = sim.particles().position[0].x();
    runUntil(sim, 0.6);
    const double t2 = sim.time(), v2 = sim.particles().velocity[0].x();
    EXPECT_NEAR((v1 - v2) / (t2 - t1), a, 1e-4 * a);
    // Still rolling, not sliding.
    const Particles& p = sim.particles();
    EXPECT_NEAR(p.velocity[0].x(), kR * p.angularVelocity[0].y(), 1e-3 * v0);
    // It stops (v = 0 for the first time) after v1/a more, v1²/(2a) further on.
    while (sim.particles().velocity[0].x() > 0.0) sim.step();
    const double dt = sim.config().timeStep;
    EXPECT_NEAR(sim.time() - t1, v1 / a, dt);
    EXPECT_NEAR(sim.particles().position[0].x() - x1, v1 * v1 / (2 * a), 5e-4 * v1 * v1 / (2 * a));
    EXPECT_NEAR(sim.particles().position[0].x(), v0 * v0 / (2 * a), 5e-3 * v0 * v0 / (2 * a));
  }
}

TEST(RollingResistance, ARollingSphereComesToRestAndDoesNotCreep) {
  // With the rolling dashpot (η_r = 0.3) the springs' last swing decays, e^−13 a second, and
  // the sphere then stays where it is: no creep under no load.
  Simulation sim = sphereOnFloor(rollingMaterial(kMuR), Vec3(0, 0, -kG), 0.5);
  runUntil(sim, 4.0);
  const double x4 = sim.particles().position[0].x();
  EXPECT_GT(x4, 0.1);
  runUntil(sim, 5.0);
  EXPECT_LT(std::abs(sim.particles().position[0].x() - x4), 1e-12);
  EXPECT_LT(sim.particles().velocity[0].norm(), 1e-12);
}

TEST(RollingResistance, WithoutRollingFrictionTheSphereRollsOn) {
  // The control: the same sphere with μ_r = 0 (the build without the term) keeps its speed.
  Simulation sim = sphereOnFloor(rollingMaterial(0.0), Vec3(0, 0, -kG), 0.5);
  runUntil(sim, 1.0);
  EXPECT_NEAR(sim.particles().velocity[0].x(), 0.5, 1e-9);
}

TEST(RollingResistance, AMomentBelowTheCapIsHeldWithoutCreepAndAboveItTheSphereRolls) {
  // Gravity tilted by α: the weight's moment about the contact point is m g sin α R, the cap
  // μ_r R m g cos α.
  auto tilted = [](double tanAlpha) {
    const double alpha = std::atan(tanAlpha);
    return Vec3(kG * std::sin(alpha), 0, -kG * std::cos(alpha));
  };
  {  // tan α = 0.8 μ_r: held. After the springs settle, the sphere does not move at all.
    Simulation sim = sphereOnFloor(rollingMaterial(kMuR), tilted(0.8 * kMuR), 0.0);
    runUntil(sim, 4.0);
    const double x1 = sim.particles().position[0].x();
    EXPECT_LT(std::abs(x1), 1e-3) << "held, with the springs' elastic give only";
    runUntil(sim, 5.0);
    EXPECT_LT(std::abs(sim.particles().position[0].x() - x1), 1e-12) << "creeps";
    EXPECT_LT(sim.particles().velocity[0].norm(), 1e-12);
  }
  {  // tan α = 1.2 μ_r: rolls at (5/7) g (sin α − μ_r cos α).
    const double alpha = std::atan(1.2 * kMuR);
    const double a = rollingAcceleration(rollingMaterial(kMuR), alpha);
    Simulation sim = sphereOnFloor(rollingMaterial(kMuR), tilted(1.2 * kMuR), 0.0);
    runUntil(sim, 0.4);
    const double t1 = sim.time(), v1 = sim.particles().velocity[0].x();
    runUntil(sim, 1.0);
    const double t2 = sim.time(), v2 = sim.particles().velocity[0].x();
    EXPECT_NEAR((v2 - v1) / (t2 - t1), a, 1e-3 * a);
  }
}

TEST(RollingResistance, TheCapFollowsTheNormalForceAndTheReducedRadius) {
  // The stored torque never exceeds μ_r R_ij F_n: on the floor R_ij = R, F_n = m g.
  Simulation sim = sphereOnFloor(rollingMaterial(kMuR), Vec3(0, 0, -kG), 0.5);
  const double m = sim.particles().mass[0];
  const double cap = kMuR * kR * m * kG;
  double largest = 0;
  while (sim.time() < 0.3) {
    sim.step();
    largest = std::max(largest, std::abs(sim.energy().of("elastic_rolling_J")));
  }
  // ½ M²/k_r at the cap: the spring holds exactly the cap while rolling.
  const double kn = sim.config().material.normalCoefficient() * kR;
  const double kr = sim.config().material.rollingStiffness * kMuR * kMuR * kn * kR * kR;
  EXPECT_NEAR(largest, 0.5 * cap * cap / kr, 0.01 * 0.5 * cap * cap / kr);
}

TEST(RollingResistance, TheEnergyBalanceClosesWithTheRollingAccounts) {
  // A bed falls, bounces and settles with friction and rolling resistance: the total of every
  // account is constant to the integrator's error, converges as the step shrinks, and the
  // rolling accounts are live; rolling at the cap only ever takes energy.
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    SCOPED_TRACE(integrator == Integrator::Gear5 ? "gear5" : "verlet");
    double drift[2] = {0, 0};
    for (int fine = 0; fine < 2; ++fine) {
      SimulationConfig cfg;
      cfg.material = rollingMaterial(kMuR);
      cfg.material.friction = 0.3;
      cfg.integrator = integrator;
      cfg.impactSpeed = 3.0;
      cfg.timeStep =
          stiffestContact(cfg.material, 0.03, cfg.impactSpeed).duration / (fine ? 200.0 : 50.0);
      Simulation sim = fallingGrid(4, 4, 5, cfg, 0.3);
      const double start = sim.energy().total();
      double scale = 0, slip = 0;
      while (sim.time() < 1.5) {
        sim.step();
        const EnergyBalance e = sim.energy();
        drift[fine] = std::max(drift[fine], std::abs(e.total() - start));
        scale = std::max(scale, std::abs(e.gravityWork));
        const double nowSlip = e.of("dissipated_rolling_slip_J");
        EXPECT_GE(nowSlip, slip - 1e-6 * scale) << "rolling at the cap gave energy back";
        slip = nowSlip;
      }
      drift[fine] /= scale;
      const EnergyBalance e = sim.energy();
      EXPECT_GT(e.of("dissipated_rolling_slip_J"), 1e-3 * scale);
      EXPECT_GT(e.of("dissipated_rolling_J"), 0.0);
      EXPECT_GT(e.of("elastic_rolling_J"), 0.0);
    }
    const bool gear = integrator == Integrator::Gear5;
    // At t_c/50 to 1e-4 (Gear) and 1e-3 (Verlet) of gravity's work, as without the term
    // (test_energy.cpp).
    EXPECT_LT(drift[0], gear ? 1e-4 : 1e-3);
    EXPECT_GT(drift[0] / drift[1], gear ? 4.0 : 10.0);
  }
}

TEST(RollingResistance, ACheckpointCarriesTheRollingSpringsBitForBit) {
  SimulationConfig cfg;
  cfg.material = rollingMaterial(kMuR);
  cfg.timeStep = stiffestContact(cfg.material, 0.03, 3.0).duration / 50;
  Simulation straight = fallingGrid(3, 3, 4, cfg, 0.3);
  Simulation first = fallingGrid(3, 3, 4, cfg, 0.3);
  straight.run(6000);
  first.run(3000);
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("granular_rolling_" + std::to_string(::getpid()) + ".ckpt");
  writeCheckpoint(first, file, 7);
  Simulation resumed = readCheckpoint(file, 7);
  std::filesystem::remove(file);
  resumed.run(3000);
  for (std::size_t i = 0; i < straight.particles().size(); ++i) {
    EXPECT_EQ(straight.particles().position[i], resumed.particles().position[i]) << i;
    EXPECT_EQ(straight.particles().angularVelocity[i], resumed.particles().angularVelocity[i]);
  }
  EXPECT_EQ(straight.energy().of("elastic_rolling_J"), resumed.energy().of("elastic_rolling_J"));
}

TEST(RollingResistance, RollingFrictionWithoutFrictionIsRefusedByName) {
  Material m;
  m.rollingFriction = 0.1;
  try {
    validateMaterial(m);
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("material.rolling_friction = 0.1: needs friction > 0"),
              std::string::npos)
        << e.what();
  }
  m.friction = 0.3;
  m.rollingFriction = 1.0;
  m.rollingStiffness = 3.0;  // β_r μ_r² = 3 > 2.25
  EXPECT_THROW(validateMaterial(m), ConfigError);
  m.rollingStiffness = 2.25;
  EXPECT_NO_THROW(validateMaterial(m));
}

TEST(RollingResistance, SwitchedOnAndOffMidRunTheSpringsFollow) {
  // A frictional bed without rolling resistance stores 4 doubles a contact; switched on, the
  // records gain the rolling slots (from zero), a checkpoint carries them, and switched off
  // they are dropped again while the tangential springs go on.
  SimulationConfig cfg;
  cfg.material = rollingMaterial(0.0);
  cfg.timeStep = stiffestContact(cfg.material, 0.03, 3.0).duration / 50;
  Simulation sim = fallingGrid(3, 3, 4, cfg, 0.3);
  sim.run(3000);
  EXPECT_THROW(sim.energy().of("elastic_rolling_J"), std::out_of_range);
  Material on = sim.config().material;
  on.rollingFriction = kMuR;
  sim.setMaterial(on);
  sim.run(1000);
  EXPECT_GT(sim.energy().of("elastic_rolling_J"), 0.0);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() /
      ("granular_rolling_switch_" + std::to_string(::getpid()) + ".ckpt");
  writeCheckpoint(sim, file, 7);
  Simulation resumed = readCheckpoint(file, 7);
  std::filesystem::remove(file);
  sim.run(500);
  resumed.run(500);
  EXPECT_EQ(sim.stateHash(), resumed.stateHash());
  const double tangential = sim.energy().of("elastic_tangential_J");
  Material off = sim.config().material;
  off.rollingFriction = 0.0;
  sim.setMaterial(off);
  EXPECT_NEAR(sim.energy().of("elastic_tangential_J"), tangential, 1e-6 * tangential);
  sim.run(500);
  EXPECT_THROW(sim.energy().of("elastic_rolling_J"), std::out_of_range);
  EXPECT_GT(sim.energy().of("elastic_tangential_J"), 0.0);
}
