#pragma once
/// Cubic spline interpolation on regular grids with not-a-knot end conditions, in 1-D and as a
/// tensor product in 3-D. Not-a-knot (the third derivative is continuous at the second and the
/// second-to-last node; de Boor, A Practical Guide to Splines, ch. IV) makes the spline
/// reproduce every cubic exactly, with no end derivative to guess. Outside the nodes each spline
/// continues the cubic of its end interval: the paper extrapolates the local stress fields from
/// the cell centres to the walls this way (Figs. 9 and 10).
#include <array>
#include <span>
#include <vector>

#include "granular/vec3.hpp"

namespace granular {

/// Second derivatives M_i of the not-a-knot cubic spline through n values y_i at uniform spacing
/// h [units of y / h²], written to `second` (same size as `values`). Uniform spacing decouples the
/// end equations: not-a-knot makes [x0, x2] one cubic, so M1 = (y0 − 2y1 + y2)/h² exactly, and
/// likewise M_{n−2}; the rows M_{i−1} + 4M_i + M_{i+1} = 6(y_{i−1} − 2y_i + y_{i+1})/h² for
/// 2 ≤ i ≤ n − 3 are solved by the Thomas algorithm (diagonally dominant: stable), and
/// M0 = 2M1 − M2, M_{n−1} = 2M_{n−2} − M_{n−3}. Fewer nodes give the interpolating polynomial
/// of lower degree: n = 3 the parabola (all M_i equal), n = 2 the line, n = 1 the constant
/// (M = 0). Throws ConfigError on a size mismatch or a non-positive spacing.
void notAKnotSecondDerivatives(std::span<const double> values, double spacing,
                               std::span<double> second);

/// Weights of one evaluation of a uniform cubic spline in the (values, second derivatives) form
///   S(x) = a·y_i + b·y_{i+1} + c·M_i + d·M_{i+1},  t = (x − x_i)/h,
///   a = 1 − t, b = t, c = h²((1 − t)³ − (1 − t))/6, d = h²(t³ − t)/6,
/// with the interval i clamped to [0, n − 2], so that t outside [0, 1] extrapolates the end
/// interval's cubic. For n = 1, i = 0 and only a = 1 is non-zero (i + 1 is then also 0).
struct SplineWeights {
  int lower = 0;                      ///< index i of the interval's lower node
  int upper = 0;                      ///< index of its upper node, i + 1 (i for a single node)
  double a = 0, b = 0, c = 0, d = 0;  ///< weights of y_i, y_{i+1} [-], M_i, M_{i+1} [h²]
};
SplineWeights splineWeights(double x, double origin, double spacing, int count);

/// A not-a-knot cubic spline through values at x_i = origin + i·spacing, i = 0 … n − 1.
class CubicSpline {
 public:
  /// origin [m], spacing [m] > 0, at least one value. Throws ConfigError otherwise.
  CubicSpline(double origin, double spacing, std::vector<double> values);

  /// The spline at x, anywhere: outside [x_0, x_{n−1}] the end interval's cubic continues.
  double operator()(double x) const;

  double origin() const { return origin_; }                                 ///< x_0 [m]
  double spacing() const { return spacing_; }                               ///< h [m]
  int count() const { return static_cast<int>(values_.size()); }            ///< n [-]
  const std::vector<double>& secondDerivatives() const { return second_; }  ///< M_i [y/m²]

 private:
  double origin_;
  double spacing_;
  std::vector<double> values_;
  std::vector<double> second_;
};

/// The tensor product of three not-a-knot cubic splines on the regular grid
/// x_ijk = origin + (i, j, k)∘spacing, with values listed x fastest, then y, then z.
///
/// Each 1-D spline is linear in its data, S(x) = a y_i + b y_{i+1} + c (Ly)_i + d (Ly)_{i+1}
/// with L the map to second derivatives; applying that form along the three axes in turn gives
/// S(x, y, z) = Σ over the 8 cell corners and the 8 choices (value or L) per axis of the
/// product of weights times f, L_x f, L_y f, L_z f, L_xL_y f, …, L_xL_yL_z f at the corner
/// (the L along different axes commute). These 8 arrays are precomputed (7 sweeps of 1-D
/// solves), so an evaluation is 64 products: about 1e7 evaluations per second. Axes with fewer
/// than 4 nodes reduce to the lower-degree interpolant along that axis (see
/// notAKnotSecondDerivatives).
class TricubicSpline {
 public:
  /// origin [m], spacing [m] (each > 0), counts ≥ 1 per axis, values.size() = product of
  /// counts. Throws ConfigError otherwise.
  TricubicSpline(const Vec3& origin, const Vec3& spacing, std::array<int, 3> counts,
                 std::vector<double> values);

  /// The interpolant at p, anywhere: outside the node range each axis continues the cubic of
  /// its end interval [units of the values].
  double operator()(const Vec3& p) const;

  const Vec3& origin() const { return origin_; }                ///< node (0, 0, 0) [m]
  const Vec3& spacing() const { return spacing_; }              ///< node spacing per axis [m]
  const std::array<int, 3>& counts() const { return counts_; }  ///< nodes per axis [-]

 private:
  Vec3 origin_;
  Vec3 spacing_;
  std::array<int, 3> counts_;
  /// Per node: f and its images under the second-derivative maps, indexed by a mask whose bit
  /// k says "L applied along axis k" (0: f, 1: L_x f, 2: L_y f, 3: L_xL_y f, …).
  std::vector<std::array<double, 8>> nodes_;
};

}  // namespace granular
