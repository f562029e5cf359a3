/// Exact volumes of sphere pieces (geometry.hpp).
///
/// Sections: tanh-sinh quadrature; caps and slabs; disc ∩ rectangle; sphere ∩ box; lens.
#include "granular/geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace granular {
namespace {

constexpr double kPi = std::numbers::pi;

// ---------------------------------------------------------------------------------------------
// Tanh-sinh quadrature (Takahasi & Mori 1974; Bailey, Jeyabalan & Li, Exp. Math. 14, 2005).
// ∫_{-1}^{1} f(x) dx = ∫ f(tanh(π/2 sinh t)) (π/2) cosh t / cosh²(π/2 sinh t) dt, summed by the
// trapezoidal rule in t. The weights decay double-exponentially, so algebraic endpoint
// behaviour such as (x + 1)^{3/2} costs nothing, and the error of step h is ~exp(-c/h): it
// roughly squares when h halves.

/// One abscissa of the rule: the distance δ = 1 − tanh(u) of the node from the end of [-1, 1]
/// (kept apart so that nodes near an end do not lose digits to 1 − x) and the weight.
struct TanhSinhNode {
  double gap = 0;     ///< 1 − x_t [-]
  double weight = 0;  ///< dx/dt [-]
};

constexpr int kTanhSinhLevels = 8;     // h = 1 ... 2^-7
constexpr double kTanhSinhMaxT = 3.6;  // weight there ~1e-23 of the central one: negligible

/// Nodes t > 0 new at each level: t = j (level 0), t = (2j − 1)·2^-level (level ≥ 1).
const std::array<std::vector<TanhSinhNode>, kTanhSinhLevels>& tanhSinhTable() {
  static const auto table = [] {
    std::array<std::vector<TanhSinhNode>, kTanhSinhLevels> levels;
    for (int level = 0; level < kTanhSinhLevels; ++level) {
      const double h = std::ldexp(1.0, -level);
      const double first = level == 0 ? 1.0 : h;
      const double stride = level == 0 ? 1.0 : 2.0 * h;
      for (double t = first; t <= kTanhSinhMaxT; t += stride) {
        const double u = 0.5 * kPi * std::sinh(t);
        const double coshU = std::cosh(u);
        // 1 − tanh u = 2 / (1 + e^{2u}): no cancellation for large u.
        levels[level].push_back(
            {2.0 / (1.0 + std::exp(2.0 * u)), 0.5 * kPi * std::cosh(t) / (coshU * coshU)});
      }
    }
    return levels;
  }();
  return table;
}

/// ∫_a^b f, halving the step until two estimates agree to `relTol` (plus `absTol` [same units
/// as the integral]). The error after the accepted level is about the square of that
/// difference, i.e. round-off.
template <class F>
double tanhSinh(const F& f, double a, double b, double relTol, double absTol) {
  const double half = 0.5 * (b - a);
  if (!(half > 0)) return 0;
  const auto& table = tanhSinhTable();
  double sum = 0.5 * kPi * f(0.5 * (a + b));  // t = 0: x = 0, weight π/2
  double estimate = 0;
  for (int level = 0; level < kTanhSinhLevels; ++level) {
    for (const TanhSinhNode& node : table[level]) {
      const double offset = half * node.gap;
      sum += node.weight * (f(a + offset) + f(b - offset));
    }
    const double next = std::ldexp(sum, -level) * half;
    const bool converged =
        level >= 3 && std::abs(next - estimate) <= relTol * std::abs(next) + absTol;
    estimate = next;
    if (converged) break;
  }
  return estimate;
}

// ---------------------------------------------------------------------------------------------
// Caps and slabs.

/// Volume of the sphere between the planes lo < hi (relative to its centre, within [-R, R]),
/// as the whole minus caps, choosing the caps so that no large numbers cancel.
double slabVolume(double radius, double lo, double hi) {
  if (lo >= 0) return sphereCapVolume(radius, radius - lo) - sphereCapVolume(radius, radius - hi);
  if (hi <= 0) return sphereCapVolume(radius, radius + hi) - sphereCapVolume(radius, radius + lo);
  return 4.0 / 3.0 * kPi * radius * radius * radius - sphereCapVolume(radius, radius + lo) -
         sphereCapVolume(radius, radius - hi);
}

// ---------------------------------------------------------------------------------------------
// Disc ∩ rectangle.

/// A point of the circle-side of the integrand: x and the half chord s = √(r² − x²), computed
/// from whichever of the two is known exactly, so the angle atan2(x, s) is accurate even near
/// x = ±r (asin(x/r) there would turn a round-off of 1e-16 into an angle error of 1e-8).
struct ChordPoint {
  double x = 0;
  double s = 0;
};

/// ∫_u^v √(r² − x²) dx = ½ [x s + r² atan2(x, s)]_u^v.
double chordIntegral(double r, const ChordPoint& u, const ChordPoint& v) {
  return 0.5 * ((v.x * v.s - u.x * u.s) + r * r * (std::atan2(v.x, v.s) - std::atan2(u.x, u.s)));
}

/// Insertion sort of the first n entries by key: these arrays hold at most 18 entries (and
/// std::sort on a short std::array trips GCC 12's -Warray-bounds with a false positive).
template <class T, std::size_t N, class Key>
void sortSmall(std::array<T, N>& a, int n, const Key& key) {
  for (int i = 1; i < n; ++i) {
    const T item = a[i];
    int j = i;
    for (; j > 0 && key(a[j - 1]) > key(item); --j) a[j] = a[j - 1];
    a[j] = item;
  }
}

/// Half chord at x, with (r − |x|)(r + |x|) instead of r² − x² for accuracy near the ends.
double halfChord(double r, double x) {
  const double ax = std::abs(x);
  return ax >= r ? 0.0 : std::sqrt((r - ax) * (r + ax));
}

}  // namespace

double sphereCapVolume(double radius, double height) {
  if (!(radius > 0)) return 0;
  const double h = std::clamp(height, 0.0, 2.0 * radius);
  return kPi * h * h * (3.0 * radius - h) / 3.0;
}

double discRectangleArea(double cx, double cy, double radius, double xMin, double xMax, double yMin,
                         double yMax) {
  if (!(radius > 0) || !(xMax > xMin) || !(yMax > yMin)) return 0;
  const double r = radius;
  const double x0 = std::max(xMin - cx, -r), x1 = std::min(xMax - cx, r);
  const double y0 = yMin - cy, y1 = yMax - cy;
  if (!(x1 > x0) || y1 <= -r || y0 >= r) return 0;

  // The integrand min(y1, s) − max(y0, −s), clipped at 0, changes form only where s = |y0| or
  // s = |y1|, i.e. at x = ±√(r² − y²): there the half chord is |y| exactly.
  std::array<ChordPoint, 6> cuts;
  int n = 0;
  cuts[n++] = {x0, halfChord(r, x0)};
  cuts[n++] = {x1, halfChord(r, x1)};
  for (double y : {y0, y1}) {
    const double ay = std::abs(y);
    if (ay >= r) continue;
    const double xb = std::sqrt((r - ay) * (r + ay));
    if (xb > x0 && xb < x1) cuts[n++] = {xb, ay};
    if (-xb > x0 && -xb < x1) cuts[n++] = {-xb, ay};
  }
  sortSmall(cuts, n, [](const ChordPoint& p) { return p.x; });

  double area = 0;
  for (int k = 0; k + 1 < n; ++k) {
    const ChordPoint& u = cuts[k];
    const ChordPoint& v = cuts[k + 1];
    if (!(v.x > u.x)) continue;
    // Which branch holds on this piece is read at its middle, away from the switching points.
    const double s = halfChord(r, 0.5 * (u.x + v.x));
    const bool topIsSide = y1<s, bottomIsSide = y0> - s;
    const double top = topIsSide ? y1 : s, bottom = bottomIsSide ? y0 : -s;
    if (!(top > bottom)) continue;
    const double width = v.x - u.x;
    const double arc = (topIsSide && bottomIsSide) ? 0.0 : chordIntegral(r, u, v);
    area += (topIsSide ? y1 * width : arc) - (bottomIsSide ? y0 * width : -arc);
  }
  return area;
}

double sphereBoxVolume(const Vec3& centre, double radius, const Vec3& boxMin, const Vec3& boxMax) {
  if (!(radius > 0) || !(boxMax.array() > boxMin.array()).all()) return 0;
  const double r = radius;
  // Box relative to the centre, clipped to the sphere's bounding cube.
  Vec3 lo = boxMin - centre, hi = boxMax - centre;
  double gap2 = 0;  // squared distance from the centre to the box
  int cuts = 0, cutAxis = -1;
  for (int k = 0; k < 3; ++k) {
    gap2 += std::pow(std::max({lo[k], -hi[k], 0.0}), 2);
    lo[k] = std::max(lo[k], -r);
    hi[k] = std::min(hi[k], r);
    if (!(hi[k] > lo[k])) return 0;
    if (lo[k] > -r || hi[k] < r) {
      ++cuts;
      cutAxis = k;
    }
  }
  if (gap2 >= r * r) return 0;
  if (cuts == 0) return 4.0 / 3.0 * kPi * r * r * r;
  if (cuts == 1) return slabVolume(r, lo[cutAxis], hi[cutAxis]);

  // Breakpoints in z: where the section radius ρ(z) = √(R² − z²) equals the distance to a side
  // line (|x0|, |x1|, |y0|, |y1|) or to a corner of the rectangle; between them A(z) is analytic.
  const double zLo = lo.z(), zHi = hi.z();
  std::array<double, 18> breaks;
  int n = 0;
  breaks[n++] = zLo;
  breaks[n++] = zHi;
  auto addDistance = [&](double d2) {
    if (!(d2 < r * r)) return;
    const double zb = std::sqrt(r * r - d2);
    if (zb > zLo && zb < zHi) breaks[n++] = zb;
    if (-zb > zLo && -zb < zHi) breaks[n++] = -zb;
  };
  for (int k = 0; k < 2; ++k) {
    addDistance(lo[k] * lo[k]);
    addDistance(hi[k] * hi[k]);
  }
  for (double x : {lo.x(), hi.x()})
    for (double y : {lo.y(), hi.y()}) addDistance(x * x + y * y);
  sortSmall(breaks, n, [](double z) { return z; });

  auto section = [&](double z) {
    const double rho = halfChord(r, z);
    return discRectangleArea(0.0, 0.0, rho, lo.x(), hi.x(), lo.y(), hi.y());
  };
  // Absolute floor: pieces whose volume is ~1e-16 of the sphere's need no relative accuracy.
  const double absTol = 1e-16 * r * r * r;
  double volume = 0;
  for (int k = 0; k + 1 < n; ++k)
    volume += tanhSinh(section, breaks[k], breaks[k + 1], 1e-10, absTol);
  return volume;
}

double lensVolume(double r1, double r2, double distance) {
  if (!(r1 > 0) || !(r2 > 0)) return 0;
  const double d = std::abs(distance);
  if (d >= r1 + r2) return 0;
  if (d <= std::abs(r1 - r2)) {
    const double r = std::min(r1, r2);
    return 4.0 / 3.0 * kPi * r * r * r;
  }
  const double sum = r1 + r2, diff = r1 - r2;
  // d² + 2d(r1 + r2) − 3(r1 − r2)² ≥ d² + 2d·d − 3d² = 0 here, and the division by d is safe:
  // d > |r1 − r2| ≥ 0.
  return kPi * (sum - d) * (sum - d) * (d * d + 2.0 * d * sum - 3.0 * diff * diff) / (12.0 * d);
}

}  // namespace granular
