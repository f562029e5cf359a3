#pragma once
/// Principal stresses and their trajectories (the paper's Fig. 10: σ1 trajectories on the
/// midsection). Compression is negative, as in the paper, so σ1 — the most compressive principal
/// stress — is the smallest eigenvalue.
#include <functional>
#include <optional>
#include <vector>

#include "granular/vec3.hpp"

namespace granular {

/// Eigen-decomposition of a stress tensor's symmetric part.
struct PrincipalStresses {
  /// σ1 ≤ σ2 ≤ σ3 [Pa]: σ1 the most compressive (most negative).
  Vec3 values = Vec3::Zero();
  /// Column k is the unit eigenvector of values[k] [-]; the columns form a right-handed
  /// orthonormal basis (the sign of an eigenvector carries no meaning; see orientLike).
  Mat3 vectors = Mat3::Identity();
};

/// Principal stresses of ½(σ + σᵀ) by Eigen's SelfAdjointEigenSolver (Jacobi-like QR
/// iteration, accurate also for close eigenvalues), ascending so that σ1 is the most
/// compressive. Non-finite input gives NaN values.
PrincipalStresses principalStresses(const Mat3& stress);

/// v or −v, whichever has a non-negative dot product with `reference` [same units as v]: an
/// eigenvector field has no sign, so a trajectory keeps the one continuous with its last step.
Vec3 orientLike(const Vec3& v, const Vec3& reference);

/// A unit direction field: the direction at a point, or nullopt where it is undefined (outside
/// the data, or where the principal stresses are degenerate). Its sign may be arbitrary.
using DirectionField = std::function<std::optional<Vec3>(const Vec3&)>;

/// Integrates the trajectory dx/ds = d(x) of a sign-free direction field by the classical
/// fourth-order Runge–Kutta method with arc-length step `step` [m], from `start`, its first
/// direction oriented like `initialOrientation` (a zero vector keeps the field's own sign).
/// Each stage's direction is oriented like the step's first one, and each step's first like the
/// previous step's displacement, so arbitrary sign flips of the field do not fold the line
/// back. The field's vectors are normalised (a zero vector counts as undefined). The points
/// start at `start` and stop:
/// - at the box [boxMin, boxMax]: the step that would leave it is cut where it crosses the
///   boundary, and that boundary point (exactly on the face) ends the line. Axes with
///   boxMin[k] == boxMax[k] are not bounded: give the plane of a 2-D trajectory that way;
/// - where the direction at the current point is undefined. A later stage of a step that falls
///   where the field is undefined makes that step a first-order (Euler) one with the direction
///   at the current point, so that a field undefined just outside the box still lets the line
///   reach the boundary;
/// - after `maxSteps` steps.
/// A start outside the box gives an empty line. Throws ConfigError on a non-positive step or a
/// negative maxSteps. Points in [m].
std::vector<Vec3> traceTrajectory(const DirectionField& direction, const Vec3& start, double step,
                                  int maxSteps, const Vec3& boxMin, const Vec3& boxMax,
                                  const Vec3& initialOrientation);

}  // namespace granular
