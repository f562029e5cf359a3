#pragma once
/// The exact spectrum of a bed's linearised contact network, assembled independently of the
/// engine (dense, Eigen): its mass-weighted stiffness and damping matrices, their largest
/// eigenvalue, and the spectral radius of one velocity-Verlet or Gear5 step on them. The truth
/// the step control's bound and estimate are tested against. The dense work is in
/// network_matrices.cpp, which the sanitizer builds compile optimised and uninstrumented: it is
/// the tests' own reference, not code under test, and instrumented it took minutes of CI.
#include <Eigen/Dense>

#include "granular/simulation.hpp"

namespace granular::testing {

/// n × (the vector): the cross-product matrix [n]×.
inline Eigen::Matrix3d crossMatrix(const Vec3& n) {
  Eigen::Matrix3d c;
  c << 0, -n.z(), n.y(), n.z(), 0, -n.x(), -n.y(), n.x(), 0;
  return c;
}

/// The largest eigenvalue of a symmetric matrix.
double largestEigenvalue(const Eigen::MatrixXd& a);

/// The linearised network's mass-weighted stiffness matrix A = M^(-1/2) K M^(-1/2) and, with
/// `damping`, its dashpots' D = M^(-1/2) C M^(-1/2): per contact the stretches (normal;
/// tangential at the contact point, u_i − u_j + a_i φ_i × n + a_j φ_j × n projected on the
/// tangent plane; rolling, φ_i − φ_j projected), each weighted by √k (or √c), as a matrix G of
/// the mass-weighted displacements; A = Σ G^T G.
Eigen::MatrixXd networkMatrix(const Simulation& sim, bool damping);

/// The spectral radius of one velocity-Verlet step on the linearised network
/// y'' = −A y − D y', the dashpots at v + `dashpotLead` Δt a (1: the predicted velocity, the
/// stricter scheme; ½: the half-step velocity, as the engine has it, physics.md §2.6): the
/// state (y, v, a) maps linearly, y' = y + Δt v + Δt²/2 a, a' = −A y' − D (v + lead Δt a),
/// v' = v + Δt/2 (a + a').
double verletStepRadius(const Eigen::MatrixXd& a, const Eigen::MatrixXd& d, double dt,
                        double dashpotLead = 1.0);

/// The spectral radius of one Gear5 step on the linearised network y'' = −A y − D y', as the
/// engine takes it: each unit vector of the state (y and its derivatives to the fifth) stepped
/// through `Gear5::predict` and `Gear5::correct` themselves, the acceleration evaluated at the
/// predicted y and y' (the dashpots at the predicted velocity). The k-th derivative is taken
/// × Δt^k, a similarity that leaves the spectrum as it is and the map's entries of one scale
/// (unscaled they span Δt^±5, beyond what the eigensolver resolves).
double gearStepRadius(const Eigen::MatrixXd& a, const Eigen::MatrixXd& d, double dt);

/// ω_max [rad/s] of the linearised network.
double exactOmegaMax(const Simulation& sim);

}  // namespace granular::testing
