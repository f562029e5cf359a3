/// Hard cases: impacts at the edge of the stable step, a stiff material, a 10:1 size ratio, a long
/// static hold, stick-slip on a moving or tilted floor, coincident centres, bad scenes and a
/// million particles. Every expected number comes from the physics (closed forms, conservation,
/// equilibrium), never from a previous run.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "granular/impact_probe.hpp"
#include "granular/network_step.hpp"
#include "granular/scene.hpp"
#include "granular/simulation.hpp"
#include "granular/stress.hpp"
#include "physics_fixtures.hpp"

using namespace granular;
using granular::testing::measureImpact;
using granular::testing::sphereMass;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.81;

struct IntegratorCase {
  Integrator integrator;
  const char* name;
  bool automatic = false;  ///< time_step = "auto"
};
const IntegratorCase kIntegrators[] = {{Integrator::Gear5, "gear5"},
                                       {Integrator::VelocityVerlet, "verlet"}};
/// Both integrators at a fixed step and at time_step = "auto".
const IntegratorCase kSteppings[] = {{Integrator::Gear5, "gear5", false},
                                     {Integrator::VelocityVerlet, "verlet", false},
                                     {Integrator::Gear5, "gear5 auto", true},
                                     {Integrator::VelocityVerlet, "verlet auto", true}};

/// splitmix64 in [0, 1): reproducible on every platform.
class Uniform {
 public:
  explicit Uniform(std::uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ULL + 1) {}
  double operator()() {
    state_ += 0x9E3779B97F4A7C15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t state_;
};

/// Duration of a damped Hooke contact (spring k, dashpot γ·m on mass m) until the clamped force
/// vanishes: h = A e^{-βt} sin(ω_d t) with β = γ/2, ω_d = sqrt(k/m - β²), and k h + γ m ḣ = 0
/// first at ω_d t = π - atan2(γ m ω_d, k - γ m β).
double hookeForceDuration(double k, double gamma, double m) {
  const double beta = 0.5 * gamma;
  const double omegaD = std::sqrt(k / m - beta * beta);
  return (kPi - std::atan2(gamma * m * omegaD, k - gamma * m * beta)) / omegaD;
}

double fractionOf(Integrator integrator) {
  return integrator == Integrator::Gear5 ? kMaxStepFractionGear5 : kMaxStepFractionVerlet;
}

/// The single wall contact of particle 0 (force on the particle), or zero when there is none.
Vec3 wallContactForce(const Simulation& sim) {
  Vec3 f = Vec3::Zero();
  sim.forEachContact([&](const ContactView& c) {
    if (c.particle == 0 && c.isWall()) f += c.force;
  });
  return f;
}

Wall floorWall() {
  return Wall{"bottom", Vec3::Zero(), Vec3::UnitZ()};
}

}  // namespace

// ---- 1. Fast impact at the edge of the stable step -------------------------------------------

TEST(HardCase, ImpactAtTheStableStepLimitBouncesBackWithHertzOverlap) {
  // Undamped Hertz, F = K h^{3/2}: energy conservation ½ m v² = (2/5) K h_max^{5/2} gives the
  // peak overlap h_max = (5 m v² / (4 K))^{2/5} and restitution exactly 1. The speed is chosen
  // so that h_max = 8 % of the radius (the largest overlap for which the small-overlap contact
  // law still means something), v = sqrt(4 K h_max^{5/2} / (5 m)). The step is chosen by the
  // engine (time_step = "auto"): the network's step, which counts the coming contact at the
  // overlap the impact will reach, or the accuracy floor t_c/10, whichever is shorter (Verlet:
  // the floor; Gear: its interval at the peak stiffness, ≈ t_c/40).
  // Tolerances: at t_c/10 the largest overlap is sampled up to Δt/2 = t_c/20 from the
  // true peak, which on a half-sine costs 1 - cos(π/20) = 1.2 %, and the scheme's own O(Δt²)
  // error over one contact is of the same size: 3 % for both quantities.
  Material mat;
  mat.normalLaw = NormalLaw::Hertz;
  mat.normalDamping = 0.0;
  const double r = 0.03, m = sphereMass(r, mat.density), hMax = 0.08 * r;
  auto speedFor = [&](double hertzK, double reducedMass) {
    return std::sqrt(4.0 * hertzK * std::pow(hMax, 2.5) / (5.0 * reducedMass));
  };
  for (const IntegratorCase& c : kIntegrators) {
    // (a) Sphere on the floor: the wall has infinite radius and mass, R* = R, m* = m.
    {
      const double hertzK = mat.normalCoefficient() * std::sqrt(r);
      const double v = speedFor(hertzK, m);
      Particles p;
      p.add(Vec3(0, 0, r + 1e-4), r, mat.density, Vec3(0, 0, -v));
      SimulationConfig cfg;
      cfg.material = mat;
      cfg.gravity = Vec3::Zero();
      cfg.integrator = c.integrator;
      cfg.impactSpeed = v;
      cfg.step.automatic = true;
      cfg.threads = 1;
      Simulation sim(std::move(p), {floorWall()}, cfg);
      const double dt = sim.config().timeStep;
      EXPECT_GT(dt, 0.5 * maxStableStep(sim.contactScale(), c.integrator)) << c.name;
      EXPECT_LE(dt, sim.contactScale().duration / 10) << c.name;
      const auto got = measureImpact(
          sim,
          [](const Simulation& s) {
            return s.particles().radius[0] - s.particles().position[0].z();
          },
          v, 0, Vec3::UnitZ(), 1.0);
      const Vec3 x = sim.particles().position[0];
      EXPECT_GT(x.z(), r) << c.name << ": the sphere must end above the floor";
      EXPECT_GT(got.velocityAfter.z(), 0.0) << c.name << ": velocity reversed";
      EXPECT_NEAR(got.restitution, 1.0, 0.03) << c.name << " wall, dt = " << dt;
      EXPECT_NEAR(got.peakOverlap, hMax, 0.03 * hMax) << c.name << " wall";
      EXPECT_LT(got.peakOverlap, 0.1 * r) << c.name;
    }
    // (b) Two equal spheres head-on: R* = R/2, m* = m/2, approach speed v.
    {
      PairImpactSpec spec;
      spec.material = mat;
      spec.integrator = c.integrator;
      spec.radius = r;
      spec.approachSpeed = speedFor(mat.normalCoefficient() * std::sqrt(0.5 * r), 0.5 * m);
      spec.timeStep = 1e-7;
      Simulation sim = makePairImpact(spec);
      StepControl automatic;
      automatic.automatic = true;
      sim.setStepControl(automatic);
      EXPECT_GT(sim.config().timeStep, 0.5 * maxStableStep(sim.contactScale(), c.integrator));
      const ImpactMeasurement got = measurePairImpact(sim, spec.approachSpeed, 1.0);
      const Particles& p = sim.particles();
      ASSERT_TRUE(got.separated) << c.name;
      EXPECT_GT(p.position[1].x() - p.position[0].x(), 2.0 * r) << c.name << ": no tunnelling";
      EXPECT_LT(p.velocity[0].x(), 0.0) << c.name;
      EXPECT_GT(p.velocity[1].x(), 0.0) << c.name;
      EXPECT_NEAR(got.restitution, 1.0, 0.03) << c.name << " pair";
      EXPECT_NEAR(got.peakOverlap, hMax, 0.03 * hMax) << c.name << " pair";
    }
  }
}

// ---- 2. Stiff material ------------------------------------------------------------------------

TEST(HardCase, StiffMaterialRefusesTheSoftStepAndImpactsAtHalfItsLimit) {
  // E and G × 1000. For an undamped Hooke contact t_c = π sqrt(m/k) with k = (2/3)E/(1-ν²) R, so
  // the duration, and every step limit with it, shrinks exactly by sqrt(1000). With the paper's
  // damping γn = 60 1/s the duration is (π - atan2(γ m ω_d, k - γ m β)) / ω_d: the limit must be
  // the integrator's fraction of that, for the stiffest contact (the smallest sphere; for Hooke
  // a wall and an equal sphere have the same k/m).
  const Material soft;
  Material stiff = soft;
  stiff.youngModulus *= 1000.0;
  stiff.shearModulus *= 1000.0;
  const double r = 0.03, m = sphereMass(r, soft.density);
  {
    Material soft0 = soft, stiff0 = stiff;
    soft0.normalDamping = stiff0.normalDamping = 0.0;
    const double tSoft = stiffestContact(soft0, r, 1.0).duration;
    const double tStiff = stiffestContact(stiff0, r, 1.0).duration;
    EXPECT_NEAR(tStiff, kPi * std::sqrt(m / (stiff0.normalCoefficient() * r)), 1e-12 * tStiff);
    EXPECT_NEAR(tSoft / tStiff, std::sqrt(1000.0), 1e-9 * std::sqrt(1000.0));
  }
  const double tStiff = hookeForceDuration(stiff.normalCoefficient() * r, stiff.normalDamping, m);
  const double v0 = 1.0;
  for (const IntegratorCase& c : kIntegrators) {
    SimulationConfig cfg;
    cfg.integrator = c.integrator;
    cfg.gravity = Vec3::Zero();
    cfg.threads = 1;
    auto sphereOnFloor = [&](const Material& mat, double dt) {
      Particles p;
      p.add(Vec3(0, 0, r + 1e-5), r, mat.density, Vec3(0, 0, -v0));
      SimulationConfig c2 = cfg;
      c2.material = mat;
      c2.timeStep = dt;
      return Simulation(std::move(p), {floorWall()}, c2);
    };
    // A step well inside the soft material's limit...
    const double softStep =
        0.5 * maxStableStep(stiffestContact(soft, r, cfg.impactSpeed), c.integrator);
    EXPECT_NO_THROW(sphereOnFloor(soft, softStep)) << c.name;
    // ... is refused for the stiff one, naming the step its coming contact allows. For one
    // contact the network's bound is exact: ω = √(k/m), damping rate γn, so the step is the
    // integrator's interval at ζ = γn/(2ω), over ω.
    const double limit = fractionOf(c.integrator) * tStiff;
    const ContactScale stiffScale = sphereOnFloor(stiff, 1e-9).contactScale();
    EXPECT_NEAR(maxStableStep(stiffScale, c.integrator), limit, 1e-12 * limit) << c.name;
    const double omega = std::sqrt(stiff.normalCoefficient() * r / m);
    const double zeta = stiff.normalDamping / (2 * omega);
    const double networkLimit = stableOmegaDtOver(c.integrator, zeta, zeta) / omega;
    EXPECT_LT(networkLimit, softStep) << c.name;
    try {
      sphereOnFloor(stiff, softStep);
      ADD_FAILURE() << c.name << ": the soft material's step was accepted for the stiff one";
    } catch (const ConfigError& e) {
      // Gear5 keeps its binary limit (stricter here); Verlet's is the network's.
      std::ostringstream shown;
      if (c.integrator == Integrator::Gear5) {
        shown << "above the stable limit " << maxStableStep(stiffScale, c.integrator) << " s";
      } else {
        shown.precision(4);
        shown << "above the step the contact network allows, " << networkLimit << " s";
      }
      EXPECT_NE(std::string(e.what()).find(shown.str()), std::string::npos) << e.what();
    }
    // At half the new limit an impact is clean: the energy balance holds (the only error is the
    // integrator's, first order in Δt/t_c because the dashpot force jumps at the first touch:
    // at Δt = t_c/20 (Verlet) or t_c/100 (Gear) 1 % of the impact energy is a generous bound)
    // and the restitution is the clamped damped-oscillator value within 1 %.
    Simulation sim = sphereOnFloor(stiff, 0.5 * limit);
    const double e0 = 0.5 * m * v0 * v0;
    double worstDrift = 0.0;
    auto overlap = [&worstDrift, e0](const Simulation& s) {
      worstDrift = std::max(worstDrift, std::abs(s.energy().total() - e0));
      return s.particles().radius[0] - s.particles().position[0].z();
    };
    const auto got = measureImpact(sim, overlap, v0, 0, Vec3::UnitZ(), 0.1);
    const double expected =
        hookeDampedImpact(stiff.normalCoefficient() * r, stiff.normalDamping, m, v0).restitution;
    EXPECT_GT(got.restitution, 0.0) << c.name;
    EXPECT_LT(got.restitution, 1.0) << c.name;
    EXPECT_NEAR(got.restitution, expected, 0.01 * expected) << c.name;
    EXPECT_LT(worstDrift, 0.01 * e0) << c.name;
    EXPECT_TRUE(sim.particles().position[0].allFinite());
    EXPECT_GT(sim.particles().position[0].z(), r) << c.name;
  }
}

// ---- 3. Size ratio 10:1 ------------------------------------------------------------------------

namespace {

constexpr double kLarge = 0.05, kSmall = 0.005;
constexpr double kBoxX = 0.2, kBoxY = 0.1;

/// A jammed bed with a 10:1 size ratio: 200 small spheres (R = 0.005 m) in a square monolayer
/// that fills the floor of a 0.2 × 0.1 m box wall to wall, and two large spheres (R = 0.05 m)
/// touching the side walls and each other, each just above a hollow of four small ones. (Loose
/// spheres on a floor never come to rest: nothing stops a sphere rolling on a plane, so a bed
/// that must be static is built jammed.)
Simulation bimodalBed(const SimulationConfig& cfg) {
  Particles p;
  // Each large sphere rests on the four small ones of a hollow, √2 R_s away horizontally: it
  // touches them at height z0 = R_s + sqrt((R_L + R_s)² - 2 R_s²), at cos α = (z0 - R_s)/(R_L +
  // R_s) from the vertical. It starts near its static height (so that it need not fall into it and
  // ring: the dashpots, scaled by the small spheres' masses, damp its bounce slowly): each of the
  // four contacts carries F = m_L g / (4 cos α), sinking it by F/k_ls along the contact normal,
  // and each small sphere carries F cos α + m_s g on the floor.
  const Material& mat = cfg.material;
  const double mL = sphereMass(kLarge, mat.density), mS = sphereMass(kSmall, mat.density);
  const double z0 = kSmall + std::sqrt(std::pow(kLarge + kSmall, 2) - 2.0 * kSmall * kSmall);
  const double cosA = (z0 - kSmall) / (kLarge + kSmall);
  const double force = mL * kG / (4.0 * cosA);
  const double kLS = mat.normalCoefficient() * kLarge * kSmall / (kLarge + kSmall);
  const double kSW = mat.normalCoefficient() * kSmall;
  const double zLarge = z0 - force / kLS / cosA - (force * cosA + mS * kG) / kSW;
  p.add(Vec3(kLarge, kLarge, zLarge), kLarge, cfg.material.density);
  p.add(Vec3(3 * kLarge, kLarge, zLarge), kLarge, cfg.material.density);
  for (int j = 0; j < 10; ++j) {
    for (int i = 0; i < 20; ++i) {
      p.add(Vec3((2 * i + 1) * kSmall, (2 * j + 1) * kSmall, kSmall), kSmall, cfg.material.density);
    }
  }
  BoxSpec box;
  box.min = Vec3::Zero();
  box.max = Vec3(kBoxX, kBoxY, 1.0);
  return Simulation(std::move(p), buildWalls(box), cfg);
}

/// Compares the contacts reported by forEachContact with an O(N²) search over all pairs and
/// walls, using the engine's own tests (pair: |d|² < (R_i + R_j)²; wall: R - distance > 0).
void expectContactsMatchBruteForce(const Simulation& sim, const char* when,
                                   std::size_t largeSmallAtLeast) {
  const Particles& p = sim.particles();
  using Contact = std::tuple<std::size_t, ContactView::Other, std::size_t>;  // i, kind, index
  std::set<Contact> brute, reported;
  std::size_t largeSmall = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double reach = p.radius[i] + p.radius[j];
      if ((p.position[j] - p.position[i]).squaredNorm() < reach * reach) {
        brute.insert({i, ContactView::Other::Particle, j});
        brute.insert({j, ContactView::Other::Particle, i});  // seen from both sides
        if (p.radius[i] != p.radius[j]) ++largeSmall;
      }
    }
    for (std::size_t w = 0; w < sim.walls().size(); ++w) {
      const Wall& wall = sim.walls()[w];
      if (p.radius[i] - (p.position[i] - wall.point).dot(wall.normal) > 0.0) {
        brute.insert({i, ContactView::Other::Wall, w});
      }
    }
  }
  std::size_t views = 0;
  sim.forEachContact([&](const ContactView& c) {
    reported.insert({c.particle, c.otherKind, c.otherIndex});
    ++views;
  });
  EXPECT_EQ(views, reported.size()) << when << ": a contact was reported twice";
  EXPECT_GE(largeSmall, largeSmallAtLeast) << when;
  std::vector<Contact> missed, spurious;
  std::set_difference(brute.begin(), brute.end(), reported.begin(), reported.end(),
                      std::back_inserter(missed));
  std::set_difference(reported.begin(), reported.end(), brute.begin(), brute.end(),
                      std::back_inserter(spurious));
  if (!missed.empty()) {
    const auto [i, kind, index] = missed[0];
    ADD_FAILURE() << when << ": " << missed.size() << " contacts missed, first: particle " << i
                  << " with " << (kind == ContactView::Other::Wall ? "wall " : "particle ")
                  << index;
  }
  EXPECT_TRUE(spurious.empty()) << when << ": " << spurious.size() << " spurious contacts";
}

}  // namespace

TEST(HardCase, SizeRatioTenContactSearchBalanceAndStressIdentity) {
  // (a) The cell grid is sized by the largest pair: every small sphere's contacts with a large
  //     one must still be found, while the large spheres sink in and at rest.
  // (b) At rest the walls carry the whole weight: Σ_walls R = Σ m g (R the force of the particles
  //     on a wall), to 1e-3 of W.
  // (c) Love-Weber: V σ(Eq. 1) = Σ_wall contacts F ⊗ x_c - Σ_p F_p ⊗ x_p exactly (F_p the net
  //     contact force: particle pairs cancel), and at rest F_p = -m_p g, so
  //     V σ(Eq. 1) = Σ_wall contacts F ⊗ x_c + Σ_p m_p g ⊗ x_p to the same 1e-3.
  // E × 10 keeps the overlaps under a large sphere (its weight on four small ones) near 1 % of
  // the small radius; the paper's soft material would let it sink by 13 %.
  // At a fixed step (t_c/20) and at time_step = "auto".
  for (bool automatic : {false, true}) {
    SCOPED_TRACE(automatic ? "auto" : "fixed");
    SimulationConfig cfg;
    cfg.material.youngModulus *= 10.0;
    cfg.material.shearModulus *= 10.0;
    cfg.material.friction = 0.3;
    cfg.material.normalDamping = 8000.0;
    cfg.material.tangentialDamping = 100.0;
    cfg.integrator = Integrator::VelocityVerlet;
    cfg.threads = 1;
    cfg.timeStep = stiffestContact(cfg.material, kSmall, 1.0).duration / 20;
    cfg.step.automatic = automatic;
    Simulation sim = bimodalBed(cfg);
    ASSERT_EQ(sim.particles().size(), 202u);
    const Particles& p = sim.particles();
    double weight = 0;
    for (std::size_t i = 0; i < p.size(); ++i) weight += p.mass[i] * kG;

    while (sim.time() < 0.005) sim.step();  // the large spheres land on the small ones
    ASSERT_GT(sim.kineticEnergy(), 1e-8);
    expectContactsMatchBruteForce(sim, "landing", 8);
    while (sim.time() < 0.8) sim.step();
    expectContactsMatchBruteForce(sim, "at rest", 8);
    // Kinetic energy of the whole mass moving at 1 mm/s: a bed at rest is far below it.
    ASSERT_LT(sim.kineticEnergy(), 0.5 * (weight / kG) * 1e-6);

    Vec3 reactions = Vec3::Zero();
    for (const Wall& w : sim.walls()) reactions += w.reaction;
    EXPECT_NEAR(reactions.z(), -weight, 1e-3 * weight);  // pushed down by the weight
    EXPECT_NEAR(reactions.x(), 0.0, 1e-3 * weight);
    EXPECT_NEAR(reactions.y(), 0.0, 1e-3 * weight);
    const BoxStress box = measureBox(sim);
    EXPECT_LT(std::abs(box.balanceError), 1e-3);

    const double volume = kBoxX * kBoxY * 0.11;
    const Mat3 lhs = volume * volumeAveragedStress(sim, volume);
    Mat3 walls = Mat3::Zero();
    sim.forEachContact([&](const ContactView& c) {
      if (c.isWall()) walls += c.force * c.point.transpose();
    });
    Mat3 exact = walls, statics = walls;
    const std::vector<Vec3> net = sim.netContactForces();
    for (std::size_t i = 0; i < p.size(); ++i) {
      exact -= net[i] * p.position[i].transpose();
      statics += p.mass[i] * cfg.gravity * p.position[i].transpose();
    }
    const double scale = lhs.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 0.0);
    EXPECT_LT((lhs - exact).cwiseAbs().maxCoeff(), 1e-11 * scale) << lhs << "\n\n" << exact;
    EXPECT_LT((lhs - statics).cwiseAbs().maxCoeff(), 1e-3 * scale) << lhs << "\n\n" << statics;
  }
}

// ---- 4. Long static hold ---------------------------------------------------------------------

namespace {

/// 26 equal spheres (R = 0.03 m) stacked body-centred in a box of side 6R: layers of 3 × 3 and
/// 2 × 2 alternating, each sphere in the hollow of the layer below (layers √2 R apart), the
/// 3 × 3 layers wall to wall. Every sphere is caged, so the bed can come to rest (a loose sphere
/// on a plane would roll for ever: there is no rolling resistance). A 1e-7 m gap everywhere.
Simulation stackedBed(const SimulationConfig& cfg) {
  const double r = 0.03, rise = std::sqrt(2.0) * r, gap = 1e-7;
  Particles p;
  for (int layer = 0; layer < 4; ++layer) {
    const int m = layer % 2 == 0 ? 3 : 2;
    const double offset = layer % 2 == 0 ? r : 2 * r;
    for (int j = 0; j < m; ++j) {
      for (int i = 0; i < m; ++i) {
        p.add(Vec3(offset + 2 * r * i, offset + 2 * r * j, r + layer * (rise + gap) + gap), r,
              cfg.material.density);
      }
    }
  }
  BoxSpec box;
  box.max = Vec3(6 * r, 6 * r, 1.0);
  return Simulation(std::move(p), buildWalls(box), cfg);
}

}  // namespace

TEST(HardCase, SettledBedHoldsStillForTenSeconds) {
  // 26 frictional spheres settled with strong damping, then held 10 s. Bounds:
  // - kinetic energy: the bed's energy above its rest state, E = K + U - U_rest, only decreases
  //   (dashpots and friction dissipate, walls are fixed) and in the last second of settling,
  //   many periods of the bed's slowest mode, K reached E at its peaks; so during the hold K must
  //   stay below the largest K of that last second (or below round-off: K of the bed's mass M at
  //   1e-12 m/s, a speed that moves nothing measurably in 10 s);
  // - displacement: at most 1e-6 m, 1 % of a typical overlap (≈ 1e-4 m): any creep of the
  //   contact springs (tangential spring rotation, the stiffness-work term) would show;
  // - energy balance: with every particle within 1e-6 m the work terms can change by at most
  //   W · 1e-6 m (W the weight), so total() may drift by no more than that.
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.material.normalDamping = 400.0;
  cfg.material.tangentialDamping = 100.0;
  cfg.integrator = Integrator::VelocityVerlet;
  cfg.threads = 1;
  cfg.step.automatic = true;  // this damping: the network allows less than t_c/20
  Simulation sim = stackedBed(cfg);
  const Particles& p = sim.particles();
  double weight = 0;
  for (std::size_t i = 0; i < p.size(); ++i) weight += p.mass[i] * kG;
  double kineticBound = 0;
  while (sim.time() < 2.0) {
    sim.step();
    if (sim.time() > 1.0) kineticBound = std::max(kineticBound, sim.kineticEnergy());
  }
  // Each sphere of a 2 × 2 layer sits on four below and layer 2's carry four above: 48 pairs.
  ASSERT_GE(sim.counters().particleContacts, 48u);
  const std::vector<Vec3> start = p.position;
  const double total0 = sim.energy().total();
  const double end = sim.time() + 10.0;
  double worstKinetic = 0, worstDrift = 0;
  while (sim.time() < end) {
    sim.step();
    worstKinetic = std::max(worstKinetic, sim.kineticEnergy());
    if (sim.stepCount() % 100 == 0) {
      worstDrift = std::max(worstDrift, std::abs(sim.energy().total() - total0));
    }
  }
  double worstMove = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    worstMove = std::max(worstMove, (p.position[i] - start[i]).norm());
  }
  double mass = weight / kG;
  EXPECT_LE(worstKinetic, std::max(kineticBound, 0.5 * mass * 1e-24));
  EXPECT_LT(worstMove, 1e-6);
  EXPECT_LT(worstDrift, weight * 1e-6);
}

// ---- 5. Stick-slip on the floor ----------------------------------------------------------------

namespace {

/// A sphere of the paper's material resting on the floor at its static overlap m g_n / k
/// (so no normal oscillation starts), μ = 0.3, gravity `g`; at half Gear5's binary limit, or
/// with `automatic` at time_step = "auto".
Simulation sphereResting(const Vec3& g, Integrator integrator, double& radius,
                         bool automatic = false) {
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.integrator = integrator;
  cfg.gravity = g;
  cfg.threads = 1;
  cfg.step.automatic = automatic;
  const double r = 0.03, m = sphereMass(r, cfg.material.density);
  cfg.timeStep = 0.5 * maxStableStep(stiffestContact(cfg.material, r, 1.0), Integrator::Gear5);
  const double overlap = m * -g.z() / (cfg.material.normalCoefficient() * r);
  Particles p;
  p.add(Vec3(0, 0, r - overlap), r, cfg.material.density);
  radius = r;
  return Simulation(std::move(p), {floorWall()}, cfg);
}

/// Velocity of the contact point of particle 0 on the floor, relative to the floor.
Vec3 slipVelocity(const Simulation& sim) {
  const Particles& p = sim.particles();
  const double h = p.radius[0] - p.position[0].z();
  const Vec3 arm(0, 0, -(p.radius[0] - 0.5 * h));  // centre to contact point
  return p.velocity[0] + p.angularVelocity[0].cross(arm) - sim.walls()[0].velocity;
}

}  // namespace

TEST(HardCase, SphereOnASlidingFloorSlipsThenRollsAtTwoSevenths) {
  // The floor starts moving at V along x under a sphere at rest. The sphere slips: friction is
  // at the Coulomb cap μ m g, so v = μ g t and ω_y = -(5/2) μ g t / R (I = 2/5 m R²); the
  // contact point's speed v - R ω_y = (7/2) μ g t reaches V at t* = 2V/(7 μ g), and from then on
  // the sphere rolls at v = 2V/7 (angular momentum about the contact point is conserved, since
  // friction acts there). The slip phase is identified by the force: |F_t| = μ F_n to round-off
  // while capped. Delays: the tangential spring needs μ m g / k_t / V ≈ 0.6 ms to load (0.6 % of
  // t*); the lever arm R - h/2 changes I/(m a²) by h/R ≈ 0.3 %: 2 % on t*, 1 % on the rest.
  const double mu = 0.3, V = 1.0, tStar = 2.0 * V / (7.0 * mu * kG);
  for (const IntegratorCase& c : kSteppings) {
    double r = 0;
    Simulation sim = sphereResting(Vec3(0, 0, -kG), c.integrator, r, c.automatic);
    sim.setWallVelocity(0, Vec3(V, 0, 0));
    double slipStart = -1, slipEnd = -1, v1 = 0, v2 = 0;
    const double t1 = 0.2 * tStar, t2 = 0.8 * tStar;
    double tPrev = 0, vPrev = 0;
    while (sim.time() < tStar + 0.3) {
      sim.step();
      const double t = sim.time(), v = sim.particles().velocity[0].x();
      if (tPrev < t1 && t >= t1) v1 = vPrev + (v - vPrev) * (t1 - tPrev) / (t - tPrev);
      if (tPrev < t2 && t >= t2) v2 = vPrev + (v - vPrev) * (t2 - tPrev) / (t - tPrev);
      tPrev = t;
      vPrev = v;
      if (slipEnd >= 0) continue;
      const Vec3 f = wallContactForce(sim);
      const double fn = f.z(), ft = std::hypot(f.x(), f.y());
      const bool capped = ft >= (1.0 - 1e-9) * mu * fn;
      if (capped && slipStart < 0) slipStart = t;
      if (!capped && slipStart >= 0) slipEnd = t;
    }
    ASSERT_GE(slipStart, 0.0) << c.name << ": never slipped";
    ASSERT_GE(slipEnd, 0.0) << c.name << ": never stuck";
    EXPECT_LT(slipStart, 0.01 * tStar) << c.name;
    EXPECT_NEAR((v2 - v1) / (t2 - t1), mu * kG, 0.01 * mu * kG) << c.name;
    EXPECT_NEAR(slipEnd, tStar, 0.02 * tStar) << c.name;
    EXPECT_NEAR(sim.particles().velocity[0].x(), 2.0 * V / 7.0, 0.01 * 2.0 * V / 7.0) << c.name;
    EXPECT_LT(slipVelocity(sim).norm(), 0.01 * V) << c.name << ": rolling, no slip";
  }
}

TEST(HardCase, SphereOnATiltedFloorRollsBelowAndSlidesAboveTheCoulombLimit) {
  // Gravity tilted by θ about y pushes the sphere along x. Rolling without slip needs the
  // friction (2/7) m g sin θ, at most μ m g cos θ: it rolls for tan θ < (7/2) μ (46.4° at
  // μ = 0.3) with acceleration (5/7) g sin θ and zero slip at the contact point; above it slides
  // with g (sin θ - μ cos θ) while the slip speed grows at g (sin θ - (7/2) μ cos θ).
  // 35° and 55° bracket the limit. Accelerations from the velocities at 0.2 s and 0.4 s, after
  // the start-up (the tangential spring loading, its oscillation damped as e^{-35 t} by γt)
  // has died out; 1 % (the lever arm R - h/2 alone moves them by h/R ≈ 0.3 %).
  //
  // "A block pushed by a wall" is not added: without cohesion a block of spheres is not a rigid
  // body, and the pushing wall's own friction adds a vertical force to the normal load, so its
  // limit is not clean. The moving floor (previous test) and this one meet the same Coulomb
  // limit μ F_n from both sides: there in time (slip, then stick at t*), here in the load
  // (stick below tan θ = 7μ/2, slip above).
  const double mu = 0.3;
  for (const IntegratorCase& c : kSteppings) {
    for (double degrees : {35.0, 55.0}) {
      const double theta = degrees * kPi / 180.0;
      const bool rolls = std::tan(theta) < 3.5 * mu;
      double r = 0;
      Simulation sim = sphereResting(kG * Vec3(std::sin(theta), 0, -std::cos(theta)), c.integrator,
                                     r, c.automatic);
      while (sim.time() < 0.2) sim.step();
      const double vA = sim.particles().velocity[0].x(), tA = sim.time();
      const double slipA = slipVelocity(sim).x();
      while (sim.time() < 0.4) sim.step();
      const double vB = sim.particles().velocity[0].x(), tB = sim.time();
      const double slipB = slipVelocity(sim).x();
      const double accel = (vB - vA) / (tB - tA);
      const std::string what = std::string(c.name) + " at " + std::to_string(degrees) + " deg";
      if (rolls) {
        const double expect = 5.0 / 7.0 * kG * std::sin(theta);
        EXPECT_NEAR(accel, expect, 0.01 * expect) << what;
        EXPECT_LT(std::abs(slipB), 1e-3 * vB) << what << ": rolls without slipping";
      } else {
        const double expect = kG * (std::sin(theta) - mu * std::cos(theta));
        EXPECT_NEAR(accel, expect, 0.01 * expect) << what;
        const double slipRate = kG * (std::sin(theta) - 3.5 * mu * std::cos(theta));
        EXPECT_NEAR((slipB - slipA) / (tB - tA), slipRate, 0.02 * slipRate) << what;
      }
    }
  }
}

// ---- 6. Coincident centres ---------------------------------------------------------------------

TEST(HardCase, CoincidentCentresAreRefusedAndAZeroDistanceMidRunHasANormal) {
  // Two centres at the same point have no line of centres, so no contact normal: the
  // constructor refuses centres closer than 1e-9 (R_i + R_j), naming both particles. Overlap
  // itself is allowed (a restored packed state overlaps), down to that distance.
  for (double apart : {0.0, 1e-12}) {
    Particles p;
    p.add(Vec3(0.5, 0.5, 0.5), 0.03, 500.0);
    p.add(Vec3(0.2, 0.2, 0.2), 0.03, 500.0);
    p.add(Vec3(0.5 + apart, 0.5, 0.5), 0.03, 500.0);
    SimulationConfig cfg;
    try {
      Simulation sim(std::move(p), {}, cfg);
      ADD_FAILURE() << "centres " << apart << " m apart were accepted";
    } catch (const ConfigError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("particles 0 and 2"), std::string::npos) << msg;
    }
  }
  {
    Particles p;  // heavily overlapping, but 1e-6 m apart: accepted, pushed apart along x
    p.add(Vec3(0, 0, 0), 0.03, 500.0);
    p.add(Vec3(1e-6, 0, 0), 0.03, 500.0);
    SimulationConfig cfg;
    cfg.gravity = Vec3::Zero();
    cfg.threads = 1;
    Simulation sim(std::move(p), {}, cfg);
    sim.run(10);
    EXPECT_LT(sim.particles().velocity[0].x(), 0.0);
    EXPECT_GT(sim.particles().velocity[1].x(), 0.0);
    EXPECT_NEAR(sim.particles().velocity[0].y(), 0.0, 1e-12);
  }
  // Mid-run, a pair can still pass through distance 0. With E = 1e-300 Pa the contact forces
  // are far below one ulp of the velocities, so the spheres move exactly as in free flight:
  // the step size and speeds are powers of two and sphere 1 lands exactly on sphere 0's centre
  // at step 4. The force pass must use a defined normal there, not 0/0 (which would turn the
  // state into NaN and stop the run with a NumericalError).
  for (const IntegratorCase& c : kIntegrators) {
    for (double friction : {0.0, 0.3}) {
      Particles p;
      const double dt = 0x1p-10, v = 0x1p-4;
      // At x = 1 the forces' tiny accelerations (~1e-301 m/s²) are far below an ulp.
      p.add(Vec3(1, 0, 0), 0.03, 500.0);
      p.add(Vec3(1 + 4 * v * dt, 0, 0), 0.03, 500.0, Vec3(-v, 0, 0));
      SimulationConfig cfg;
      cfg.material.youngModulus = 1e-300;
      cfg.material.shearModulus = 1e-300;
      cfg.material.normalDamping = 0.0;
      cfg.material.tangentialDamping = 0.0;
      cfg.material.friction = friction;
      cfg.gravity = Vec3::Zero();
      cfg.integrator = c.integrator;
      cfg.timeStep = dt;
      cfg.threads = 1;
      Simulation sim(std::move(p), {}, cfg);
      bool coincided = false;
      for (int k = 0; k < 8; ++k) {
        ASSERT_NO_THROW(sim.step()) << c.name << " step " << k;
        const Particles& q = sim.particles();
        coincided |= (q.position[1] - q.position[0]).norm() < 1e-300;
        for (std::size_t i = 0; i < 2; ++i) {
          ASSERT_TRUE(q.position[i].allFinite() && q.velocity[i].allFinite()) << c.name;
        }
        EXPECT_EQ(sim.counters().particleContacts, 1u) << c.name;
      }
      EXPECT_TRUE(coincided) << c.name << ": the test must reach distance 0";
      std::size_t views = 0;
      sim.forEachContact([&](const ContactView& view) {
        EXPECT_TRUE(view.force.allFinite() && view.point.allFinite());
        ++views;
      });
      EXPECT_EQ(views, 2u);
    }
  }
}

// ---- 7. Bad scenes -----------------------------------------------------------------------------

TEST(HardCase, SceneWithAParticleOutsideOrOverlappingNamesIt) {
  // buildSimulation must refuse, before any step, a particle crossing a box face (naming its
  // index, position and the face) and two overlapping particles (naming both indices).
  auto error = [](const Scene& scene) {
    try {
      buildSimulation(scene);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    ADD_FAILURE() << "no ConfigError";
    return std::string();
  };
  Scene scene;
  scene.box.min = Vec3(0, 0, 0);
  scene.box.max = Vec3(1, 1, 1);
  GridGenerator grid;
  grid.origin = Vec3(0, 0, 0);
  grid.cellSize = 0.25;
  grid.cells = {4, 1, 1};
  grid.count = 4;
  grid.radiusMin = grid.radiusMax = 0.1;
  scene.generators.push_back(grid);
  EXPECT_NO_THROW(buildSimulation(scene));

  Scene outside = scene;
  std::get<GridGenerator>(outside.generators[0]).origin = Vec3(0.1, 0, 0);  // last one at 0.975
  std::string msg = error(outside);
  EXPECT_NE(msg.find("particle 3 "), std::string::npos) << msg;
  EXPECT_NE(msg.find("(0.975, 0.125, 0.125)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("x+"), std::string::npos) << msg;

  Scene overlapping = scene;
  GridGenerator second = grid;  // one more sphere 0.05 m from particle 1's centre
  second.origin = Vec3(0.3, 0, 0);
  second.cells = {1, 1, 1};
  second.count = 1;
  overlapping.generators.push_back(second);
  msg = error(overlapping);
  // Both named by their index and by the scene entry that made them.
  EXPECT_NE(msg.find("particle 1 (particles[0], grid particle 1) and particle 4 (particles[1], "
                     "grid particle 0) overlap"),
            std::string::npos)
      << msg;
}

// ---- 10. A million particles -------------------------------------------------------------------

TEST(HardCase, MillionParticleMemoryPerParticle) {
  // A 100³ simple cubic lattice of touching spheres (spacing 2R (1 + 1e-9)) on the floor of a
  // box, frictionless velocity Verlet, two steps. Per particle the model needs its state
  // (88 B), force and acceleration (48 B), reference position (24 B), its three candidate pairs
  // (3 × 8 B), their force slots (3 × 24 B) and the per-particle contact index (≈ 24 B): about
  // 280 B; 400 B leaves room for vector growth but not for an extra per-pair or per-particle
  // array of forces.
  const int side = 100;
  const double r = 0.03, spacing = 2.0 * r * (1.0 + 1e-9);
  const auto start = std::chrono::steady_clock::now();
  Particles p;
  const std::size_t n = std::size_t(side) * side * side;
  p.position.reserve(n);
  p.velocity.reserve(n);
  p.angularVelocity.reserve(n);
  p.radius.reserve(n);
  p.mass.reserve(n);
  for (int k = 0; k < side; ++k) {
    for (int j = 0; j < side; ++j) {
      for (int i = 0; i < side; ++i) {
        p.add(Vec3(r + i * spacing, r + j * spacing, r + k * spacing), r, 500.0);
      }
    }
  }
  BoxSpec box;
  box.max = Vec3(side * spacing, side * spacing, side * spacing + 1.0);
  SimulationConfig cfg;
  cfg.integrator = Integrator::VelocityVerlet;
  cfg.timeStep = 1e-4;
  Simulation sim(std::move(p), buildWalls(box), cfg);
  sim.run(2);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const MemoryUse use = sim.memoryUse();
  EXPECT_EQ(sim.particles().size(), n);
  EXPECT_EQ(sim.counters().neighbourPairs, 3u * side * side * (side - 1));
  EXPECT_LE(double(use.total()) / double(n), 400.0)
      << "particles " << use.particles << ", integrator " << use.integrator << ", neighbours "
      << use.neighbours << ", force plan " << use.forcePlan << ", scratch " << use.scratch;
  RecordProperty("seconds", std::to_string(seconds));
  RecordProperty("bytesPerParticle", std::to_string(double(use.total()) / double(n)));
}
