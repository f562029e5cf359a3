/// Eq. (1) and Eq. (2): the Love-Weber identity on a live state (exact, so it catches a wrong
/// branch vector, a missed wall contact or a sign) and the static balances of a settled bed.
#include <gtest/gtest.h>

#include <cmath>

#include "granular/stress.hpp"
#include "physics_fixtures.hpp"

using namespace granular;
using granular::testing::fallingGrid;

namespace {

/// A frictional bed settled for `settle` seconds, then a top wall on its surface moving down.
Simulation compactedBed(double settle, double compact, Integrator integrator, double friction) {
  SimulationConfig cfg;
  cfg.material.friction = friction;
  cfg.integrator = integrator;
  cfg.timeStep = stiffestContact(cfg.material, 0.03, 1.0).duration / 50;
  Simulation sim = fallingGrid(4, 4, 4, cfg, 0.3);
  while (sim.time() < settle) sim.step();
  double top = 0;
  const Particles& p = sim.particles();
  for (std::size_t i = 0; i < p.size(); ++i) top = std::max(top, p.position[i].z() + p.radius[i]);
  const std::size_t w = sim.addWall(Wall{"top", Vec3(0, 0, top), Vec3(0, 0, -1)});
  sim.setWallVelocity(w, Vec3(0, 0, -0.01));
  const double end = sim.time() + compact;
  while (sim.time() < end) sim.step();
  return sim;
}

}  // namespace

TEST(Stress, LoveWeberIdentityHoldsToRoundOffOnALiveState) {
  // V σ(Eq. 1) = Σ_wall contacts F ⊗ x_c - Σ_p F_p ⊗ x_p, F_p the net contact force on p:
  // the particle-pair terms cancel because both sides use the same contact point.
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    Simulation sim = compactedBed(0.4, 0.05, integrator, 0.3);  // still moving: not static
    const double volume = 0.4 * 0.4 * 1.0;
    const Mat3 lhs = volume * volumeAveragedStress(sim, volume);
    Mat3 rhs = Mat3::Zero();
    sim.forEachContact([&](const ContactView& c) {
      if (c.isWall()) rhs += c.force * c.point.transpose();
    });
    const std::vector<Vec3> net = sim.netContactForces();
    const Particles& p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i) rhs -= net[i] * p.position[i].transpose();
    ASSERT_GT(sim.kineticEnergy(), 1e-4);
    ASSERT_GT(sim.counters().wallContacts, 10u);
    EXPECT_LT((lhs - rhs).cwiseAbs().maxCoeff(), 1e-11 * lhs.cwiseAbs().maxCoeff())
        << "lhs\n"
        << lhs << "\nrhs\n"
        << rhs;
  }
}

TEST(Stress, ParticleStressesTimesTheirVolumesSumToTheBoxStress) {
  // Σ_i V_i σ^i = V σ(Eq. 1): the same contact sums, split by particle. A wrong branch vector,
  // volume or transposition breaks it (the tensor is not symmetric on a moving bed).
  Simulation sim = compactedBed(0.4, 0.05, Integrator::Gear5, 0.3);
  const double volume = 0.4 * 0.4 * 1.0;
  const Mat3 box = volume * volumeAveragedStress(sim, volume);
  const std::vector<Mat3> each = particleStresses(sim);
  ASSERT_EQ(each.size(), sim.particles().size());
  Mat3 sum = Mat3::Zero();
  for (std::size_t i = 0; i < each.size(); ++i) {
    const double r = sim.particles().radius[i];
    sum += each[i] * (4.0 / 3.0 * M_PI * r * r * r);
  }
  ASSERT_GT(box.cwiseAbs().maxCoeff(), 1.0);
  EXPECT_LT((sum - box).cwiseAbs().maxCoeff(), 1e-12 * box.cwiseAbs().maxCoeff());
  // A particle without contacts carries no stress; one pressed from above and below compresses.
  double mostCompressed = 0;
  for (const Mat3& s : each) mostCompressed = std::min(mostCompressed, s(2, 2));
  EXPECT_LT(mostCompressed, 0.0);
}

TEST(Stress, NetContactForceBalancesGravityAndInertia) {
  // The net contact force from the measurement evaluation is m (a - g) up to the difference
  // between the evaluation state and the integrator's; in a slowly compacted bed that is small.
  Simulation sim = compactedBed(1.5, 0.2, Integrator::Gear5, 0.3);
  const std::vector<Vec3> net = sim.netContactForces();
  const Particles& p = sim.particles();
  double worst = 0, weight = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 expect = p.mass[i] * (sim.acceleration(i) - sim.config().gravity);
    worst = std::max(worst, (net[i] - expect).norm());
    weight = std::max(weight, p.mass[i] * 9.81);
  }
  EXPECT_LT(worst, 0.05 * weight);
}

TEST(Stress, SettledFrictionlessBedObeysTheStaticBalances) {
  // Frictionless: side walls carry no weight, so bottom - top = W, and σ33(Eq. 1) - σ33(Eq. 2) is
  // the centre-of-mass term (W/A)(1/2 - z_cm/H) up to the bed's residual motion.
  Simulation sim = compactedBed(2.5, 0.3, Integrator::Gear5, 0.0);
  const BoxStress b = measureBox(sim);
  EXPECT_NEAR(b.sideVerticalForce, 0.0, 1e-12 * b.weight);
  EXPECT_LT(std::abs(b.balanceError), 0.02);
  const double diff33 = b.eq1(2, 2) - b.eq2.z();
  EXPECT_NEAR(diff33, b.sigma33CentreOfMassTerm, 0.02 * std::abs(b.eq2.z()));
  EXPECT_LT(b.eq1(2, 2), 0.0);                                          // compression is negative
  EXPECT_NEAR(b.eq1(0, 1), b.eq1(1, 0), 1e-9 * std::abs(b.eq1(2, 2)));  // no friction: symmetric
}
