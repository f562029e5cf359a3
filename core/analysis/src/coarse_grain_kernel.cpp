/// Lucy's kernel and its branch integrals (coarse_grain_kernel.hpp).
#include "granular/coarse_grain_kernel.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "granular/error.hpp"

namespace granular {
namespace {

constexpr int kGaussPoints = 12;

/// Gauss–Legendre nodes and weights on [-1, 1], by Newton's method on P_n from the usual
/// cosine guesses (converges in a few steps to round-off for every node).
struct GaussLegendre {
  std::array<double, kGaussPoints> node{};
  std::array<double, kGaussPoints> weight{};
};

const GaussLegendre& gaussLegendre() {
  static const GaussLegendre rule = [] {
    GaussLegendre g;
    constexpr int n = kGaussPoints;
    for (int i = 0; i < n; ++i) {
      double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
      double derivative = 1;
      for (int iteration = 0; iteration < 100; ++iteration) {
        double p0 = 1, p1 = x;  // P_{k-1}, P_k by the three-term recurrence
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        derivative = n * (x * p1 - p0) / (x * x - 1);
        const double dx = p1 / derivative;
        x -= dx;
        if (std::abs(dx) < 1e-16) break;
      }
      g.node[i] = x;
      g.weight[i] = 2 / ((1 - x * x) * derivative * derivative);
    }
    return g;
  }();
  return rule;
}

/// Finest piece of the grading, as a fraction of a side's length (see lineIntegral's doc).
constexpr double kFinestPiece = 1.0 / 4096;

/// ∫₀¹ f(p − s d) ds for an integrand f supported in |x| < c that is a polynomial in x and
/// |x| (φ or ∇φ), by graded Gauss–Legendre in the distance u along the line (see lineIntegral).
template <class T, class F>
T integrateAlongBranch(const Vec3& p, const Vec3& d, double c, const T& zero, const F& f) {
  const double length2 = d.squaredNorm();
  if (length2 == 0) return f(p);
  const double length = std::sqrt(length2);
  const Vec3 dir = d / length;
  // x(u) = closest − u·dir; s = 0 is u = −along, s = 1 is u = L − along. Working from the
  // closest point (not from s) keeps the positions accurate when L ≪ c.
  const double along = p.dot(dir);
  const Vec3 closest = p - along * dir;
  const double m = closest.norm();
  if (!(m < c)) return zero;
  const double half = std::sqrt((c - m) * (c + m));  // support: |u| < half
  const double uA = std::max(-along, -half), uB = std::min(length - along, half);
  if (!(uB > uA)) return zero;

  const GaussLegendre& gl = gaussLegendre();
  T sum = zero;
  // One side of u = 0: distances t in [ta, tb], u = sign·t.
  auto side = [&](double sign, double ta, double tb) {
    const double finest = (tb - ta) * kFinestPiece;
    for (double cursor = ta; cursor < tb;) {
      // A piece no longer than its distance to the branch points u = ±i m.
      const double width = std::max(std::hypot(cursor, m), finest);
      const double next = cursor + width >= tb ? tb : cursor + width;
      const double mid = 0.5 * (cursor + next), halfWidth = 0.5 * (next - cursor);
      for (int k = 0; k < kGaussPoints; ++k) {
        const double u = sign * (mid + halfWidth * gl.node[k]);
        sum += (halfWidth * gl.weight[k]) * f(Vec3(closest - u * dir));
      }
      cursor = next;
    }
  };
  if (uA < 0) side(-1.0, std::max(-uB, 0.0), -uA);
  if (uB > 0) side(1.0, std::max(uA, 0.0), uB);
  return sum / length;  // ds = du / L
}

}  // namespace

LucyKernel::LucyKernel(double width) : width_(width) {
  if (!(width > 0) || !std::isfinite(width)) throw ConfigError("LucyKernel: width must be > 0");
  norm_ = 105.0 / (16.0 * std::numbers::pi * width * width * width);
}

double LucyKernel::lineIntegral(const Vec3& r, const Vec3& a, const Vec3& b) const {
  return integrateAlongBranch(r - a, b - a, width_, 0.0,
                              [this](const Vec3& x) { return value(x.norm()); });
}

Vec3 LucyKernel::lineIntegralGradient(const Vec3& r, const Vec3& a, const Vec3& b) const {
  return integrateAlongBranch(r - a, b - a, width_, Vec3(Vec3::Zero()),
                              [this](const Vec3& x) { return gradient(x); });
}

}  // namespace granular
