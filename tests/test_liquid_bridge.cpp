/// Liquid bridges (contact_terms/liquid_bridge.hpp), a term that acts beyond touch, against
/// closed forms: the pull at touch, 2π R γ cos θ, and across a gap, Willett's form in
/// Herminghaus' writing 1 + 1.05 S √(R/V) + 2.5 S² R/V (the test's own algebra); the rupture
/// distance (1 + θ/2) V^(1/3); two spheres pulled apart from touch leave with the kinetic energy
/// less the work of the pull out to rupture (Simpson's rule on the closed form); the energy
/// ledger with the bridges' column; a wet bed at rest; a bridge across a gap is no contact and
/// leaves the contact terms nothing; the same bits on any thread count and vector build; a
/// checkpoint that carries them.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "granular/checkpoint.hpp"
#include "granular/contact_model.hpp"
#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "granular/simd_build.hpp"
#include "physics_fixtures.hpp"
#include "simd_build_guard.hpp"

using namespace granular;
using std::numbers::pi;

namespace {

constexpr double kR = 0.01;                                       // [m]
constexpr double kGamma = 0.072;                                  // water [N/m]
constexpr double kAngle = 20.0;                                   // [°]
constexpr double kVolume = 1e-3 * 4.0 / 3.0 * pi * kR * kR * kR;  // [m³]

Material wet(double gamma = kGamma) {
  Material m;
  m.normalLaw = NormalLaw::Hertz;
  m.surfaceTension = gamma;
  m.contactAngle = kAngle;
  m.bridgeVolume = kVolume;
  return m;
}

double rupture() {
  return (1.0 + 0.5 * kAngle * pi / 180.0) * std::cbrt(kVolume);
}

/// Willett's pull between bodies of R = 2 R_ij at gap S (Herminghaus' form).
double willett(double radius, double gap) {
  const double s = gap * std::sqrt(radius / kVolume);
  return 2.0 * pi * radius * kGamma * std::cos(kAngle * pi / 180.0) /
         (1.0 + 1.05 * s + 2.5 * s * s);
}

SimulationConfig config(const Material& m) {
  SimulationConfig cfg;
  cfg.material = m;
  cfg.gravity = Vec3::Zero();
  cfg.threads = 1;
  cfg.timeStep = stiffestContact(m, 0.5 * kR, 0.1).duration / 100.0;
  return cfg;
}

/// The falling grid's beds, wet: γ = 1 N/m, bridges of volume V, μ = 0.3.
SimulationConfig wetBed(double volume) {
  SimulationConfig cfg;
  cfg.material = wet(1.0);
  cfg.material.bridgeVolume = volume;
  cfg.material.friction = 0.3;
  cfg.impactSpeed = 3.0;
  cfg.timeStep = stiffestContact(cfg.material, 0.03, cfg.impactSpeed).duration / 50.0;
  return cfg;
}

/// The normal force on sphere 0 from sphere 1 at overlap h (negative: a gap), through the
/// engine (positive: repulsion).
double engineNormalForce(const Material& m, double h) {
  Particles p;
  p.add(Vec3(0, 0, 0), kR, m.density);
  p.add(Vec3(2.0 * kR - h, 0, 0), kR, m.density);
  Simulation sim(std::move(p), {}, config(m));
  return -sim.netContactForces()[0].x();
}

/// The same for a sphere at overlap h with a floor.
double engineWallForce(const Material& m, double h) {
  Particles p;
  p.add(Vec3(0, 0, kR - h), kR, m.density);
  Simulation sim(std::move(p), {Wall{"floor", Vec3::Zero(), Vec3::UnitZ()}}, config(m));
  return sim.netContactForces()[0].z();
}

}  // namespace

TEST(LiquidBridge, ThePullAtTouchIsTwoPiRGammaCosTheta) {
  const Material m = wet();
  const double atTouch = 2.0 * pi * kR * kGamma * std::cos(kAngle * pi / 180.0);  // R = 2 R_ij
  EXPECT_NEAR(-engineNormalForce(m, -1e-12 * kR), atTouch, 1e-2 * atTouch);
  EXPECT_NEAR(-engineNormalForce(m, -1e-12 * kR), atTouch, 1e-8 * atTouch);
  // Against a wall R = 2 R_i: twice the pull.
  EXPECT_NEAR(-engineWallForce(m, -1e-12 * kR), 2.0 * atTouch, 1e-8 * atTouch);
  // Overlapping, the bridge pulls as at touch beside the elastic force.
  const double h = 1e-4;
  const double elastic = m.normalCoefficient() * std::sqrt(0.5 * kR) * h * std::sqrt(h);
  EXPECT_NEAR(engineNormalForce(m, h), elastic - atTouch, 1e-9 * elastic);
  // Without surface tension there is no bridge, nor any force across a gap.
  EXPECT_EQ(engineNormalForce(wet(0.0), -0.5 * rupture()), 0.0);
}

TEST(LiquidBridge, AcrossAGapThePullIsWillettsClosedForm) {
  const Material m = wet();
  for (double fraction : {0.01, 0.1, 0.3, 0.6, 0.95}) {
    const double gap = fraction * rupture();
    const double expected = willett(kR, gap);
    EXPECT_NEAR(-engineNormalForce(m, -gap), expected, 1e-9 * expected) << fraction;
    EXPECT_NEAR(-engineWallForce(m, -gap), willett(2.0 * kR, gap), 1e-9 * expected) << fraction;
  }
}

TEST(LiquidBridge, ItRupturesAtOnePlusHalfThetaTimesTheCubeRootOfItsVolume) {
  const Material m = wet();
  EXPECT_DOUBLE_EQ(reachBeyondTouch(m), rupture());
  EXPECT_EQ(reachBeyondTouch(wet(0.0)), 0.0);  // no bridges: every force needs contact
  EXPECT_GT(-engineNormalForce(m, -(1.0 - 1e-6) * rupture()), 0.0);
  EXPECT_EQ(engineNormalForce(m, -(1.0 + 1e-6) * rupture()), 0.0);
  EXPECT_GT(-engineWallForce(m, -(1.0 - 1e-6) * rupture()), 0.0);
  EXPECT_EQ(engineWallForce(m, -(1.0 + 1e-6) * rupture()), 0.0);
}

TEST(LiquidBridge, SpheresPulledApartLeaveWithTheirEnergyLessThePullsWorkOutToRupture) {
  // Two spheres leave touch at speed u each way; the bridge pulls back until it ruptures, then
  // they coast. Their kinetic energy at the end is the start's less ∫₀^{S_c} F dS, which
  // Simpson's rule gives from the closed form. The discrete run misses it by the step's share
  // of the jump at rupture and the integrator's error.
  const Material m = wet();
  double work = 0;
  const int n = 4000;
  for (int k = 0; k <= n; ++k) {
    const double w = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
    work += w * willett(kR, rupture() * k / n);
  }
  work *= rupture() / (3.0 * n);
  const double mass = m.density * 4.0 / 3.0 * pi * kR * kR * kR;
  const double u = std::sqrt(3.0 * work / mass);  // KE = 2 · ½ m u² = 3 W: they escape
  Particles p;
  p.add(Vec3(0, 0, 0), kR, m.density, Vec3(-u, 0, 0));
  p.add(Vec3(2.0 * kR + 1e-12, 0, 0), kR, m.density, Vec3(u, 0, 0));
  Simulation sim(std::move(p), {}, config(m));
  const double start = sim.energy().kineticTranslational;
  while ((sim.particles().position[1] - sim.particles().position[0]).norm() <
         2.0 * kR + 2.0 * rupture()) {
    sim.step();
  }
  const double left = sim.energy().kineticTranslational;
  EXPECT_NEAR(start - left, work, 2e-3 * work);
  // Once ruptured, nothing acts: the speed stays.
  sim.run(100);
  EXPECT_EQ(sim.energy().kineticTranslational, left);
}

TEST(LiquidBridge, TheEnergyLedgerClosesWithTheBridgesColumn) {
  // Two spheres released at rest across half the rupture distance, undamped: the bridge pulls
  // them together, they bounce, and they swing back to where they started, trading kinetic,
  // elastic and the bridge's energy; the total stays to the integrator's error, converging
  // with the step.
  Material m = wet();
  m.normalDamping = 0.0;
  double drift[2] = {0, 0}, deepest = 0;
  for (int fine = 0; fine < 2; ++fine) {
    Particles p;
    p.add(Vec3(0, 0, 0), kR, m.density);
    p.add(Vec3(2.0 * kR + 0.5 * rupture(), 0, 0), kR, m.density);
    SimulationConfig cfg = config(m);
    cfg.timeStep /= fine ? 4.0 : 1.0;
    Simulation sim(std::move(p), {}, cfg);
    const double total = sim.energy().total();
    bool touched = false;
    while (sim.time() < 0.3) {
      sim.step();
      const EnergyBalance e = sim.energy();
      drift[fine] = std::max(drift[fine], std::abs(e.total() - total));
      deepest = std::min(deepest, e.of("bridge_J"));
      const auto& x = sim.particles().position;
      touched = touched || (x[1] - x[0]).norm() < 2.0 * kR;
      ASSERT_LT((x[1] - x[0]).norm(), 2.0 * kR + rupture()) << "ruptured at t = " << sim.time();
    }
    ASSERT_TRUE(touched);
  }
  // bridge_J is what the bridge took from the particles: negative once its pull has worked on
  // them, at most the well's depth from half the rupture distance to touch.
  ASSERT_LT(deepest, -willett(kR, 0.5 * rupture()) * 0.5 * rupture());
  ASSERT_GT(deepest, -willett(kR, 0.0) * 0.5 * rupture());
  EXPECT_LT(drift[0], 1e-5 * std::abs(deepest));
  EXPECT_GT(drift[0] / drift[1], 4.0);  // the integrator's error, not a leak
}

TEST(LiquidBridge, ABridgeAcrossAGapIsNoContactAndLeavesTheContactTermsNothing) {
  // Friction on, a constant k_t (whose spring holds energy at any overlap) and a pull allowed
  // (so that the dashpot's pull as the pair separates keeps a Coulomb limit): a pair that slid
  // in contact and then opened across a gap keeps its bridge but no spring; the gap is no
  // contact in the counters, and the contact view says it is a gap.
  Material m = wet();
  m.friction = 0.5;
  m.noPull = false;
  m.tangentialLaw = TangentialLaw::Constant;
  m.tangentialStiffness = 100.0;
  Particles p;
  p.add(Vec3(0, 0, 0), kR, m.density, Vec3(0, -0.01, 0));
  p.add(Vec3(2.0 * kR - 1e-4, 0, 0), kR, m.density, Vec3(0.02, 0.01, 0));
  Simulation sim(std::move(p), {}, config(m));
  bool stretched = false;
  while ((sim.particles().position[1] - sim.particles().position[0]).norm() < 2.0 * kR) {
    sim.step();
    stretched = stretched || sim.energy().of("elastic_tangential_J") > 0.0;
  }
  ASSERT_TRUE(stretched);
  sim.step();
  ASSERT_LT(sim.energy().kineticTranslational, 1.0);  // sanity
  EXPECT_EQ(sim.energy().of("elastic_tangential_J"), 0.0);
  const std::size_t before = sim.counters().particleContacts;
  sim.step();
  EXPECT_EQ(sim.counters().particleContacts, before);
  int views = 0;
  sim.forEachContact([&](const ContactView& c) {
    ++views;
    EXPECT_LT(c.overlap, 0.0);
    EXPECT_GT(c.force.dot(c.normal), 0.0);  // the pull: along n, towards the other
  });
  EXPECT_EQ(views, 2);  // the pair, seen from each side
}

TEST(LiquidBridge, APairApproachingAcrossAGapFeelsNoDashpot) {
  // Damped, with friction: while the bridge pulls a pair together across the gap, the normal
  // dashpot (which would push against the approach) neither acts nor dissipates.
  for (double friction : {0.0, 0.5}) {
    SCOPED_TRACE(friction);
    Material m = wet();
    m.friction = friction;
    m.normalDamping = 300.0;
    Particles p;
    p.add(Vec3(0, 0, 0), kR, m.density, Vec3(0.01, 0, 0));
    p.add(Vec3(2.0 * kR + 0.9 * rupture(), 0, 0), kR, m.density, Vec3(-0.01, 0, 0));
    Simulation sim(std::move(p), {}, config(m));
    const auto gap = [&] {
      return (sim.particles().position[1] - sim.particles().position[0]).norm() - 2.0 * kR;
    };
    double kinetic = sim.energy().kineticTranslational;
    while (gap() > 0.05 * rupture()) {
      sim.step();
      EXPECT_EQ(sim.energy().of("dissipated_normal_J"), 0.0);
      const double now = sim.energy().kineticTranslational;
      EXPECT_GT(now, kinetic);  // pulled together, never held back
      kinetic = now;
    }
  }
}

TEST(LiquidBridge, AWetBedAtRestKeepsItsEnergy) {
  SimulationConfig cfg = wetBed(1e-8);
  cfg.material.normalDamping = 300.0;
  cfg.step.automatic = true;
  Simulation sim = granular::testing::fallingGrid(3, 3, 3, cfg, 0.3);
  const granular::testing::RestingBed bed = granular::testing::watchAtRest(sim, 3.0, 0.5);
  ASSERT_LT(bed.settled.of("bridge_J"), 0.0);
  EXPECT_LT(bed.kinetic, 1e-6);
  EXPECT_LT(bed.moved, 1e-6);
}

TEST(LiquidBridge, TheSameBitsOnAnyThreadCountAndVectorBuild) {
  SimulationConfig cfg = wetBed(1e-7);
  const granular::testing::SimdBuildGuard guard;
  std::uint64_t hash[3];
  double bridge[3];
  for (int run = 0; run < 3; ++run) {
    cfg.threads = run == 1 ? 2 : 1;
    if (run == 2 && !setSimdBuild(SimdBuild::Baseline)) break;
    Simulation sim = granular::testing::fallingGrid(4, 4, 3, cfg, 0.5);
    sim.run(3000);
    hash[run] = sim.stateHash();
    bridge[run] = sim.energy().of("bridge_J");
  }
  EXPECT_NE(bridge[0], 0.0);
  EXPECT_EQ(hash[0], hash[1]);
  EXPECT_EQ(bridge[0], bridge[1]);
  EXPECT_EQ(hash[0], hash[2]);
  EXPECT_EQ(bridge[0], bridge[2]);
}

TEST(LiquidBridge, ACheckpointCarriesTheBridgesBitForBit) {
  SimulationConfig cfg = wetBed(1e-7);
  Simulation straight = granular::testing::fallingGrid(3, 3, 3, cfg, 0.3);
  Simulation first = granular::testing::fallingGrid(3, 3, 3, cfg, 0.3);
  straight.run(6000);
  first.run(3000);
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("granular_bridge_" + std::to_string(::getpid()) + ".ckpt");
  writeCheckpoint(first, file, 7);
  Simulation resumed = readCheckpoint(file, 7);
  std::filesystem::remove(file);
  EXPECT_EQ(resumed.config().material.bridgeVolume, 1e-7);
  resumed.run(3000);
  EXPECT_EQ(straight.stateHash(), resumed.stateHash());
  EXPECT_NE(straight.energy().of("bridge_J"), 0.0);
  EXPECT_EQ(straight.energy().of("bridge_J"), resumed.energy().of("bridge_J"));
}

TEST(LiquidBridge, SurfaceTensionWithoutLiquidIsRefusedByName) {
  Material m = wet();
  m.bridgeVolume = 0.0;
  try {
    validateMaterial(m);
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("material.surface_tension"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("bridge_volume"), std::string::npos) << e.what();
  }
  m.surfaceTension = 0.0;  // no bridges: nothing needs a volume
  EXPECT_NO_THROW(validateMaterial(m));
}
