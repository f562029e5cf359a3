/// The network's frequency bound (granular/network_frequency.hpp) against the exact spectrum:
/// the mass-weighted stiffness matrix of the linearised contacts, assembled here independently
/// (dense, Eigen), and its largest eigenvalue. A free chain of three equal spheres has
/// ω_max² = 3 k/m in closed form; a triangle with friction and rolling resistance, and settled
/// beds (Hooke and Hertz, with and without friction, on walls) give the truth numerically. The
/// bound must never be below it, and on these beds it is within 1.5 × it (Gershgorin's own
/// bound, without the sweeps, is 1.50–1.70 ×).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>

#include "granular/contact_theory.hpp"
#include "granular/network_frequency.hpp"
#include "physics_fixtures.hpp"

using namespace granular;

namespace {

/// n × (the vector): the cross-product matrix [n]×.
Eigen::Matrix3d crossMatrix(const Vec3& n) {
  Eigen::Matrix3d c;
  c << 0, -n.z(), n.y(), n.z(), 0, -n.x(), -n.y(), n.x(), 0;
  return c;
}

/// ω_max [rad/s] of the linearised network, from its full mass-weighted stiffness matrix:
/// per contact the stretches (normal; tangential at the contact point, u_i − u_j +
/// a_i φ_i × n + a_j φ_j × n projected on the tangent plane; rolling, φ_i − φ_j projected),
/// each weighted by √k, as a matrix G of the mass-weighted displacements; A = Σ G^T G.
double exactOmegaMax(const Simulation& sim) {
  const Particles& p = sim.particles();
  const Material& material = sim.config().material;
  const bool rotations = sim.frictional();
  const Eigen::Index per = rotations ? 6 : 3, n = static_cast<Eigen::Index>(p.size()) * per;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  sim.forEachContact([&](const ContactView& c) {
    const std::size_t i = c.particle;
    const bool wall = c.isWall();
    const std::size_t j = wall ? i : c.otherParticle();
    if (!wall && j < i) return;
    const double reduced =
        wall ? p.radius[i] : p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
    const ContactStiffness k = contactStiffness(material, reduced, c.overlap);
    const Eigen::Vector3d nn = c.normal;
    const Eigen::Matrix3d tangent = Eigen::Matrix3d::Identity() - nn * nn.transpose();
    const Eigen::Matrix3d cross = crossMatrix(c.normal);
    // One body's columns of G; `sign` +1 for i, −1 for j (its translation and rolling count
    // negatively; its rotation moves its contact point as i's does: − a [n]×).
    auto columns = [&](std::size_t body, double sign) {
      Eigen::MatrixXd g = Eigen::MatrixXd::Zero(7, per);
      const double m = p.mass[body], inertia = p.inertia(body);
      const double arm = p.radius[body] - 0.5 * c.overlap;
      g.block(0, 0, 1, 3) = sign * std::sqrt(k.normal / m) * nn.transpose();
      if (rotations) {
        g.block(1, 0, 3, 3) = sign * std::sqrt(k.tangential / m) * tangent;
        g.block(1, 3, 3, 3) = -std::sqrt(k.tangential / inertia) * arm * cross;
        g.block(4, 3, 3, 3) = sign * std::sqrt(k.rolling / inertia) * tangent;
      }
      return g;
    };
    const Eigen::MatrixXd gi = columns(i, 1.0);
    const Eigen::Index bi = static_cast<Eigen::Index>(i) * per;
    a.block(bi, bi, per, per) += gi.transpose() * gi;
    if (wall) return;
    const Eigen::MatrixXd gj = columns(j, -1.0);
    const Eigen::Index bj = static_cast<Eigen::Index>(j) * per;
    a.block(bj, bj, per, per) += gj.transpose() * gj;
    a.block(bi, bj, per, per) += gi.transpose() * gj;
    a.block(bj, bi, per, per) += gj.transpose() * gi;
  });
  const Eigen::VectorXd values = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(a).eigenvalues();
  return std::sqrt(std::max(values(n - 1), 0.0));
}

Simulation threeInARow(const Material& material) {
  SimulationConfig cfg;
  cfg.material = material;
  cfg.gravity = Vec3::Zero();
  cfg.timeStep = stiffestContact(material, 0.03, 1.0).duration / 50;
  Particles p;
  for (int k = 0; k < 3; ++k) p.add(Vec3(0.5 + 0.0599 * k, 0.5, 0.5), 0.03, material.density);
  return Simulation(std::move(p), {Wall{"floor", Vec3::Zero(), Vec3::UnitZ()}}, cfg);
}

/// A bed of 4 × 4 × 5 spheres fallen and settled on the floor of a box.
Simulation settledBed(const Material& material) {
  SimulationConfig cfg;
  cfg.material = material;
  cfg.impactSpeed = 3.0;
  cfg.timeStep = stiffestContact(material, 0.03, cfg.impactSpeed).duration / 50;
  Simulation sim = granular::testing::fallingGrid(4, 4, 5, cfg, 0.3);
  while (sim.time() < 1.5) sim.step();
  return sim;
}

}  // namespace

/// The normal force of two spheres of radius 0.03 m at rest at overlap h, as the engine gives it.
double pairForce(const Material& material, double h) {
  SimulationConfig cfg;
  cfg.material = material;
  cfg.gravity = Vec3::Zero();
  cfg.timeStep = stiffestContact(material, 0.03, 1.0).duration / 50;
  Particles p;
  p.add(Vec3(0.5, 0.5, 0.5), 0.03, material.density);
  p.add(Vec3(0.56 - h, 0.5, 0.5), 0.03, material.density);
  const Simulation sim(std::move(p), {Wall{"floor", Vec3::Zero(), Vec3::UnitZ()}}, cfg);
  double force = 0;
  sim.forEachContact([&](const ContactView& c) { force = c.force.norm(); });
  return force;
}

TEST(NetworkFrequency, TheNormalStiffnessIsTheForceLawsDerivative) {
  for (NormalLaw law : {NormalLaw::Hooke, NormalLaw::Hertz}) {
    Material material;
    material.normalLaw = law;
    const double h = 2e-4, dh = 1e-8;
    const double numeric = (pairForce(material, h + dh) - pairForce(material, h - dh)) / (2 * dh);
    EXPECT_NEAR(contactStiffness(material, 0.015, h).normal, numeric, 1e-5 * numeric);
  }
}

TEST(NetworkFrequency, AFreeChainOfThreeHasThreeKOverMAndTheBoundIsAbove) {
  const Simulation sim = threeInARow(Material{});
  const double m = sim.particles().mass[0];
  double k = 0;  // Hooke: the spring k = F/h, from the engine's force
  sim.forEachContact([&](const ContactView& c) { k = c.force.norm() / c.overlap; });
  const double exact = exactOmegaMax(sim);
  EXPECT_NEAR(exact, std::sqrt(3.0 * k / m), 1e-9 * exact);
  const NetworkFrequency bound = networkFrequencyBound(sim, 0);
  EXPECT_EQ(bound.contacts, 2u);
  EXPECT_EQ(bound.particle, 1u);  // the middle sphere's row: 2 k/m + 2 k/m
  EXPECT_NEAR(bound.omegaMax, 2.0 * std::sqrt(k / m), 1e-12 * bound.omegaMax);
}

TEST(NetworkFrequency, TheBoundIsNeverBelowTheExactSpectrum) {
  struct Case {
    const char* name;
    NormalLaw law;
    double friction, rollingFriction, tangentialStiffness;  // > 0: the constant law
  };
  // The last case's constant k_t equals the normal k_n of a mean pair, so the tangential
  // springs, with the contact points' rotation (3.5 k_t/m on a wall), set the frequency.
  const double meanPairKn = contactStiffness(Material{}, 0.0164, 0.0).normal;
  for (const Case& c : {Case{"hooke, frictionless", NormalLaw::Hooke, 0.0, 0.0, 0.0},
                        Case{"hertz, frictionless", NormalLaw::Hertz, 0.0, 0.0, 0.0},
                        Case{"hooke, mu 0.3", NormalLaw::Hooke, 0.3, 0.0, 0.0},
                        Case{"hertz, mu 0.3", NormalLaw::Hertz, 0.3, 0.0, 0.0},
                        Case{"hooke, mu 0.3, mu_r 0.1", NormalLaw::Hooke, 0.3, 0.1, 0.0},
                        Case{"hooke, mu 0.3, k_t = k_n", NormalLaw::Hooke, 0.3, 0.0, meanPairKn}}) {
    SCOPED_TRACE(c.name);
    Material material;
    material.normalLaw = c.law;
    material.friction = c.friction;
    material.rollingFriction = c.rollingFriction;
    if (c.tangentialStiffness > 0.0) {
      material.tangentialLaw = TangentialLaw::Constant;
      material.tangentialStiffness = c.tangentialStiffness;
    }
    const Simulation sim = settledBed(material);
    const double exact = exactOmegaMax(sim);
    const NetworkFrequency gershgorin = networkFrequencyBound(sim, 0);
    const NetworkFrequency bound = networkFrequencyBound(sim);
    std::printf(
        "%-26s contacts %3zu  exact %7.1f rad/s  Gershgorin %7.1f (%.3f)  32 sweeps %7.1f "
        "(%.3f)\n",
        c.name, bound.contacts, exact, gershgorin.omegaMax, gershgorin.omegaMax / exact,
        bound.omegaMax, bound.omegaMax / exact);
    EXPECT_GT(bound.contacts, 80u);
    EXPECT_GE(gershgorin.omegaMax, exact * (1.0 - 1e-12));
    EXPECT_GE(bound.omegaMax, exact * (1.0 - 1e-12));
    EXPECT_LE(bound.omegaMax, gershgorin.omegaMax);
    // The target for a dense bed: within 1.5 × the truth in ω.
    EXPECT_LE(bound.omegaMax, 1.5 * exact);
  }
}
