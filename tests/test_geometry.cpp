/// Exact sphere volumes (geometry.hpp) against closed forms, symmetry, additivity and an
/// independent nested adaptive Gauss–Kronrod quadrature of the chord length.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "granular/geometry.hpp"

using namespace granular;

namespace {

constexpr double kPi = std::numbers::pi;

double ballVolume(double r) {
  return 4.0 / 3.0 * kPi * r * r * r;
}

double uniform(std::mt19937_64& rng, double a, double b) {
  return a + (b - a) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Adaptive Gauss–Kronrod (7, 15) (QUADPACK's QK15 rule): an interval is accepted when the
/// Gauss and Kronrod estimates differ by at most `tol` [integral units], once it is at least
/// `minDepth` bisections deep (so that a kink cannot fool both rules at the first look); else it
/// is bisected. The Kronrod estimate is far more accurate than that difference.
template <class F>
double gaussKronrod(const F& f, double a, double b, double tol, int minDepth, int depth = 0) {
  static constexpr std::array<double, 8> xk = {
      0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
      0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
      0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
      0.207784955007898467600689403773245, 0.0};
  static constexpr std::array<double, 8> wk = {
      0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
      0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
      0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
      0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
  // 7-point Gauss weights at xk[1], xk[3], xk[5], xk[7].
  static constexpr std::array<double, 4> wg = {
      0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
      0.381830050505118944950369775488975, 0.417959183673469387755102040816327};
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double kronrod = wk[7] * f(mid), gauss = wg[3] * f(mid);
  for (int i = 0; i < 7; ++i) {
    const double pair = f(mid - half * xk[i]) + f(mid + half * xk[i]);
    kronrod += wk[i] * pair;
    if (i % 2 == 1) gauss += wg[i / 2] * pair;
  }
  kronrod *= half;
  gauss *= half;
  if ((depth >= minDepth && std::abs(kronrod - gauss) <= tol) || depth >= 60) return kronrod;
  return gaussKronrod(f, a, mid, tol, minDepth, depth + 1) +
         gaussKronrod(f, mid, b, tol, minDepth, depth + 1);
}

/// V = ∫∫ (length of [z0, z1] ∩ [cz − h, cz + h]) dx dy, h = √(R² − x² − y²): the chord is exact,
/// y and x are integrated adaptively. Both are split where their integrands are not smooth,
/// because Gauss and Kronrod can agree by accident across a kink (unsplit, this reference was
/// off by up to 1e-9 and missed a 6e-10 sliver altogether): y where the chord meets z0 or z1;
/// x where the y–z section circle, radius √(R² − x²), passes a side line or a corner of the
/// y–z rectangle. Nothing is shared with the library's method (exact section areas in z).
double nestedQuadratureVolume(const Vec3& c, double r, const Vec3& lo, const Vec3& hi, double tol) {
  const double xa = std::max(lo.x(), c.x() - r), xb = std::min(hi.x(), c.x() + r);
  if (!(xb > xa)) return 0;
  auto inner = [&](double x) {
    const double dx = x - c.x();
    const double yHalf = std::sqrt(std::max(0.0, r * r - dx * dx));
    const double ya = std::max(lo.y(), c.y() - yHalf), yb = std::min(hi.y(), c.y() + yHalf);
    if (!(yb > ya)) return 0.0;
    auto chord = [&](double y) {
      const double dy = y - c.y();
      const double h = std::sqrt(std::max(0.0, r * r - dx * dx - dy * dy));
      return std::max(0.0, std::min(hi.z(), c.z() + h) - std::max(lo.z(), c.z() - h));
    };
    std::vector<double> cuts = {ya, yb};
    for (double dz : {lo.z() - c.z(), hi.z() - c.z()}) {
      const double q = r * r - dx * dx - dz * dz;
      if (q <= 0) continue;
      for (double y : {c.y() - std::sqrt(q), c.y() + std::sqrt(q)})
        if (y > ya && y < yb) cuts.push_back(y);
    }
    std::sort(cuts.begin(), cuts.end());
    double sum = 0;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
      sum += gaussKronrod(chord, cuts[i], cuts[i + 1], 0.1 * tol, 0);
    return sum;
  };
  std::vector<double> cuts = {xa, xb};
  const std::array<double, 2> ys = {lo.y() - c.y(), hi.y() - c.y()};
  const std::array<double, 2> zs = {lo.z() - c.z(), hi.z() - c.z()};
  std::vector<double> distances2;  // squared distances to side lines and corners in y–z
  for (double y : ys) distances2.push_back(y * y);
  for (double z : zs) distances2.push_back(z * z);
  for (double y : ys)
    for (double z : zs) distances2.push_back(y * y + z * z);
  for (double d2 : distances2) {
    if (d2 >= r * r) continue;
    const double q = std::sqrt(r * r - d2);
    for (double x : {c.x() - q, c.x() + q})
      if (x > xa && x < xb) cuts.push_back(x);
  }
  std::sort(cuts.begin(), cuts.end());
  double sum = 0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
    sum += gaussKronrod(inner, cuts[i], cuts[i + 1], tol, 2);
  return sum;
}

}  // namespace

TEST(Geometry, GaussKronrodReferenceIsExactOnPolynomialsAndConvergesOnASqrt) {
  // The reference of the random-position test must itself be right: QK15 integrates degree 22
  // exactly, and √x on [0, 1] (an endpoint singularity like the chord's) gives 2/3.
  auto poly = [](double x) { return std::pow(x, 21) - 3 * std::pow(x, 8) + 2; };
  const double exact = (std::pow(2.0, 22) - 1) / 22 - 3 * (std::pow(2.0, 9) - 1) / 9 + 2;
  EXPECT_NEAR(gaussKronrod(poly, 1.0, 2.0, 1e-9, 0), exact, 1e-12 * exact);
  EXPECT_NEAR(gaussKronrod([](double x) { return std::sqrt(x); }, 0.0, 1.0, 1e-15, 0), 2.0 / 3.0,
              1e-13);
}

TEST(Geometry, CapVolumeClosedForms) {
  const double r = 0.7;
  EXPECT_EQ(sphereCapVolume(r, 0.0), 0.0);
  EXPECT_EQ(sphereCapVolume(r, -0.1), 0.0);
  EXPECT_NEAR(sphereCapVolume(r, r), 0.5 * ballVolume(r), 1e-15);
  EXPECT_NEAR(sphereCapVolume(r, 2 * r), ballVolume(r), 1e-15);
  EXPECT_NEAR(sphereCapVolume(r, 5 * r), ballVolume(r), 1e-15);  // clamped
  // h = R/2 by stacking discs: ∫_{R/2}^{R} π (R² − z²) dz.
  const double byDiscs = kPi * (r * r * (r - r / 2) - (r * r * r - r * r * r / 8) / 3);
  EXPECT_NEAR(sphereCapVolume(r, r / 2), byDiscs, 1e-15);
  // Complementary caps fill the sphere.
  EXPECT_NEAR(sphereCapVolume(r, 0.3) + sphereCapVolume(r, 2 * r - 0.3), ballVolume(r), 1e-15);
  EXPECT_EQ(sphereCapVolume(0.0, 1.0), 0.0);
}

TEST(Geometry, DiscRectangleAreaClosedForms) {
  const double r = 1.3;
  const double disc = kPi * r * r;
  // Whole disc, half, quarter (centre on a side, on a corner).
  EXPECT_NEAR(discRectangleArea(0.2, -0.1, r, -5, 5, -5, 5), disc, 1e-14);
  EXPECT_NEAR(discRectangleArea(0.2, -0.1, r, 0.2, 5, -5, 5), disc / 2, 1e-14);
  EXPECT_NEAR(discRectangleArea(0.2, -0.1, r, -5, 0.2, -0.1, 5), disc / 4, 1e-14);
  // A rectangle inside the disc.
  EXPECT_NEAR(discRectangleArea(0, 0, r, -0.5, 0.4, -0.3, 0.6), 0.9 * 0.9, 1e-15);
  // One side line at distance d: the segment r² acos(d/r) − d √(r² − d²) is cut off.
  const double d = 0.45;
  const double segment = r * r * std::acos(d / r) - d * std::sqrt(r * r - d * d);
  EXPECT_NEAR(discRectangleArea(0, 0, r, -5, d, -5, 5), disc - segment, 1e-14);
  EXPECT_NEAR(discRectangleArea(0, 0, r, -5, 5, d, 5), segment, 1e-14);
  // A strip |y| < d through the centre: the disc minus two segments.
  EXPECT_NEAR(discRectangleArea(0, 0, r, -5, 5, -d, d), disc - 2 * segment, 1e-14);
  // Disjoint, empty, and a side tangent at a point.
  EXPECT_EQ(discRectangleArea(0, 0, r, 2, 3, -1, 1), 0.0);
  EXPECT_EQ(discRectangleArea(0, 0, r, 1, 1, -1, 1), 0.0);
  EXPECT_EQ(discRectangleArea(0, 0, r, -5, 5, r, 5), 0.0);
  // A line almost through the centre: asin-based forms lose 1e-8 here; the area must not.
  const double tiny = 1e-13;
  EXPECT_NEAR(discRectangleArea(0, 0, r, -5, 5, tiny, 5), disc / 2 - 2 * r * tiny, 1e-15);
}

TEST(Geometry, SphereOnAFaceAnEdgeAndACorner) {
  const double r = 0.031;
  const Vec3 lo(0, 0, 0), hi(0.4, 0.5, 1.1);
  const double v = ballVolume(r);
  // Inside, on each face, on each kind of edge, on a corner.
  EXPECT_NEAR(sphereBoxVolume(Vec3(0.2, 0.2, 0.2), r, lo, hi), v, 1e-15 * v);
  for (int axis = 0; axis < 3; ++axis) {
    for (bool upper : {false, true}) {
      Vec3 c(0.2, 0.2, 0.2);
      c[axis] = upper ? hi[axis] : lo[axis];
      EXPECT_NEAR(sphereBoxVolume(c, r, lo, hi), v / 2, 1e-14 * v) << axis << upper;
    }
  }
  EXPECT_NEAR(sphereBoxVolume(Vec3(0, 0, 0.3), r, lo, hi), v / 4, 1e-14 * v);
  EXPECT_NEAR(sphereBoxVolume(Vec3(0.4, 0.2, 0), r, lo, hi), v / 4, 1e-14 * v);
  EXPECT_NEAR(sphereBoxVolume(Vec3(0.1, 0.5, 1.1), r, lo, hi), v / 4, 1e-14 * v);
  EXPECT_NEAR(sphereBoxVolume(Vec3(0, 0, 0), r, lo, hi), v / 8, 1e-14 * v);
  EXPECT_NEAR(sphereBoxVolume(Vec3(0.4, 0.5, 1.1), r, lo, hi), v / 8, 1e-14 * v);
  EXPECT_NEAR(sphereBoxVolume(Vec3(0.4, 0, 1.1), r, lo, hi), v / 8, 1e-14 * v);
}

TEST(Geometry, CutsAlongOneAxisAreCapsAndSlabs) {
  const double r = 0.8;
  const Vec3 lo(-3, -3, -3), hi(3, 3, 0.25);
  // Centre 0.25 − 0.6 below the top face: the cap of height 0.8 − 0.6 is outside.
  const Vec3 c(0.1, -0.2, 0.25 - 0.6);
  EXPECT_NEAR(sphereBoxVolume(c, r, lo, hi), ballVolume(r) - sphereCapVolume(r, 0.2), 1e-15);
  // A slab thinner than the sphere: two caps removed.
  const Vec3 slabLo(-3, 0.1, -3), slabHi(3, 0.5, 3);
  const double slab = ballVolume(r) - sphereCapVolume(r, r + 0.1) - sphereCapVolume(r, r - 0.5);
  EXPECT_NEAR(sphereBoxVolume(Vec3::Zero(), r, slabLo, slabHi), slab, 1e-15);
}

TEST(Geometry, OutsideTouchingAndEmpty) {
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  EXPECT_EQ(sphereBoxVolume(Vec3(3, 0.5, 0.5), 0.5, lo, hi), 0.0);
  // Outside the corner although every axis range overlaps the box's.
  const double off = 0.5 / std::sqrt(3.0) * 1.01;
  EXPECT_EQ(sphereBoxVolume(Vec3(-off, -off, -off), 0.5, lo, hi), 0.0);
  // Just inside the corner: tiny but positive, and below the octant bound.
  const double in = 0.5 / std::sqrt(3.0) * 0.99;
  const double sliver = sphereBoxVolume(Vec3(-in, -in, -in), 0.5, lo, hi);
  EXPECT_GT(sliver, 0.0);
  // The octant lies beyond the plane through the corner normal to the diagonal, so its share
  // is at most the cap that plane cuts off.
  EXPECT_LT(sliver, sphereCapVolume(0.5, 0.5 - std::sqrt(3.0) * in));
  // Tangent to a face from outside.
  EXPECT_EQ(sphereBoxVolume(Vec3(0.5, 0.5, 1.5), 0.5, lo, hi), 0.0);
  EXPECT_EQ(sphereBoxVolume(Vec3(0.5, 0.5, 0.5), 0.5, lo, Vec3(1, 0, 1)), 0.0);  // empty box
  EXPECT_EQ(sphereBoxVolume(Vec3(0.5, 0.5, 0.5), 0.0, lo, hi), 0.0);
}

TEST(Geometry, RandomPositionsMatchNestedAdaptiveQuadrature) {
  // Two boxes: one larger than the sphere (cuts by up to three faces at edges and corners) and
  // one smaller than it along every axis (cuts by opposite faces at once).
  std::mt19937_64 rng(20240611);
  const std::array<std::pair<Vec3, Vec3>, 2> boxes = {
      std::pair{Vec3(0, 0, 0), Vec3(2.0, 1.5, 3.0)},
      std::pair{Vec3(-0.3, -0.45, -0.2), Vec3(0.4, 0.5, 0.6)}};
  const double r = 1.0, tol = 1e-13;
  int cutCases = 0;
  for (const auto& [lo, hi] : boxes) {
    for (int trial = 0; trial < 60; ++trial) {
      const Vec3 c(uniform(rng, lo.x() - 0.8, hi.x() + 0.8),
                   uniform(rng, lo.y() - 0.8, hi.y() + 0.8),
                   uniform(rng, lo.z() - 0.8, hi.z() + 0.8));
      const double v = sphereBoxVolume(c, r, lo, hi);
      const double reference = nestedQuadratureVolume(c, r, lo, hi, tol);
      // The reference accepts intervals at |G − K| ≤ tol = 1e-13; the Kronrod sums are far
      // better than that (measured agreement over 300 draws: 6e-16 of the ball).
      EXPECT_NEAR(v, reference, 2e-14 * ballVolume(r)) << c.transpose();
      if (v > 0 && v < ballVolume(r)) ++cutCases;
    }
  }
  EXPECT_GE(cutCases, 60);  // the draws must exercise cuts, not just inside/outside
}

TEST(Geometry, SplittingTheBoxAddsUp) {
  // V(box) = V(box ∩ {x_k ≤ s}) + V(box ∩ {x_k ≥ s}) for any plane: exact up to quadrature.
  std::mt19937_64 rng(7);
  const Vec3 lo(0, 0, 0), hi(1.2, 0.9, 1.5);
  const double r = 0.5;
  double worst = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const Vec3 c(uniform(rng, -0.3, 1.5), uniform(rng, -0.3, 1.2), uniform(rng, -0.3, 1.8));
    const int axis = trial % 3;
    // A plane through the sphere and the box (outside the box one part would be inverted).
    const double s = uniform(rng, std::max(lo[axis], c[axis] - r), std::min(hi[axis], c[axis] + r));
    Vec3 midHi = hi, midLo = lo;
    midHi[axis] = s;
    midLo[axis] = s;
    const double whole = sphereBoxVolume(c, r, lo, hi);
    const double parts = sphereBoxVolume(c, r, lo, midHi) + sphereBoxVolume(c, r, midLo, hi);
    worst = std::max(worst, std::abs(whole - parts) / ballVolume(r));
  }
  EXPECT_LT(worst, 1e-14);
}

TEST(Geometry, InvariantUnderAxisPermutationAndReflection) {
  // The volume integrates along z; permuting the axes sends the cuts to other axes of the
  // integration, so this compares genuinely different evaluations of the same volume.
  std::mt19937_64 rng(11);
  const Vec3 lo(-0.2, 0.0, 0.1), hi(0.7, 0.6, 0.5);
  const double r = 0.45;
  for (int trial = 0; trial < 40; ++trial) {
    const Vec3 c(uniform(rng, -0.5, 1.0), uniform(rng, -0.3, 0.9), uniform(rng, -0.2, 0.8));
    const double v = sphereBoxVolume(c, r, lo, hi);
    auto rotate = [](const Vec3& p) { return Vec3(p.y(), p.z(), p.x()); };
    EXPECT_NEAR(sphereBoxVolume(rotate(c), r, rotate(lo), rotate(hi)), v, 1e-14 * ballVolume(r));
    EXPECT_NEAR(sphereBoxVolume(rotate(rotate(c)), r, rotate(rotate(lo)), rotate(rotate(hi))), v,
                1e-14 * ballVolume(r));
    const Vec3 flip(-1, 1, 1);
    const Vec3 cf = c.cwiseProduct(flip);
    const Vec3 lf(-hi.x(), lo.y(), lo.z()), hf(-lo.x(), hi.y(), hi.z());
    EXPECT_NEAR(sphereBoxVolume(cf, r, lf, hf), v, 1e-14 * ballVolume(r));
  }
}

TEST(Geometry, LensIsTwoCapsAndHasTheRightLimits) {
  // The radical plane sits a1 = (d² + r1² − r2²)/(2d) from centre 1; the lens is the cap of
  // height r1 − a1 of sphere 1 plus the cap of height r2 − (d − a1) of sphere 2.
  auto cap = [](double r, double h) { return kPi * h * h * (3 * r - h) / 3; };
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const double r1 = uniform(rng, 0.1, 1.0), r2 = uniform(rng, 0.1, 1.0);
    const double d = uniform(rng, std::abs(r1 - r2), r1 + r2);
    const double a1 = (d * d + r1 * r1 - r2 * r2) / (2 * d);
    const double twoCaps = cap(r1, r1 - a1) + cap(r2, r2 - (d - a1));
    EXPECT_NEAR(lensVolume(r1, r2, d), twoCaps, 1e-14) << r1 << " " << r2 << " " << d;
    EXPECT_NEAR(lensVolume(r2, r1, d), twoCaps, 1e-14);
  }
  // Apart, touching, contained, concentric, and continuity at both ends of the overlap range.
  EXPECT_EQ(lensVolume(0.3, 0.4, 0.71), 0.0);
  EXPECT_EQ(lensVolume(0.3, 0.4, 0.7), 0.0);
  EXPECT_NEAR(lensVolume(0.3, 0.5, 0.1), ballVolume(0.3), 1e-15);
  EXPECT_NEAR(lensVolume(0.5, 0.3, 0.0), ballVolume(0.3), 1e-15);
  EXPECT_NEAR(lensVolume(0.4, 0.4, 0.0), ballVolume(0.4), 1e-15);
  EXPECT_NEAR(lensVolume(0.3, 0.5, 0.2 + 1e-9), ballVolume(0.3), 1e-9);
  EXPECT_NEAR(lensVolume(0.3, 0.5, 0.8 - 1e-6), 0.0, 1e-11);
  // Equal spheres at tiny separation: no 0/0.
  EXPECT_NEAR(lensVolume(0.4, 0.4, 1e-300), ballVolume(0.4), 1e-15);
}
