/// Coarse-grained fields: the stress of a lattice under known contact forces, and the static
/// momentum balance ∇·σ + ρg + t = 0 in a settled bed, in the bulk and at the walls; the fields
/// evaluated on several threads at once (as the paper's fields are) are the serial ones.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <thread>
#include <vector>

#include "granular/coarse_grain.hpp"
#include "physics_fixtures.hpp"

using namespace granular;

namespace {

/// n × n columns of n spheres of radius r along z, dx apart, dz between centres in a column.
Particles columns(int n, double r, double dx, double dz, double density) {
  Particles p;
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) p.add(Vec3(i * dx, j * dx, k * dz), r, density);
    }
  }
  return p;
}

}  // namespace

TEST(CoarseGrain, LatticeUnderKnownForcesGivesForcePerArea) {
  // Columns of spheres along z, overlapping by h (Hooke, no damping, at rest): every contact
  // carries F = k h. Columns are dx apart, so σ_zz = −F/dx² and nothing else.
  const double r = 0.03, h = 0.002, dz = 2 * r - h, dx = 2.2 * r;
  Material mat;
  mat.normalDamping = 0;
  Particles p = columns(12, r, dx, dz, mat.density);
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

TEST(CoarseGrain, FieldsEvaluatedOnSeveralThreadsAtOnceAreTheSerialOnesToTheBit) {
  // One grainer read by three threads at once, each taking every third point (the paper's fields
  // are evaluated on the threads, granular paper's fields/): the same bits as one thread, and no
  // race under ThreadSanitizer (the grainer holds no cache it fills while read).
  Material mat;
  mat.normalDamping = 0;
  const double r = 0.03, dz = 2 * r - 0.002, dx = 2.1 * r;
  Particles p = columns(8, r, dx, dz, mat.density);
  SimulationConfig cfg;
  cfg.material = mat;
  cfg.timeStep = 1e-4;
  const Simulation sim(std::move(p), {Wall{"floor", Vec3(0, 0, -r + 0.001), Vec3::UnitZ()}}, cfg);
  const CoarseGrainer cg(sim, 2.5 * dx);
  std::vector<Vec3> points;
  for (int k = 0; k < 4; ++k) {
    for (int i = 0; i < 6; ++i) points.emplace_back(i * 1.3 * dx, 3.5 * dx, k * 2.0 * dz);
  }
  // σ33, ρ and the balance's residual at each point.
  auto fieldsAt = [&](const Vec3& x) {
    const CoarseGrainedFields f = cg.at(x);
    return std::array<double, 3>{f.stress()(2, 2), f.density, cg.balanceResidual(x, 1e-4).z()};
  };
  std::vector<std::array<double, 3>> serial, threaded(points.size());
  for (const Vec3& x : points) serial.push_back(fieldsAt(x));
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < 3; ++t) {
    threads.emplace_back([&, t] {
      for (std::size_t n = t; n < points.size(); n += 3) threaded[n] = fieldsAt(points[n]);
    });
  }
  for (std::thread& t : threads) t.join();
  ASSERT_GT(serial[8][0] * serial[8][0], 0.0);  // a point inside the lattice sees its stress
  for (std::size_t n = 0; n < points.size(); ++n) {
    for (std::size_t q = 0; q < 3; ++q) EXPECT_EQ(threaded[n][q], serial[n][q]) << n << ' ' << q;
  }
}
