/// SJKR cohesion (contact_terms/sjkr_cohesion.hpp) against closed forms, Hertz's law: the
/// contact circle's area from the two spheres' geometry; the force between two spheres,
/// F_n = κ √R_ij h^(3/2) − k_c A; the pull-off force of two equal spheres and of a sphere and a
/// wall, the maximum of k_c A(h) − κ √R_ij h^(3/2), which a quadratic in √h gives (A's own h²
/// term kept); a sphere that hangs below a ceiling under a weight below the wall's pull-off and
/// falls under one above; the energy ledger with the bond's account; a cohesive bed at rest; a
/// checkpoint that carries them.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "granular/checkpoint.hpp"
#include "granular/contact_model.hpp"
#include "granular/contact_terms/sjkr_cohesion.hpp"
#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "physics_fixtures.hpp"

using namespace granular;
using std::numbers::pi;

namespace {

constexpr double kR = 0.01;  // [m]
constexpr double kKc = 7e3;  // [J/m³]: the pull-off overlap is a few % of R
constexpr double kG = 9.81;  // [m/s²]

Material cohesive(double kc = kKc) {
  Material m;
  m.normalLaw = NormalLaw::Hertz;
  m.cohesionEnergyDensity = kc;
  return m;
}

/// The contact circle's area from the geometry of the two spheres: a² = R_i² − x², x the
/// distance from centre i to the circle's plane, x = (d² + R_i² − R_j²)/(2d).
double circleArea(double ri, double rj, double h) {
  const double d = ri + rj - h;
  const double x = (d * d + ri * ri - rj * rj) / (2.0 * d);
  return pi * (ri * ri - x * x);
}

/// k_c A(h) − κ √R h^(3/2): the attraction left over the elastic force (A of a sphere of radius
/// r on a sphere of radius r: π (r h − h²/4); on a wall: π (2 r h − h²)).
double attraction(const Material& m, bool wall, double h) {
  const double area = wall ? pi * (2.0 * kR * h - h * h) : pi * (kR * h - 0.25 * h * h);
  const double reduced = wall ? kR : 0.5 * kR;
  return m.cohesionEnergyDensity * area -
         m.normalCoefficient() * std::sqrt(reduced) * h * std::sqrt(h);
}

/// The overlap of the largest attraction: d/dh = 0 is a quadratic in x = √h,
/// on a wall 2 k_c π x² + (3/2) κ √R x − 2 k_c π R = 0, between equal spheres
/// ½ k_c π x² + (3/2) κ √(R/2) x − k_c π R = 0.
double pullOffOverlap(const Material& m, bool wall) {
  const double cw = wall ? 2.0 : 0.5, a = cw * m.cohesionEnergyDensity * pi;
  const double b = 1.5 * m.normalCoefficient() * std::sqrt(wall ? kR : 0.5 * kR);
  const double c = -(wall ? 2.0 : 1.0) * m.cohesionEnergyDensity * pi * kR;
  const double x = (-b + std::sqrt(b * b - 4.0 * a * c)) / (2.0 * a);
  return x * x;
}

SimulationConfig config(const Material& m, const Vec3& gravity = Vec3::Zero()) {
  SimulationConfig cfg;
  cfg.material = m;
  cfg.gravity = gravity;
  cfg.threads = 1;
  cfg.timeStep = stiffestContact(m, 0.5 * kR, 0.1).duration / 100.0;
  return cfg;
}

/// The normal force on sphere 0 from sphere 1 at overlap h, through the engine (positive:
/// repulsion).
double engineNormalForce(const Material& m, double h) {
  Particles p;
  p.add(Vec3(0, 0, 0), kR, m.density);
  p.add(Vec3(2.0 * kR - h, 0, 0), kR, m.density);
  Simulation sim(std::move(p), {}, config(m));
  return -sim.netContactForces()[0].x();
}

}  // namespace

TEST(SjkrCohesion, TheBondIsTheContactCircleAndItsEnergyTheAreasIntegral) {
  for (const auto& [ri, rj] : {std::pair{0.01, 0.01}, {0.01, 0.03}, {0.025, 0.004}}) {
    for (double h : {1e-6, 1e-4, 2e-3}) {
      double area, energy;
      SjkrCohesion::bond(ri, 1.0 / rj, h, area, energy);
      EXPECT_NEAR(area, circleArea(ri, rj, h), 1e-9 * area) << ri << " " << rj << " " << h;
      // −∫₀ʰ A by Simpson's rule on 2000 intervals (A is smooth: error ~1e-13 relative).
      const int n = 2000;
      double sum = 0;
      for (int k = 0; k <= n; ++k) {
        const double w = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
        sum += w * circleArea(ri, rj, h * k / n);
      }
      EXPECT_NEAR(energy, -sum * h / (3.0 * n), 1e-9 * std::abs(energy));
    }
  }
  double area, energy;  // a wall: R_j = ∞
  SjkrCohesion::bond(kR, 0.0, 1e-3, area, energy);
  EXPECT_NEAR(area, pi * (2.0 * kR * 1e-3 - 1e-6), 1e-12 * area);
  EXPECT_NEAR(energy, -pi * (kR * 1e-6 - 1e-9 / 3.0), 1e-12 * std::abs(energy));
}

TEST(SjkrCohesion, TheForceBetweenTwoSpheresIsTheElasticForceLessKcTimesTheArea) {
  const Material m = cohesive();
  for (double h : {1e-5, 2e-4, 1e-3}) {
    const double expected = -attraction(m, false, h);
    EXPECT_NEAR(engineNormalForce(m, h), expected, 1e-9 * std::abs(expected)) << h;
  }
  // Without cohesion the same contact only pushes.
  EXPECT_GT(engineNormalForce(cohesive(0.0), 2e-4), 0.0);
}

TEST(SjkrCohesion, ThePullOffForceOfTwoEqualSpheresIsTheClosedForm) {
  const Material m = cohesive();
  const double at = pullOffOverlap(m, false), pullOff = attraction(m, false, at);
  ASSERT_GT(pullOff, 0.0);
  ASSERT_LT(at, 0.1 * kR);
  // The engine's largest pull over overlaps around the closed form's is the closed form's.
  double largest = 0;
  for (double f = 0.8; f <= 1.2; f += 0.001)
    largest = std::max(largest, -engineNormalForce(m, f * at));
  EXPECT_NEAR(largest, pullOff, 1e-6 * pullOff);
  EXPECT_NEAR(-engineNormalForce(m, at), pullOff, 1e-9 * pullOff);
}

TEST(SjkrCohesion, ASphereHangsBelowACeilingUnderAWeightBelowThePullOffAndFallsAboveIt) {
  // A ceiling at z = 0 (normal −z), the sphere below it. The weight W pulls it off; the net
  // pull k_c A − F_e holds it where they balance, on the side of the largest pull (h > h*)
  // where a smaller overlap pulls harder. W = 0.97 of the pull-off: it settles there, at the
  // closed form's overlap; 1.03: no balance, and it falls.
  for (double fraction : {0.97, 1.03}) {
    SCOPED_TRACE(fraction);
    Material m = cohesive();
    const double hStar = pullOffOverlap(m, true), pullOff = attraction(m, true, hStar);
    const double volume = 4.0 / 3.0 * pi * kR * kR * kR;
    m.density = fraction * pullOff / (kG * volume);
    m.normalDamping = 200.0;
    const double weight = m.density * volume * kG;
    double hold = hStar;  // the balance h > h*, by bisection (the pull falls as h grows)
    if (fraction < 1.0) {
      double lo = hStar, hi = kR;
      for (int k = 0; k < 200; ++k) {
        const double mid = 0.5 * (lo + hi);
        (attraction(m, true, mid) > weight ? lo : hi) = mid;
      }
      hold = 0.5 * (lo + hi);
    }
    Particles p;
    p.add(Vec3(0, 0, -(kR - 1.2 * hold)), kR, m.density);  // pressed 20 % deeper, at rest
    Simulation sim(std::move(p), {Wall{"ceiling", Vec3::Zero(), -Vec3::UnitZ()}},
                   config(m, Vec3(0, 0, -kG)));
    while (sim.time() < 0.3) sim.step();
    const double overlap = kR + sim.particles().position[0].z();
    if (fraction < 1.0) {
      EXPECT_NEAR(overlap, hold, 1e-6 * hold);
    } else {
      EXPECT_LT(overlap, -0.1 * kR) << "it should have fallen off";
    }
  }
}

TEST(SjkrCohesion, TheEnergyLedgerClosesWithTheBondsAccount) {
  // Two spheres released at rest, touching at a third of the pull-off overlap, where the bond
  // outweighs the elastic energy: undamped they oscillate bonded, trading kinetic, elastic and
  // bond energy, and the total stays to the integrator's error, converging with the step.
  Material m = cohesive();
  m.normalDamping = 0.0;
  const double start = pullOffOverlap(m, false) / 3.0;
  double drift[2] = {0, 0}, deepest = 0;
  for (int fine = 0; fine < 2; ++fine) {
    Particles p;
    p.add(Vec3(0, 0, 0), kR, m.density);
    p.add(Vec3(2.0 * kR - start, 0, 0), kR, m.density);
    SimulationConfig cfg = config(m);
    cfg.timeStep /= fine ? 4.0 : 1.0;
    Simulation sim(std::move(p), {}, cfg);
    const double total = sim.energy().total();
    while (sim.time() < 0.05) {
      sim.step();
      const EnergyBalance e = sim.energy();
      drift[fine] = std::max(drift[fine], std::abs(e.total() - total));
      deepest = std::min(deepest, e.of("cohesion_J"));
      const auto& x = sim.particles().position;
      ASSERT_LT((x[1] - x[0]).norm(), 2.0 * kR) << "the bond broke at t = " << sim.time();
    }
    ASSERT_GT(sim.energy().kineticTranslational, 0.0);
  }
  ASSERT_LT(deepest, 0.0);
  EXPECT_LT(drift[0], 1e-6 * std::abs(deepest));
  EXPECT_GT(drift[0] / drift[1], 4.0);  // the integrator's error, not a leak
}

TEST(SjkrCohesion, ACohesiveBedAtRestKeepsItsEnergy) {
  // A small bed falls and settles with cohesion; at rest its bonds hold it: the kinetic energy
  // stays near zero and the ledger's total does not move.
  SimulationConfig cfg;
  cfg.material = cohesive(2e4);
  cfg.material.friction = 0.3;
  cfg.material.normalDamping = 300.0;
  cfg.material.rollingFriction = 0.2;  // a sphere rolling free on the floor: nothing else stops it
  cfg.step.automatic = true;           // the damping shrinks Gear's interval: the network chooses
  cfg.impactSpeed = 3.0;
  cfg.timeStep = stiffestContact(cfg.material, 0.03, cfg.impactSpeed).duration / 50.0;
  Simulation sim = granular::testing::fallingGrid(3, 3, 3, cfg, 0.3);
  const granular::testing::RestingBed bed = granular::testing::watchAtRest(sim, 3.0, 0.5);
  ASSERT_LT(bed.settled.of("cohesion_J"), 0.0);
  EXPECT_LT(bed.kinetic, 1e-6);
  EXPECT_LT(bed.moved, 1e-6);
}

TEST(SjkrCohesion, ACheckpointCarriesTheCohesionAndItsAccountBitForBit) {
  // The parameter and the bond's account travel in the checkpoint (they are not the defaults):
  // a run resumed halfway ends on the same bits as one run straight through.
  SimulationConfig cfg;
  cfg.material = cohesive(2e4);
  cfg.material.friction = 0.3;
  cfg.impactSpeed = 3.0;
  cfg.timeStep = stiffestContact(cfg.material, 0.03, cfg.impactSpeed).duration / 50.0;
  Simulation straight = granular::testing::fallingGrid(3, 3, 3, cfg, 0.3);
  Simulation first = granular::testing::fallingGrid(3, 3, 3, cfg, 0.3);
  straight.run(6000);
  first.run(3000);
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("granular_sjkr_" + std::to_string(::getpid()) + ".ckpt");
  writeCheckpoint(first, file, 7);
  Simulation resumed = readCheckpoint(file, 7);
  std::filesystem::remove(file);
  EXPECT_EQ(resumed.config().material.cohesionEnergyDensity, 2e4);
  resumed.run(3000);
  EXPECT_EQ(straight.stateHash(), resumed.stateHash());
  EXPECT_LT(straight.energy().of("cohesion_J"), 0.0);
  EXPECT_EQ(straight.energy().of("cohesion_J"), resumed.energy().of("cohesion_J"));
  EXPECT_EQ(straight.energy().total(), resumed.energy().total());
}

TEST(SjkrCohesion, AHookeBondThatOutpullsTheSpringIsRefusedByName) {
  // Hooke's spring κ R h against the pull ≈ 2π R k_c h: from k_c = κ/(2π) on nothing holds a
  // contact. Refused there, accepted just below, and never under Hertz's law.
  Material m;
  const double limit = m.normalCoefficient() / (2.0 * pi);
  m.cohesionEnergyDensity = 1.0001 * limit;
  try {
    validateMaterial(m);
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("material.cohesion_energy_density"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("hooke"), std::string::npos) << e.what();
  }
  m.cohesionEnergyDensity = 0.9999 * limit;
  EXPECT_NO_THROW(validateMaterial(m));
  m.cohesionEnergyDensity = 10.0 * limit;
  m.normalLaw = NormalLaw::Hertz;
  EXPECT_NO_THROW(validateMaterial(m));
}
