/// Principal stresses and trajectories (principal.hpp).
#include "granular/principal.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "granular/error.hpp"

namespace granular {

PrincipalStresses principalStresses(const Mat3& stress) {
  PrincipalStresses p;
  if (!stress.allFinite()) {
    p.values.setConstant(std::numeric_limits<double>::quiet_NaN());
    return p;
  }
  // The iterative solver rather than computeDirect: the closed-form 3×3 path loses the
  // eigenvectors when two principal stresses nearly coincide (a near-hydrostatic bed, §3).
  const Mat3 symmetric = 0.5 * (stress + stress.transpose());
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(symmetric);
  p.values = solver.eigenvalues();  // ascending: σ1 (most negative) first
  p.vectors = solver.eigenvectors();
  if (p.vectors.determinant() < 0) p.vectors.col(2) = -p.vectors.col(2);
  return p;
}

Vec3 orientLike(const Vec3& v, const Vec3& reference) {
  return v.dot(reference) < 0 ? Vec3(-v) : v;
}

namespace {

/// The field at x as a unit vector oriented like `reference`; nullopt where undefined or zero.
std::optional<Vec3> orientedDirection(const DirectionField& field, const Vec3& x,
                                      const Vec3& reference) {
  const std::optional<Vec3> d = field(x);
  if (!d || !d->allFinite()) return std::nullopt;
  const double norm = d->norm();
  if (!(norm > 0)) return std::nullopt;
  return orientLike(*d / norm, reference);
}

/// Whether p is in the box along every bounded axis (boxMin < boxMax).
bool insideBox(const Vec3& p, const Vec3& boxMin, const Vec3& boxMax) {
  for (int k = 0; k < 3; ++k)
    if (boxMax[k] > boxMin[k] && (p[k] < boxMin[k] || p[k] > boxMax[k])) return false;
  return true;
}

}  // namespace

std::vector<Vec3> traceTrajectory(const DirectionField& direction, const Vec3& start, double step,
                                  int maxSteps, const Vec3& boxMin, const Vec3& boxMax,
                                  const Vec3& initialOrientation) {
  if (!(step > 0) || !std::isfinite(step)) throw ConfigError("traceTrajectory: step must be > 0");
  if (maxSteps < 0) throw ConfigError("traceTrajectory: maxSteps must be >= 0");
  std::vector<Vec3> line;
  if (!start.allFinite() || !insideBox(start, boxMin, boxMax)) return line;
  line.push_back(start);

  Vec3 x = start;
  Vec3 heading = initialOrientation;  // the direction the line last moved in
  for (int n = 0; n < maxSteps; ++n) {
    // Classical RK4 on dx/ds = d(x); every stage oriented like k1 so a sign flip of the
    // eigenvector field between stages cannot cancel the increment.
    const std::optional<Vec3> k1 = orientedDirection(direction, x, heading);
    if (!k1) break;
    Vec3 next = x + step * *k1;  // Euler, kept if a later stage is undefined
    const std::optional<Vec3> k2 = orientedDirection(direction, x + 0.5 * step * *k1, *k1);
    if (k2) {
      const std::optional<Vec3> k3 = orientedDirection(direction, x + 0.5 * step * *k2, *k1);
      if (k3) {
        const std::optional<Vec3> k4 = orientedDirection(direction, x + step * *k3, *k1);
        if (k4) next = x + step / 6.0 * (*k1 + 2.0 * *k2 + 2.0 * *k3 + *k4);
      }
    }

    if (!insideBox(next, boxMin, boxMax)) {
      // Cut the step where it first crosses a bounded face and end the line exactly on it.
      const Vec3 delta = next - x;
      double fraction = 1.0;
      int faceAxis = -1;
      double faceValue = 0;
      for (int k = 0; k < 3; ++k) {
        if (!(boxMax[k] > boxMin[k]) || delta[k] == 0) continue;
        const double face = delta[k] > 0 ? boxMax[k] : boxMin[k];
        const double f = (face - x[k]) / delta[k];
        if (f < fraction) {
          fraction = f;
          faceAxis = k;
          faceValue = face;
        }
      }
      Vec3 end = x + std::max(fraction, 0.0) * delta;
      // Round-off must not leave the end a hair outside: snap the crossed face, clamp the rest.
      for (int k = 0; k < 3; ++k)
        if (boxMax[k] > boxMin[k]) end[k] = std::clamp(end[k], boxMin[k], boxMax[k]);
      if (faceAxis >= 0) end[faceAxis] = faceValue;
      if (end != x) line.push_back(end);
      break;
    }
    heading = next - x;
    x = next;
    line.push_back(x);
  }
  return line;
}

}  // namespace granular
