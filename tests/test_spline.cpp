/// Not-a-knot cubic splines (spline.hpp): exact on cubics (inside and outside the nodes),
/// interpolating, fourth-order on smooth functions, graceful with few nodes, fast.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include "granular/error.hpp"
#include "granular/spline.hpp"

using namespace granular;

namespace {

double uniform(std::mt19937_64& rng, double a, double b) {
  return a + (b - a) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Samples f on the grid origin + (i, j, k)∘spacing, x fastest.
template <class F>
std::vector<double> sample(const F& f, const Vec3& origin, const Vec3& spacing,
                           std::array<int, 3> counts) {
  std::vector<double> values;
  for (int k = 0; k < counts[2]; ++k)
    for (int j = 0; j < counts[1]; ++j)
      for (int i = 0; i < counts[0]; ++i)
        values.push_back(f(origin + Vec3(i, j, k).cwiseProduct(spacing)));
  return values;
}

/// A random point in the grid's node box widened by `margin` node spacings on every side.
Vec3 randomPoint(std::mt19937_64& rng, const Vec3& origin, const Vec3& spacing,
                 std::array<int, 3> counts, double margin) {
  Vec3 p;
  for (int k = 0; k < 3; ++k) {
    const double lo = origin[k] - margin * spacing[k];
    const double hi = origin[k] + (counts[k] - 1 + margin) * spacing[k];
    p[k] = uniform(rng, lo, hi);
  }
  return p;
}

}  // namespace

TEST(Spline, OneDimensionalReproducesCubicsInsideAndOutside) {
  auto f = [](double x) { return 2 * x * x * x - x * x + 3 * x - 1; };
  auto f2 = [](double x) { return 12 * x - 2; };  // f''
  std::mt19937_64 rng(1);
  for (int n = 4; n <= 9; ++n) {
    const double x0 = -0.7, h = 0.13;
    std::vector<double> y;
    for (int i = 0; i < n; ++i) y.push_back(f(x0 + i * h));
    const CubicSpline s(x0, h, y);
    for (int i = 0; i < n; ++i) EXPECT_NEAR(s.secondDerivatives()[i], f2(x0 + i * h), 1e-11);
    for (int trial = 0; trial < 200; ++trial) {
      // Up to three spacings beyond either end node.
      const double x = uniform(rng, x0 - 3 * h, x0 + (n + 2) * h);
      EXPECT_NEAR(s(x), f(x), 1e-12) << n << " " << x;
    }
  }
}

TEST(Spline, FewNodesGiveTheLowerDegreeInterpolant) {
  std::mt19937_64 rng(2);
  auto quadratic = [](double x) { return 0.5 * x * x - 2 * x + 0.25; };
  const CubicSpline three(1.0, 0.5, {quadratic(1.0), quadratic(1.5), quadratic(2.0)});
  const CubicSpline two(1.0, 0.5, {3.0, 4.0});
  const CubicSpline one(1.0, 0.5, {7.5});
  for (int trial = 0; trial < 50; ++trial) {
    const double x = uniform(rng, -1, 4);
    EXPECT_NEAR(three(x), quadratic(x), 1e-13);
    EXPECT_NEAR(two(x), 3.0 + 2.0 * (x - 1.0), 1e-13);
    EXPECT_EQ(one(x), 7.5);
  }
}

TEST(Spline, TricubicReproducesPolynomialsOfDegreeThreePerVariable) {
  // In the tensor-product space: cubic in each variable separately, including x³y³z³.
  auto f = [](const Vec3& p) {
    const double x = p.x(), y = p.y(), z = p.z();
    return x * x * x - 2 * x * y * y + z * z * z + y * z + 0.3 * x * x * x * y * y * y * z * z * z;
  };
  const Vec3 origin(-0.4, 0.2, -1.0), spacing(0.15, 0.11, 0.2);
  const std::array<int, 3> counts = {7, 4, 9};  // 4 nodes: a single cubic along y
  const TricubicSpline s(origin, spacing, counts, sample(f, origin, spacing, counts));
  std::mt19937_64 rng(3);
  int outside = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    // Interior and up to one spacing outside (the paper extrapolates half a cell to the walls).
    const Vec3 p = randomPoint(rng, origin, spacing, counts, 1.0);
    EXPECT_NEAR(s(p), f(p), 1e-12) << p.transpose();
    for (int k = 0; k < 3; ++k)
      if (p[k] < origin[k] || p[k] > origin[k] + (counts[k] - 1) * spacing[k]) {
        ++outside;
        break;
      }
  }
  // Farther out the cubic is still the same polynomial, but the weights of the second
  // derivatives grow like t³ per axis and amplify their round-off (measured: 3e-12 at two
  // spacings, 7e-14 at one, 1e-15 inside); exact up to that.
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3 p = randomPoint(rng, origin, spacing, counts, 3.0);
    EXPECT_NEAR(s(p), f(p), 1e-10 * std::max(1.0, std::abs(f(p)))) << p.transpose();
  }
  EXPECT_GT(outside, 500);  // many draws leave the node box along some axis
}

TEST(Spline, TricubicInterpolatesNodeValues) {
  std::mt19937_64 rng(4);
  const Vec3 origin(0.05, 0.05, 0.05), spacing(0.1, 0.1, 0.1);
  const std::array<int, 3> counts = {6, 5, 12};
  std::vector<double> values;
  for (int n = 0; n < 6 * 5 * 12; ++n) values.push_back(uniform(rng, -2000, 0));  // [Pa]
  const TricubicSpline s(origin, spacing, counts, values);
  std::size_t n = 0;
  for (int k = 0; k < counts[2]; ++k)
    for (int j = 0; j < counts[1]; ++j)
      for (int i = 0; i < counts[0]; ++i, ++n)
        EXPECT_NEAR(s(origin + Vec3(i, j, k).cwiseProduct(spacing)), values[n], 1e-10);
}

TEST(Spline, FewNodesAlongAnAxisReduceTheDegreeThere) {
  // One node in x (constant), three in y (quadratic), two in z (linear): that polynomial space
  // is reproduced everywhere.
  auto f = [](const Vec3& p) { return 1.5 + p.y() * p.y() - 0.5 * p.y() * p.z() + 2 * p.z(); };
  const Vec3 origin(0.3, -0.2, 0.1), spacing(1.0, 0.25, 0.4);
  const std::array<int, 3> counts = {1, 3, 2};
  const TricubicSpline s(origin, spacing, counts, sample(f, origin, spacing, counts));
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 p = randomPoint(rng, origin, spacing, counts, 2.0);
    EXPECT_NEAR(s(p), f(p), 1e-13) << p.transpose();
  }
}

TEST(Spline, ConvergesAtFourthOrder) {
  // f smooth, not polynomial: the max error over fixed points must fall 2⁴ = 16-fold per halving
  // of h (not-a-knot keeps fourth order up to the ends, unlike natural end conditions).
  auto f = [](const Vec3& p) {
    return std::sin(2 * p.x()) * std::cos(3 * p.y()) * std::exp(p.z());
  };
  std::mt19937_64 rng(6);
  std::vector<Vec3> points;
  for (int i = 0; i < 3000; ++i)
    points.emplace_back(uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, 0, 1));
  std::vector<double> errors;
  for (int cells : {8, 16, 32}) {
    const Vec3 spacing = Vec3::Constant(1.0 / cells);
    const std::array<int, 3> counts = {cells + 1, cells + 1, cells + 1};
    const TricubicSpline s(Vec3::Zero(), spacing, counts, sample(f, Vec3::Zero(), spacing, counts));
    double worst = 0;
    for (const Vec3& p : points) worst = std::max(worst, std::abs(s(p) - f(p)));
    errors.push_back(worst);
  }
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double ratio = errors[i - 1] / errors[i];
    EXPECT_GT(ratio, 13.0) << i;
    EXPECT_LT(ratio, 19.0) << i;
  }
  // And the same in 1-D, where many more points are cheap.
  auto g = [](double x) { return std::exp(std::sin(3 * x)); };
  std::vector<double> errors1;
  for (int cells : {10, 20, 40, 80}) {
    std::vector<double> y;
    for (int i = 0; i <= cells; ++i) y.push_back(g(static_cast<double>(i) / cells));
    const CubicSpline s(0.0, 1.0 / cells, y);
    double worst = 0;
    for (int i = 0; i <= 10000; ++i) worst = std::max(worst, std::abs(s(i / 1e4) - g(i / 1e4)));
    errors1.push_back(worst);
  }
  for (std::size_t i = 1; i < errors1.size(); ++i) {
    const double ratio = errors1[i - 1] / errors1[i];
    EXPECT_GT(ratio, 13.0) << i;
    EXPECT_LT(ratio, 19.0) << i;
  }
}

TEST(Spline, RejectsBadGrids) {
  EXPECT_THROW(CubicSpline(0, 0.1, {}), ConfigError);
  EXPECT_THROW(CubicSpline(0, 0.0, {1, 2, 3, 4}), ConfigError);
  EXPECT_THROW(TricubicSpline(Vec3::Zero(), Vec3::Ones(), {2, 2, 2}, std::vector<double>(7)),
               ConfigError);
  EXPECT_THROW(TricubicSpline(Vec3::Zero(), Vec3::Ones(), {0, 2, 2}, {}), ConfigError);
  EXPECT_THROW(TricubicSpline(Vec3::Zero(), Vec3(1, -1, 1), {2, 2, 2}, std::vector<double>(8)),
               ConfigError);
}

TEST(Spline, EvaluatesAMillionPointsWellUnderASecond) {
  const Vec3 origin = Vec3::Zero(), spacing = Vec3::Constant(0.1);
  const std::array<int, 3> counts = {12, 12, 30};
  std::mt19937_64 rng(7);
  std::vector<double> values;
  for (int n = 0; n < 12 * 12 * 30; ++n) values.push_back(uniform(rng, -1, 1));
  const TricubicSpline s(origin, spacing, counts, values);
  std::vector<Vec3> points;
  for (int i = 0; i < 1000000; ++i)
    points.push_back(randomPoint(rng, origin, spacing, counts, 0.5));
  const auto start = std::chrono::steady_clock::now();
  double sum = 0;
  for (const Vec3& p : points) sum += s(p);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(std::isfinite(sum));
#if defined(NDEBUG) && !defined(__SANITIZE_ADDRESS__)
  EXPECT_LT(seconds, 0.5) << "1e6 evaluations";  // optimised builds only
#endif
  RecordProperty("seconds_per_million", std::to_string(seconds));
}
