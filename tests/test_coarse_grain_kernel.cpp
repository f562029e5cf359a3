/// Lucy's kernel and its branch integral (coarse_grain_kernel.hpp): normalisation, smoothness
/// at the support edge, the closed form of the branch integral, and the identity
/// (b − a)·∇ψ = φ(r − a) − φ(r − b) behind the coarse-grained momentum balance.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "granular/coarse_grain_kernel.hpp"
#include "granular/error.hpp"

using namespace granular;

namespace {

constexpr double kWidth = 0.07;  // [m], about a particle diameter

double uniform(std::mt19937_64& rng, double a, double b) {
  return a + (b - a) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

Vec3 randomVector(std::mt19937_64& rng, double scale) {
  // One draw per statement (argument order is unspecified); z, y, x as GCC evaluated it.
  const double z = uniform(rng, -1, 1), y = uniform(rng, -1, 1), x = uniform(rng, -1, 1);
  return scale * Vec3(x, y, z);
}

/// K = 105/(16π c³) [1/m³], the kernel's value at its centre.
double peak(double c) {
  return 105.0 / (16.0 * std::numbers::pi * c * c * c);
}

/// ψ in closed form, in long double: along the line, with u the distance from the point
/// closest to r (at distance m), the integrand is K(1 − 6ρ² + 8ρ³ − 3ρ⁴), ρ² = (u² + m²)/c²;
/// all terms are polynomials in u but ρ³, whose antiderivative is
/// J(u) = u S³/4 + 3m² u S/8 + 3m⁴ asinh(u/m)/8, S = √(u² + m²) (differentiate to check).
/// The difference of antiderivatives cancels like c/L: use for L ≳ c/100 only.
long double closedFormPsi(const Vec3& r, const Vec3& a, const Vec3& b, long double c) {
  using LD = long double;
  LD p[3], d[3];
  for (int k = 0; k < 3; ++k) {
    p[k] = static_cast<LD>(r[k]) - a[k];
    d[k] = static_cast<LD>(b[k]) - a[k];
  }
  const LD length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  const LD along = (p[0] * d[0] + p[1] * d[1] + p[2] * d[2]) / length;
  const LD m2 = std::max<LD>(0, p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - along * along);
  const LD m = std::sqrt(m2);
  if (m >= c) return 0;
  const LD half = std::sqrt(c * c - m2);
  const LD uA = std::max(-along, -half), uB = std::min(length - along, half);
  if (uB <= uA) return 0;
  auto j = [&](LD u) {
    const LD s = std::sqrt(u * u + m2);
    if (m == 0) return u * u * u * std::abs(u) / 4;
    return u * s * s * s / 4 + 3 * m2 * u * s / 8 + 3 * m2 * m2 * std::asinh(u / m) / 8;
  };
  auto antiderivative = [&](LD u) {
    const LD u2 = u * u, c2 = c * c;
    return u - 6 * (u2 * u / 3 + m2 * u) / c2 + 8 * j(u) / (c2 * c) -
           3 * (u2 * u2 * u / 5 + 2 * m2 * u2 * u / 3 + m2 * m2 * u) / (c2 * c2);
  };
  const LD k = 105.0L / (16.0L * std::numbers::pi_v<LD> * c * c * c);
  return k * (antiderivative(uB) - antiderivative(uA)) / length;
}

}  // namespace

TEST(CoarseGrainKernel, IsLucysPolynomialAndNormalised) {
  const LucyKernel phi(kWidth);
  const double k = peak(kWidth);
  EXPECT_NEAR(phi.value(0), k, 1e-15 * k);
  std::mt19937_64 rng(1);
  for (int trial = 0; trial < 100; ++trial) {
    const double rho = uniform(rng, 0, 1);
    const double factored = k * (1 + 3 * rho) * std::pow(1 - rho, 3);
    EXPECT_NEAR(phi.value(rho * kWidth), factored, 1e-14 * k);
  }
  EXPECT_EQ(phi.value(kWidth), 0.0);
  EXPECT_EQ(phi.value(2 * kWidth), 0.0);
  EXPECT_EQ(phi.gradient(Vec3(0, 0, 2 * kWidth)), Vec3::Zero());

  // ∫φ dV = 1 on a midpoint grid over the support's bounding cube. The integrand is C² with a
  // jump of the third derivative on the sphere r = c, which limits the grid's accuracy
  // (measured: 1e-9 at 80³ cells, 4e-11 at 160³); halving the spacing must shrink the error.
  auto gridIntegral = [&](int n) {
    const double h = 2 * kWidth / n;
    double sum = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int l = 0; l < n; ++l)
          sum +=
              phi(Vec3(-kWidth + (i + 0.5) * h, -kWidth + (j + 0.5) * h, -kWidth + (l + 0.5) * h));
    return sum * h * h * h;
  };
  const double coarse = gridIntegral(80), fine = gridIntegral(160);
  EXPECT_NEAR(fine, 1.0, 1e-9);
  EXPECT_LT(std::abs(fine - 1.0), std::abs(coarse - 1.0));
  // And radially, where the integrand 4πr²φ is a polynomial of degree 6 on [0, c]: Simpson's
  // rule with Richardson extrapolation (exact to degree 5) on 1000 intervals.
  auto radial = [&](int n) {
    const double h = kWidth / n;
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
      const double r = i * h;
      const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      sum += w * 4 * std::numbers::pi * r * r * phi.value(r);
    }
    return sum * h / 3;
  };
  EXPECT_NEAR((16 * radial(2000) - radial(1000)) / 15, 1.0, 1e-13);
}

TEST(CoarseGrainKernel, IsSmoothAtTheSupportEdge) {
  // With ε = 1 − ρ: φ = K(4 − 3ε)ε³ and |∇φ| = 12K ε²(1 − ε)/c, so value, slope and curvature
  // vanish at the edge (C², so C¹ in particular); the third derivative jumps.
  const LucyKernel phi(kWidth);
  const double k = peak(kWidth);
  for (double eps : {1e-2, 1e-3, 1e-4}) {
    const double r = kWidth * (1 - eps);
    EXPECT_NEAR(phi.value(r) / (k * eps * eps * eps), 4.0 - 3.0 * eps, 1e-9);
    const Vec3 g = phi.gradient(Vec3(0, r, 0));
    EXPECT_NEAR(g.y() / (-12 * k * eps * eps * (1 - eps) / kWidth), 1.0, 1e-9);
    EXPECT_DOUBLE_EQ(g.x(), 0.0);
  }
  // The gradient against central differences at random points, and zero at the centre.
  std::mt19937_64 rng(2);
  const double h = 1e-6 * kWidth;
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 x = randomVector(rng, 0.6 * kWidth);
    const Vec3 g = phi.gradient(x);
    for (int axis = 0; axis < 3; ++axis) {
      const Vec3 e = h * Vec3::Unit(axis);
      const double fd = (phi(x + e) - phi(x - e)) / (2 * h);
      EXPECT_NEAR(g[axis], fd, 1e-7 * k / kWidth);
    }
  }
  EXPECT_EQ(phi.gradient(Vec3::Zero()), Vec3::Zero());
  EXPECT_THROW(LucyKernel(0.0), ConfigError);
  EXPECT_THROW(LucyKernel(-1.0), ConfigError);
}

TEST(CoarseGrainKernel, BranchIntegralOfAPointIsTheKernel) {
  const LucyKernel phi(kWidth);
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 a = randomVector(rng, kWidth), r = randomVector(rng, kWidth);
    EXPECT_EQ(phi.lineIntegral(r, a, a), phi(r - a));
    EXPECT_EQ(phi.lineIntegralGradient(r, a, a), phi.gradient(r - a));
  }
}

TEST(CoarseGrainKernel, BranchIntegralMatchesItsClosedForm) {
  const LucyKernel phi(kWidth);
  const double k = peak(kWidth);
  std::mt19937_64 rng(4);
  double worst = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    // Branch lengths from c/100 to 30c, r anywhere near it; every fourth r within 1e-9 c to
    // 1e-1 c of the line (the hard case: the branch points of ρ³ close to the real axis).
    const double length = kWidth * std::pow(10.0, uniform(rng, -2, std::log10(30.0)));
    const Vec3 a = randomVector(rng, 0.5 * kWidth);
    const Vec3 dir = randomVector(rng, 1).normalized();
    const Vec3 b = a + length * dir;
    Vec3 r = a + uniform(rng, -0.5, 1.5) * (b - a) + randomVector(rng, 0.8 * kWidth);
    if (trial % 4 == 0) {
      const Vec3 across = dir.cross(randomVector(rng, 1)).normalized();
      r = a + uniform(rng, -0.2, 1.2) * (b - a) +
          kWidth * std::pow(10.0, uniform(rng, -9, -1)) * across;
    }
    const double error =
        std::abs(phi.lineIntegral(r, a, b) - static_cast<double>(closedFormPsi(r, a, b, kWidth)));
    worst = std::max(worst, error / k);
  }
  EXPECT_LT(worst, 1e-13);  // measured: 2e-15 of K
  // A long branch straight through r: L ψ = ∫ φ du over a full chord through the centre
  // = 2Kc ∫₀¹ (1 − 6ρ² + 8ρ³ − 3ρ⁴) dρ = 2Kc (1 − 2 + 2 − 3/5) = 4Kc/5.
  const Vec3 a(-3 * kWidth, 0.01, 0.02), b(5 * kWidth, 0.01, 0.02), r(0.4 * kWidth, 0.01, 0.02);
  EXPECT_NEAR(phi.lineIntegral(r, a, b) * (b - a).norm(), 0.8 * k * kWidth, 1e-15 * k * kWidth);
  // Symmetric in the ends; zero beyond the support.
  EXPECT_NEAR(phi.lineIntegral(r + Vec3(0, 0.3 * kWidth, 0), a, b),
              phi.lineIntegral(r + Vec3(0, 0.3 * kWidth, 0), b, a), 1e-15 * k);
  EXPECT_EQ(phi.lineIntegral(r + Vec3(0, 1.01 * kWidth, 0), a, b), 0.0);
  EXPECT_EQ(phi.lineIntegral(Vec3(7 * kWidth, 0.01, 0.02), a, b), 0.0);
}

TEST(CoarseGrainKernel, BranchGradientSatisfiesTheMomentumBalanceIdentity) {
  // (b − a)·∇_r ψ = φ(r − a) − φ(r − b): the integrand of ∇ψ along the branch is −d/ds φ.
  const LucyKernel phi(kWidth);
  const double k = peak(kWidth);
  std::mt19937_64 rng(5);
  double worst = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double length = kWidth * std::pow(10.0, uniform(rng, -6, 1.5));
    const Vec3 a = randomVector(rng, 0.5 * kWidth);
    const Vec3 b = a + length * randomVector(rng, 1).normalized();
    Vec3 r = a + uniform(rng, -0.5, 1.5) * (b - a) + randomVector(rng, 0.8 * kWidth);
    if (trial % 4 == 0)
      r = a + uniform(rng, -0.2, 1.2) * (b - a) + randomVector(rng, 1e-8 * kWidth);
    const double lhs = (b - a).dot(phi.lineIntegralGradient(r, a, b));
    const double rhs = phi(r - a) - phi(r - b);
    worst = std::max(worst, std::abs(lhs - rhs) / k);
  }
  EXPECT_LT(worst, 1e-13);  // measured: 2e-15 of K
}

TEST(CoarseGrainKernel, BranchGradientMatchesFiniteDifferences) {
  // All three components (the identity above checks only the one along the branch).
  const LucyKernel phi(kWidth);
  const double k = peak(kWidth);
  std::mt19937_64 rng(6);
  const double h = 1e-5 * kWidth;
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 a = randomVector(rng, 0.5 * kWidth);
    const Vec3 b = a + uniform(rng, 0.1, 3) * kWidth * randomVector(rng, 1).normalized();
    const Vec3 r = a + uniform(rng, -0.3, 1.3) * (b - a) + randomVector(rng, 0.6 * kWidth);
    const Vec3 g = phi.lineIntegralGradient(r, a, b);
    for (int axis = 0; axis < 3; ++axis) {
      const Vec3 e = h * Vec3::Unit(axis);
      const double fd = (phi.lineIntegral(r + e, a, b) - phi.lineIntegral(r - e, a, b)) / (2 * h);
      // Central differences: O(h²) ≈ 1e-10 K/c truncation plus 1e-16 K/h ≈ 1e-11 K/c round-off.
      EXPECT_NEAR(g[axis], fd, 1e-8 * k / kWidth);
    }
  }
}
