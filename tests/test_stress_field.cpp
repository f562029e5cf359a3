/// The paper's representative-sphere stress field and the in-plane σ1 direction.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "granular/geometry.hpp"
#include "granular/stress_field.hpp"

using namespace granular;

TEST(StressField, RepresentativeSpheresOfALatticeGiveForcePerArea) {
  // Columns of spheres along z overlapping by h, columns dx apart: σ_zz = −F/dx² everywhere,
  // F = k h. A sphere's estimate counts whole particles, so it carries the sampling error of
  // how many lattice sites fall in it; the mean over interior spheres is close.
  const double r = 0.03, h = 0.002, dz = 2 * r - h, dx = 2.2 * r;
  Material mat;
  mat.normalDamping = 0;
  Particles p;
  const int n = 14;
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i)
        p.add(Vec3((i + 0.5) * dx, (j + 0.5) * dx, (k + 0.5) * dz), r, mat.density);
    }
  }
  SimulationConfig cfg;
  cfg.material = mat;
  cfg.gravity = Vec3::Zero();
  cfg.timeStep = 1e-4;
  const Simulation sim(std::move(p), {}, cfg);
  const double force = mat.normalCoefficient() * (r / 2) * h;
  const Vec3 lo = Vec3::Zero(), hi(n * dx, n * dx, n * dz);
  const RepresentativeStress field = representativeSphereStress(sim, lo, hi, {4, 4, 4}, 0.2);
  double sum = 0;
  int count = 0;
  for (int k = 1; k <= 2; ++k) {
    for (int j = 1; j <= 2; ++j) {
      for (int i = 1; i <= 2; ++i) {
        const std::size_t s = field.grid.index(i, j, k);
        EXPECT_NEAR(field.volume[s], 4.0 / 3.0 * std::numbers::pi * 0.008, 1e-12);
        EXPECT_NEAR(field.stress[s](0, 0), 0.0, 1e-9);
        sum += field.stress[s](2, 2);
        ++count;
      }
    }
  }
  // The end contacts of the columns reach out of some spheres: a few per cent.
  EXPECT_NEAR(sum / count, -force / (dx * dx), 0.1 * force / (dx * dx));
  // A corner sphere is cut by three faces: its volume is the exact sphere-box volume.
  EXPECT_NEAR(field.volume[field.grid.index(0, 0, 0)],
              sphereBoxVolume(field.grid.node(0, 0, 0), 0.2, lo, hi), 1e-15);
  const double full = 4.0 / 3.0 * std::numbers::pi * 0.008;
  EXPECT_LT(field.volume[field.grid.index(0, 0, 0)], full);      // cut by the walls
  EXPECT_GT(field.volume[field.grid.index(0, 0, 0)], full / 8);  // centre inside the box
}

TEST(StressField, InPlaneSigma1IsTheMostCompressiveDirection) {
  Mat3 vertical = Mat3::Zero();
  vertical.diagonal() << -1000, -900, -2000;  // σ33 most compressive
  const auto d = inPlaneSigma1(vertical, 0.05);
  ASSERT_TRUE(d);
  EXPECT_NEAR(std::abs(d->z()), 1.0, 1e-12);
  Mat3 sheared = Mat3::Zero();  // [[a, τ], [τ, b]] in x-z: σ1 at ½atan2(2τ, a − b) + 90°
  sheared(0, 0) = -1200;
  sheared(2, 2) = -2000;
  sheared(0, 2) = sheared(2, 0) = -300;
  const auto s = inPlaneSigma1(sheared, 0.05);
  ASSERT_TRUE(s);
  const double angle = 0.5 * std::atan2(-600.0, 800.0) + 0.5 * std::numbers::pi;
  EXPECT_NEAR(std::abs(s->x() * std::sin(angle) - s->z() * std::cos(angle)), 0.0, 1e-12);
  const Vec3 v = sheared * (*s);  // an eigenvector: σ·d ∥ d with the smaller eigenvalue
  EXPECT_LT(v.dot(*s), -2000.0);
  Mat3 isotropic = Mat3::Identity() * -1500.0;
  EXPECT_FALSE(inPlaneSigma1(isotropic, 0.05));
}
