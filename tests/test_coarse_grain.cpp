/// Coarse-grained fields: the stress of a lattice under known contact forces, and the static
/// momentum balance ∇·σ + ρg + t = 0 in a settled bed, in the bulk and at the walls.
#include <gtest/gtest.h>

#include <cmath>

#include "granular/coarse_grain.hpp"
#include "physics_fixtures.hpp"

using namespace granular;

TEST(CoarseGrain, LatticeUnderKnownForcesGivesForcePerArea) {
  // Columns of spheres along z, overlapping by h (Hooke, no damping, at rest): every contact
  // carries F = k h. Columns are dx apart, so σ_zz = −F/dx² and nothing else.
  const double r = 0.03, h = 0.002, dz = 2 * r - h, dx = 2.2 * r;
  Material mat;
  mat.normalDamping = 0;
  Particles p;
  for (int k = 0; k < 12; ++k) {
    for (int j = 0; j < 12; ++j) {
      for (int i = 0; i < 12; ++i) p.add(Vec3(i * dx, j * dx, k * dz), r, mat.density);
    }
  }
  SimulationConfig cfg;
  cfg.material = mat;
  cfg.gravity = Vec3::Zero();
  cfg.timeStep = 1e-4;
  const Simulation sim(std::move(p), {}, cfg);
  const double force = mat.normalCoefficient() * (r / 2) * h;
  const CoarseGrainer cg(sim, 2.5 * dx);
  const Vec3 centre(5.5 * dx, 5.5 * dx, 5.5 * dz);
  const Mat3 s = cg.at(centre).contactStress;
  EXPECT_NEAR(s(2, 2), -force / (dx * dx), 0.01 * force / (dx * dx));
  EXPECT_NEAR(s(0, 0), 0.0, 1e-12);
  EXPECT_NEAR(s(0, 2), 0.0, 1e-12);
  const double density = sim.particles().mass[0] / (dx * dx * dz);
  EXPECT_NEAR(cg.at(centre).density, density, 0.01 * density);
}

TEST(CoarseGrain, SettledBedSatisfiesTheStaticMomentumBalanceNearWallsToo) {
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.timeStep = stiffestContact(cfg.material, 0.03, 1.0).duration / 50;
  Simulation sim = granular::testing::fallingGrid(4, 4, 12, cfg, 0.3);  // a bed ~0.25 m deep
  while (sim.time() < 3.0) sim.step();
  ASSERT_LT(sim.kineticEnergy(), 1e-3);
  const double c = 0.12;
  const CoarseGrainer cg(sim, c);
  const double h = c / 400;  // central differences: error ∝ h², round-off ∝ 1/h
  // In the bulk and right at a side wall and the floor (where the kernel is cut by the wall and
  // the wall force density t carries the load), relative to ρ|g| at the point.
  for (const Vec3& r :
       {Vec3(0.2, 0.2, 0.12), Vec3(0.2, 0.2, 0.02), Vec3(0.01, 0.2, 0.12), Vec3(0.2, 0.39, 0.08)}) {
    const CoarseGrainedFields f = cg.at(r);
    ASSERT_GT(f.density, 100.0) << r.transpose();
    const double scale = f.density * 9.81;
    EXPECT_LT(cg.balanceResidual(r, h).norm(), 0.01 * scale) << "at " << r.transpose();
  }
  // The identity behind it holds for any state, moving or not: ∇·σ_c + t = Σ φ F_i up to the
  // numerical error of finite differences and quadrature, at the wall too.
  for (const Vec3& r : {Vec3(0.2, 0.2, 0.12), Vec3(0.01, 0.2, 0.12), Vec3(0.2, 0.2, 0.02)}) {
    const double scale = cg.at(r).density * 9.81;
    EXPECT_LT(cg.closureError(r, h).norm(), 1e-4 * scale) << "at " << r.transpose();
  }
  // Without the wall force density the balance fails at the wall: t is what closes it.
  const Vec3 atWall(0.01, 0.2, 0.12);
  const CoarseGrainedFields f = cg.at(atWall);
  EXPECT_GT((cg.stressDivergence(atWall, h) + f.density * cfg.gravity).norm(),
            0.2 * f.density * 9.81);
}
