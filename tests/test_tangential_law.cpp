/// The tangential spring's two laws (docs/physics.md §1): Mindlin's k_t = (8/3) G/(2−ν) √(R h),
/// the paper's, and a constant k_t (material.tangential_law = "constant"). One sphere rests on
/// the floor under its weight, its contact point set slipping: the spring force is k_t ξ with the
/// law's k_t, the contact point oscillates at √(k_t/m_eff) while it sticks, and it slides when
/// the spring reaches μ F_n, at the time the harmonic solution gives.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "granular/contact_model.hpp"
#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "physics_fixtures.hpp"

using namespace granular;
using granular::testing::sphereMass;

namespace {

constexpr double kR = 0.03;  // [m]

/// The sphere of radius kR resting on the floor at its static overlap m g/(k_n R) under gravity
/// `g` (the normal load m g), its centre moving at `slip` along x without spin, so its contact
/// point slips at `slip`; no tangential dashpot, so the spring is the only tangential force.
Simulation restingSphere(const Material& material, double g, double slip, double stepFraction) {
  SimulationConfig cfg;
  cfg.material = material;
  cfg.material.tangentialDamping = 0.0;
  cfg.gravity = Vec3(0, 0, -g);
  cfg.threads = 1;
  const double m = sphereMass(kR, material.density);
  cfg.timeStep = stiffestContact(cfg.material, kR, 1.0).duration / stepFraction;
  const double overlap = m * g / (material.normalCoefficient() * kR);
  Particles p;
  p.add(Vec3(0, 0, kR - overlap), kR, material.density, Vec3(slip, 0, 0));
  return Simulation(std::move(p), {Wall{"bottom", Vec3::Zero(), Vec3::UnitZ()}}, cfg);
}

Material constantLaw(double kt, double friction) {
  Material m;
  m.friction = friction;
  m.tangentialLaw = TangentialLaw::Constant;
  m.tangentialStiffness = kt;
  return m;
}

/// The sphere's one contact: its tangential force [N], normal force [N] and overlap [m].
struct FloorContact {
  double tangential = 0, normal = 0, overlap = 0;
};

FloorContact floorContact(const Simulation& sim) {
  FloorContact c;
  int seen = 0;
  sim.forEachContact([&](const ContactView& v) {
    const double fn = v.force.dot(v.normal);
    c.normal = std::abs(fn);
    c.tangential = (v.force - fn * v.normal).norm();
    c.overlap = v.overlap;
    ++seen;
  });
  EXPECT_EQ(seen, 1);
  return c;
}

/// The mass the contact point moves with: a tangential force F at arm a = R − h/2 accelerates it
/// by F/m + a² F/I (translation and spin), I = (2/5) m R².
double contactPointMass(double m, double h) {
  const double a = kR - 0.5 * h;
  return 1.0 / (1.0 / m + a * a / (0.4 * m * kR * kR));
}

}  // namespace

TEST(TangentialLaw, TheSpringForceIsKtTimesTheStretchWithTheLawsKt) {
  // |F_t| = k_t |ξ| and the stored energy ½ k_t |ξ|² give k_t = |F_t|²/(2 E_t) whatever ξ is:
  // the constant for the constant law at any normal load, Mindlin's (8/3) G/(2−ν) √(R h) at the
  // overlap, which grows as the load's square root.
  const double kt = 400.0;
  for (double g : {9.81, 4 * 9.81}) {
    SCOPED_TRACE("g = " + std::to_string(g));
    for (bool constant : {true, false}) {
      Material material = constant ? constantLaw(kt, 10.0) : Material{};
      material.friction = 10.0;  // the cap far away: the contact sticks
      Simulation sim = restingSphere(material, g, 1e-3, 100);
      sim.run(20);
      const FloorContact c = floorContact(sim);
      const double stored = sim.energy().of("elastic_tangential_J");
      ASSERT_GT(stored, 0.0);
      const double measured = c.tangential * c.tangential / (2.0 * stored);
      if (constant) {
        EXPECT_NEAR(measured, kt, 1e-9 * kt);
        EXPECT_EQ(sim.energy().of("tangential_stiffness_work_J"), 0.0);
      } else {
        // The energy is the step's (at the predicted overlap), the force the corrected state's:
        // the two overlaps differ by the normal motion of one step, far below 1e-6 here.
        const double mindlin = material.tangentialCoefficient() * std::sqrt(kR * c.overlap);
        EXPECT_NEAR(measured, mindlin, 1e-6 * mindlin);
      }
    }
  }
}

TEST(TangentialLaw, AStickingContactOscillatesAtTheConstantLawsFrequencyAtAnyLoad) {
  // While it sticks, the contact point's stretch obeys m_eff ξ'' = −k_t ξ: its velocity changes
  // sign every half-period π √(m_eff/k_t). A constant k_t gives the same period under one and
  // four times the load; Mindlin's k_t ∝ √h makes it 4^(1/4) shorter under four times the load.
  const double kt = 400.0, slip = 1e-3;
  auto halfPeriod = [&](const Material& material, double g) {
    Simulation sim = restingSphere(material, g, slip, 200);
    const double m = sim.particles().mass[0];
    auto contactPointVelocity = [&] {
      const Particles& p = sim.particles();
      const double h = kR - p.position[0].z();
      return p.velocity[0].x() - (kR - 0.5 * h) * p.angularVelocity[0].y();
    };
    // The first two sign changes of the contact point's velocity, linearly interpolated.
    std::vector<double> crossings;
    double before = contactPointVelocity(), t0 = sim.time();
    while (crossings.size() < 2 && sim.time() < 1.0) {
      sim.step();
      const double now = contactPointVelocity();
      if ((before > 0) != (now > 0)) {
        crossings.push_back(t0 + (sim.time() - t0) * before / (before - now));
      }
      before = now;
      t0 = sim.time();
    }
    EXPECT_EQ(crossings.size(), 2u);
    const double h = m * g / (sim.config().material.normalCoefficient() * kR);
    return std::pair{crossings.size() == 2 ? crossings[1] - crossings[0] : 0.0,
                     contactPointMass(m, h)};
  };
  const Material constant = constantLaw(kt, 10.0);
  for (double g : {9.81, 4 * 9.81}) {
    const auto [measured, mass] = halfPeriod(constant, g);
    EXPECT_NEAR(measured, std::numbers::pi * std::sqrt(mass / kt), 1e-3 * measured) << g;
  }
  // Mindlin: k_t ∝ √h ∝ √load; m_eff also grows a little with the load (the arm R − h/2 shrinks).
  Material mindlin;
  mindlin.friction = 10.0;
  const auto [light, lightMass] = halfPeriod(mindlin, 9.81);
  const auto [heavy, heavyMass] = halfPeriod(mindlin, 4 * 9.81);
  EXPECT_NEAR(light / heavy, std::pow(4.0, 0.25) * std::sqrt(lightMass / heavyMass), 1e-3);
}

TEST(TangentialLaw, TheContactSticksBelowTheCapAndSlidesWhenTheSpringReachesMuFn) {
  // Sticking, F_t = u √(k_t m_eff) sin(ω t), ω = √(k_t/m_eff), for a contact point set slipping
  // at u. Below u* = μ m g/√(k_t m_eff) it peaks at u/u* of the cap and never slides; above, it
  // reaches the cap μ F_n at t* = asin(u*/u)/ω and stays there while sliding.
  const double kt = 400.0, mu = 0.3, g = 9.81;
  const Material material = constantLaw(kt, mu);
  const double m = sphereMass(kR, material.density);
  const double h = m * g / (material.normalCoefficient() * kR);
  const double mass = contactPointMass(m, h), omega = std::sqrt(kt / mass);
  const double critical = mu * m * g / std::sqrt(kt * mass);
  for (double factor : {0.8, 1.25}) {
    SCOPED_TRACE("slip " + std::to_string(factor) + " u*");
    Simulation sim = restingSphere(material, g, factor * critical, 200);
    const double dt = sim.config().timeStep;
    double peak = 0, capReached = -1, capRatio = 0;
    while (sim.time() < std::numbers::pi / omega) {  // half a period: the sticking peak is in it
      sim.step();
      const FloorContact c = floorContact(sim);
      peak = std::max(peak, c.tangential);
      capRatio = std::max(capRatio, c.tangential / (mu * c.normal));
      if (capReached < 0 && c.tangential >= (1 - 1e-12) * mu * c.normal) capReached = sim.time();
    }
    if (factor < 1) {
      // The stretch is advanced by v_t Δt from the predicted velocity, a rectangle rule: its
      // amplitude is off by about ω Δt/2 (0.3 % at this step) of the harmonic solution's.
      EXPECT_LT(capReached, 0.0);
      EXPECT_NEAR(peak / (mu * m * g), factor, omega * dt * factor);
    } else {
      EXPECT_NEAR(capRatio, 1.0, 1e-12);  // capped exactly at μ F_n, never above
      const double predicted = std::asin(1.0 / factor) / omega;
      EXPECT_NEAR(capReached, predicted, 2 * dt) << "predicted " << predicted << " s";
      EXPECT_GT(sim.energy().of("dissipated_friction_J"), 0.0);
    }
  }
}

TEST(TangentialLaw, TheConstantLawNeedsItsStiffness) {
  Material m;
  m.friction = 0.3;
  m.tangentialLaw = TangentialLaw::Constant;
  try {
    validateMaterial(m);
    ADD_FAILURE() << "the constant law without k_t was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              "material.tangential_law = \"constant\": needs tangential_stiffness > 0 N/m, the "
              "constant law's k_t");
  }
  m.tangentialStiffness = 500.0;
  EXPECT_NO_THROW(validateMaterial(m));
  // Mindlin ignores the stiffness, set or not.
  m.tangentialLaw = TangentialLaw::Mindlin;
  EXPECT_NO_THROW(validateMaterial(m));
  m.tangentialStiffness = 0.0;
  EXPECT_NO_THROW(validateMaterial(m));
  // Without friction the spring acts on nothing: the law is accepted without its k_t.
  m.tangentialLaw = TangentialLaw::Constant;
  m.friction = 0.0;
  EXPECT_NO_THROW(validateMaterial(m));
  EXPECT_EQ(Material{}.tangentialLaw, TangentialLaw::Mindlin);  // the paper's law by default
}

TEST(TangentialLaw, AStiffConstantSpringShortensTheStepLimitToItsHalfPeriod) {
  // The stiffest contact is two smallest spheres (m_ij = m/2): the half-period of a sticking
  // contact point, π √(m_ij/(3.5 k_t)), joins the normal duration where shorter. Mindlin's, and
  // a soft constant k_t, leave the normal duration alone.
  Material mindlin;
  mindlin.friction = 0.3;
  const double normal = stiffestContact(mindlin, kR, 1.0).duration;
  Material soft = constantLaw(100.0, 0.3);
  EXPECT_EQ(stiffestContact(soft, kR, 1.0).duration, normal);
  const double kt = 1e5, m = sphereMass(kR, mindlin.density);
  const ContactScale stiff = stiffestContact(constantLaw(kt, 0.3), kR, 1.0);
  EXPECT_NEAR(stiff.duration, std::numbers::pi * std::sqrt(0.5 * m / (3.5 * kt)),
              1e-12 * stiff.duration);
  EXPECT_FALSE(stiff.againstWall);
  EXPECT_TRUE(stiff.tangentialSpring);
  EXPECT_FALSE(stiffestContact(soft, kR, 1.0).tangentialSpring);
  // The refusal names what sets the limit.
  try {
    requireStableStep(stiff.duration / 5, stiff, Integrator::Gear5);
    ADD_FAILURE() << "a step of a fifth of the half-period was accepted under gear5";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("half-period"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("constant tangential spring"), std::string::npos)
        << e.what();
  }
  // Without friction the tangential spring does nothing and limits nothing.
  EXPECT_EQ(stiffestContact(constantLaw(kt, 0.0), kR, 1.0).duration, normal);
}
