/// Principal stresses (ordering, orthonormality, σ1 the most compressive) and trajectories of
/// sign-free direction fields (principal.hpp), against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <random>

#include "granular/error.hpp"
#include "granular/principal.hpp"

using namespace granular;

namespace {

double uniform(std::mt19937_64& rng, double a, double b) {
  return a + (b - a) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// A sign that changes arbitrarily from point to point (a hash of the coordinates' bits).
double scrambledSign(const Vec3& p) {
  std::uint64_t h = 1469598103934665603ull;
  for (int k = 0; k < 3; ++k) {
    std::uint64_t bits;
    std::memcpy(&bits, &p[k], sizeof bits);
    h = (h ^ bits) * 1099511628211ull;
  }
  return (h >> 17) & 1 ? 1.0 : -1.0;
}

}  // namespace

TEST(Principal, OrderedOrthonormalRightHandedAndExact) {
  std::mt19937_64 rng(1);
  for (int trial = 0; trial < 200; ++trial) {
    Mat3 a;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a(i, j) = uniform(rng, -2000, 500);  // [Pa]
    const Mat3 sym = 0.5 * (a + a.transpose());
    const PrincipalStresses p = principalStresses(a);  // the symmetric part is used
    EXPECT_LE(p.values[0], p.values[1]);
    EXPECT_LE(p.values[1], p.values[2]);
    EXPECT_LT((p.vectors.transpose() * p.vectors - Mat3::Identity()).norm(), 1e-14);
    EXPECT_NEAR(p.vectors.determinant(), 1.0, 1e-14);
    for (int k = 0; k < 3; ++k)
      EXPECT_LT((sym * p.vectors.col(k) - p.values[k] * p.vectors.col(k)).norm(),
                1e-12 * sym.norm());
    EXPECT_LT((p.vectors * p.values.asDiagonal() * p.vectors.transpose() - sym).norm(),
              1e-12 * sym.norm());
    // σ1 is the minimum of the Rayleigh quotient: no unit vector is more compressed.
    for (int probe = 0; probe < 5; ++probe) {
      // One draw per statement: argument order is unspecified.
      const double z = uniform(rng, -1, 1), y = uniform(rng, -1, 1), x = uniform(rng, -1, 1);
      const Vec3 n = Vec3(x, y, z).normalized();
      EXPECT_GE(n.dot(sym * n), p.values[0] - 1e-9);
    }
  }
}

TEST(Principal, DiagonalTensorPutsTheMostCompressiveFirst) {
  const PrincipalStresses p = principalStresses(Vec3(-1, -3, -2).asDiagonal().toDenseMatrix());
  EXPECT_EQ(p.values, Vec3(-3, -2, -1));
  EXPECT_NEAR(std::abs(p.vectors.col(0).dot(Vec3::UnitY())), 1.0, 1e-15);
  EXPECT_NEAR(std::abs(p.vectors.col(1).dot(Vec3::UnitZ())), 1.0, 1e-15);
  EXPECT_NEAR(std::abs(p.vectors.col(2).dot(Vec3::UnitX())), 1.0, 1e-15);
}

TEST(Principal, NearlyHydrostaticTensorKeepsOrthonormalVectors) {
  // The paper's frictionless bed is near-hydrostatic: close eigenvalues must not spoil the basis.
  Mat3 s = -1600 * Mat3::Identity();
  s(0, 1) = s(1, 0) = 1e-9;
  s(2, 2) += 1e-10;
  const PrincipalStresses p = principalStresses(s);
  EXPECT_LT((p.vectors.transpose() * p.vectors - Mat3::Identity()).norm(), 1e-14);
  EXPECT_LT((p.vectors * p.values.asDiagonal() * p.vectors.transpose() - s).norm(), 1e-11);
}

TEST(Principal, OrientLikeGivesANonNegativeDotProduct) {
  const Vec3 v(0.3, -0.4, 0.866);
  EXPECT_EQ(orientLike(v, Vec3(0, 0, 1)), v);
  EXPECT_EQ(orientLike(v, Vec3(0, 0, -1)), -v);
  EXPECT_EQ(orientLike(-v, Vec3(1, -1, 0)), v);
  EXPECT_EQ(orientLike(v, Vec3(0.4, 0.3, 0)), v);  // perpendicular: kept
  std::mt19937_64 rng(2);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 a(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    const Vec3 r(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    const Vec3 o = orientLike(a, r);
    EXPECT_GE(o.dot(r), 0.0);
    EXPECT_TRUE(o == a || o == -a);
  }
}

TEST(Principal, UniformVerticalFieldGivesAVerticalLineClippedAtTheBox) {
  // The plane y = 0.5 is given as a zero-thickness axis; the field's sign points down, the
  // initial orientation up.
  const Vec3 lo(0, 0.5, 0), hi(1, 0.5, 1.2);
  const DirectionField down = [](const Vec3&) { return std::optional<Vec3>(-Vec3::UnitZ()); };
  const Vec3 start(0.3, 0.5, 0.2);
  const double step = 0.07;
  const std::vector<Vec3> up = traceTrajectory(down, start, step, 1000, lo, hi, Vec3::UnitZ());
  // Full steps while z stays ≤ 1.2, then one cut step ending exactly on the top face.
  const int full = static_cast<int>(std::floor((hi.z() - start.z()) / step));
  ASSERT_EQ(up.size(), static_cast<std::size_t>(full + 2));
  for (std::size_t i = 0; i + 1 < up.size(); ++i) {
    EXPECT_EQ(up[i].x(), 0.3);
    EXPECT_EQ(up[i].y(), 0.5);
    EXPECT_NEAR(up[i].z(), start.z() + step * i, 1e-14);
  }
  EXPECT_EQ(up.back(), Vec3(0.3, 0.5, 1.2));

  const std::vector<Vec3> downLine =
      traceTrajectory(down, start, step, 1000, lo, hi, -Vec3::UnitZ());
  ASSERT_EQ(downLine.size(), static_cast<std::size_t>(std::floor(start.z() / step) + 2));
  EXPECT_EQ(downLine.back(), Vec3(0.3, 0.5, 0.0));
  // maxSteps bounds the line; a start outside gives nothing.
  EXPECT_EQ(traceTrajectory(down, start, step, 3, lo, hi, Vec3::UnitZ()).size(), 4u);
  EXPECT_TRUE(traceTrajectory(down, Vec3(0.3, 0.5, 1.3), step, 10, lo, hi, Vec3::UnitZ()).empty());
  // The zero-thickness axis is not bounded (the caller keeps the line in its plane).
  EXPECT_EQ(traceTrajectory(down, Vec3(0.3, 0.6, 0.5), step, 10, lo, hi, Vec3::UnitZ()).size(),
            11u);
  EXPECT_THROW(traceTrajectory(down, start, 0.0, 10, lo, hi, Vec3::UnitZ()), ConfigError);
  EXPECT_THROW(traceTrajectory(down, start, step, -1, lo, hi, Vec3::UnitZ()), ConfigError);
}

TEST(Principal, ConstantShearGivesAStraightLineAtTheAnalyticAngle) {
  // σ = [[a, τ], [τ, b]] in the x–z plane. Mohr: the larger principal stress is at
  // θ = ½ atan2(2τ, a − b) from x toward z; σ1, the smaller (most compressive), is at θ + π/2,
  // and equals (a + b)/2 − √(((a − b)/2)² + τ²).
  const double a = -1200, b = -1500, tau = -260;  // [Pa]
  Mat3 s = Mat3::Zero();
  s(0, 0) = a;
  s(2, 2) = b;
  s(1, 1) = -900;  // σ22 between them: σ1 stays in the plane
  s(0, 2) = s(2, 0) = tau;
  const double theta1 = 0.5 * std::atan2(2 * tau, a - b) + 0.5 * std::numbers::pi;
  const Vec3 e1(std::cos(theta1), 0, std::sin(theta1));
  const double sigma1 = 0.5 * (a + b) - std::hypot(0.5 * (a - b), tau);
  EXPECT_NEAR(e1.dot(s * e1), sigma1, 1e-10);  // the closed forms agree with each other
  const PrincipalStresses p = principalStresses(s);
  EXPECT_NEAR(p.values[0], sigma1, 1e-10);
  EXPECT_NEAR(std::abs(p.vectors.col(0).dot(e1)), 1.0, 1e-14);

  const DirectionField field = [&](const Vec3&) {
    return std::optional<Vec3>(principalStresses(s).vectors.col(0));
  };
  const Vec3 lo(0, 0, 0), hi(1, 0, 1), start(0.5, 0, 0.1);
  const std::vector<Vec3> line = traceTrajectory(field, start, 0.02, 1000, lo, hi, Vec3::UnitZ());
  ASSERT_GT(line.size(), 10u);
  const Vec3 up = orientLike(e1, Vec3::UnitZ());
  for (const Vec3& q : line) EXPECT_LT((q - start).cross(up).norm(), 1e-13) << q.transpose();
  EXPECT_GT((line[1] - start).dot(up), 0.0);
  // It ends on the boundary: the top face or a side face, whichever the line meets first.
  const Vec3 end = line.back();
  EXPECT_TRUE(end.z() == 1.0 || end.x() == 0.0 || end.x() == 1.0) << end.transpose();
}

TEST(Principal, SignScrambledCircularFieldStillGivesASmoothCircle) {
  // Tangents to circles about c = (0.5, ·, 0.5), their sign scrambled from point to point. The
  // exact trajectory is the circle through the start. For a rotation RK4's amplification factor
  // has modulus 1 − (h/R)⁶/144 + …, so the radius drifts by about R·N·(h/R)⁶/144 after N steps:
  // fifth order over a fixed arc (the phase error is fourth order).
  const Vec3 c(0.5, 0.0, 0.5);
  int flips = 0;
  auto tangent = [&](const Vec3& p) {
    const Vec3 r = p - c;
    return Vec3(-r.z(), 0, r.x()).normalized();
  };
  const DirectionField scrambled = [&](const Vec3& p) {
    const double sign = scrambledSign(p);
    if (sign < 0) ++flips;
    return std::optional<Vec3>(sign * tangent(p));
  };
  const DirectionField clean = [&](const Vec3& p) { return std::optional<Vec3>(tangent(p)); };
  const Vec3 lo(0, 0, 0), hi(1, 0, 1), start(0.8, 0, 0.5);  // radius 0.3
  auto drift = [&](const DirectionField& field, double step) {
    // Nearly a full turn: 1.8 of the circumference 2π·0.3 ≈ 1.885.
    const std::vector<Vec3> line = traceTrajectory(
        field, start, step, static_cast<int>(std::lround(1.8 / step)), lo, hi, Vec3::UnitZ());
    double worst = 0;
    for (std::size_t i = 0; i < line.size(); ++i) {
      worst = std::max(worst, std::abs((line[i] - c).norm() - 0.3));
      if (i >= 2) {  // the line never folds back: successive chords turn by step/R only
        const Vec3 d0 = (line[i - 1] - line[i - 2]).normalized(),
                   d1 = (line[i] - line[i - 1]).normalized();
        EXPECT_GT(d0.dot(d1), std::cos(2.0 * step / 0.3));
      }
    }
    EXPECT_EQ(line.size(), static_cast<std::size_t>(std::lround(1.8 / step)) + 1);
    return std::pair{worst, line};
  };
  const auto [coarse, coarseLine] = drift(scrambled, 0.02);
  const auto [fine, fineLine] = drift(scrambled, 0.01);
  EXPECT_GT(flips, 100);
  // Orientation makes the scrambled field act exactly like the clean one, bit for bit.
  EXPECT_EQ(coarseLine, drift(clean, 0.02).second);
  // Fifth order: halving the step divides the drift by about 32; and its size is the estimate's.
  const double estimate = 0.3 * (1.8 / 0.02) * std::pow(0.02 / 0.3, 6) / 144;
  EXPECT_LT(coarse, 2 * estimate);
  EXPECT_GT(coarse, 0.2 * estimate);
  EXPECT_GT(coarse / fine, 24.0);
  EXPECT_LT(coarse / fine, 40.0);
}

TEST(Principal, StopsWhereTheFieldIsUndefinedButReachesTheBoxWall) {
  const DirectionField below07 = [](const Vec3& p) {
    return p.z() <= 0.7 ? std::optional<Vec3>(Vec3::UnitZ()) : std::nullopt;
  };
  const Vec3 start(0.3, 0, 0.2);
  // Box up to 1: the line ends at the first point beyond 0.7 (reached by an Euler step from the
  // last defined point).
  const std::vector<Vec3> open =
      traceTrajectory(below07, start, 0.07, 100, Vec3(0, 0, 0), Vec3(1, 0, 1), Vec3::UnitZ());
  ASSERT_GE(open.size(), 2u);
  EXPECT_GT(open.back().z(), 0.7);
  EXPECT_LE(open[open.size() - 2].z(), 0.7);
  // Box up to 0.7 with the field undefined just outside: the line still reaches the face.
  const std::vector<Vec3> boxed =
      traceTrajectory(below07, start, 0.07, 100, Vec3(0, 0, 0), Vec3(1, 0, 0.7), Vec3::UnitZ());
  EXPECT_EQ(boxed.back(), Vec3(0.3, 0, 0.7));
  // Undefined at the start: just the start.
  EXPECT_EQ(traceTrajectory(below07, Vec3(0.3, 0, 0.8), 0.07, 100, Vec3(0, 0, 0), Vec3(1, 0, 1),
                            Vec3::UnitZ())
                .size(),
            1u);
}
