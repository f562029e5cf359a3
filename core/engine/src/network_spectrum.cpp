/// The network's extreme eigenvalues by Lanczos (granular/network_spectrum.hpp).
#include "granular/network_spectrum.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "contact_linearisation.hpp"
#include "force_pass.hpp"
#include "granular/network_frequency.hpp"
#include "simulation_state.hpp"

namespace granular {

namespace {

/// One touching contact linearised: its bodies (j = i for a wall), its normal, each body's
/// lever arm R − h/2, and its modes' springs and dashpots.
struct LinearLink {
  std::uint32_t i = 0, j = 0;
  bool wall = false;
  Vec3 normal;
  double armI = 0, armJ = 0;
  ContactModes stiffness, damping;
};

/// y = A x (or D x) for the mass-weighted coordinates x: per particle its translation √m u
/// and, with rotations, its rotation √I φ. Per contact the stretches of its modes (normal
/// n·(u_i − u_j); tangential at the contact point, the tangent part of u_i − u_j minus
/// n × (a_i φ_i + a_j φ_j); rolling, the tangent part of φ_i − φ_j) times the mode's
/// coefficient are the contact's forces, and their work-conjugates on each body add to y:
/// y = Σ G^T diag(k) G x, the matrix tests/test_network_frequency.cpp assembles.
class NetworkOperator {
 public:
  NetworkOperator(const std::vector<LinearLink>& links, const Particles& p, bool rotations,
                  bool damping)
      : links_(links), rotations_(rotations), damping_(damping), per_(rotations ? 6 : 3) {
    invSqrtMass_.resize(p.size());
    invSqrtInertia_.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      invSqrtMass_[i] = 1.0 / std::sqrt(p.mass[i]);
      invSqrtInertia_[i] = 1.0 / std::sqrt(p.inertia(i));
    }
  }
  std::size_t size() const { return invSqrtMass_.size() * per_; }

  void apply(const std::vector<double>& x, std::vector<double>& y) const {
    std::fill(y.begin(), y.end(), 0.0);
    for (const LinearLink& l : links_) {
      const ContactModes& c = damping_ ? l.damping : l.stiffness;
      const Vec3& n = l.normal;
      const Vec3 ui = translation(x, l.i);
      const Vec3 uj = l.wall ? Vec3::Zero() : translation(x, l.j);
      const Vec3 du = ui - uj;
      const double fn = c.normal * n.dot(du);
      Vec3 forceI = fn * n, torqueI = Vec3::Zero(), torqueJ = Vec3::Zero();
      if (rotations_) {
        const Vec3 pi = rotation(x, l.i);
        const Vec3 pj = l.wall ? Vec3::Zero() : rotation(x, l.j);
        const Vec3 slide = du - n.dot(du) * n - n.cross(l.armI * pi + l.armJ * pj);
        const Vec3 ft = c.tangential * slide;
        const Vec3 dphi = pi - pj;
        const Vec3 fr = c.rolling * (dphi - n.dot(dphi) * n);
        forceI += ft;
        // The stretch's rotation part −a n × φ has the transpose a n × (·) on the force.
        const Vec3 turn = n.cross(ft);
        torqueI = l.armI * turn + fr;
        torqueJ = l.armJ * turn - fr;
      }
      add(y, l.i, forceI, torqueI);
      if (!l.wall) add(y, l.j, -forceI, torqueJ);
    }
  }

 private:
  Vec3 translation(const std::vector<double>& x, std::uint32_t i) const {
    const std::size_t b = i * per_;
    return Vec3(x[b], x[b + 1], x[b + 2]) * invSqrtMass_[i];
  }
  Vec3 rotation(const std::vector<double>& x, std::uint32_t i) const {
    const std::size_t b = i * per_ + 3;
    return Vec3(x[b], x[b + 1], x[b + 2]) * invSqrtInertia_[i];
  }
  void add(std::vector<double>& y, std::uint32_t i, const Vec3& force, const Vec3& torque) const {
    const std::size_t b = i * per_;
    for (int k = 0; k < 3; ++k) y[b + k] += force[k] * invSqrtMass_[i];
    if (!rotations_) return;
    for (int k = 0; k < 3; ++k) y[b + 3 + k] += torque[k] * invSqrtInertia_[i];
  }

  const std::vector<LinearLink>& links_;
  bool rotations_, damping_;
  std::size_t per_;
  std::vector<double> invSqrtMass_, invSqrtInertia_;
};

struct RitzValue {
  double value = 0, residual = 0;  ///< θ and ‖A y − θ y‖ / θ
  int products = 0;
};

/// Lanczos for the largest eigenvalue of a symmetric positive semidefinite operator: the
/// tridiagonal's largest eigenvalue after each step, stopped when its Ritz pair's residual
/// β_k |s_k| is below `tolerance` of it. Without reorthogonalisation: lost orthogonality
/// repeats converged Ritz values but does not move the largest one.
RitzValue largestEigenvalue(const NetworkOperator& op, int iterations, double tolerance) {
  const std::size_t n = op.size();
  RitzValue out;
  if (n == 0) return out;
  // A fixed start with a part along every coordinate (a linear congruential sequence): the same
  // bits on every run.
  std::vector<double> q(n), previous(n, 0.0), w(n);
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  double norm = 0.0;
  for (double& v : q) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    v = 0.5 + double(state >> 11) * 0x1.0p-53;
    norm += v * v;
  }
  for (double& v : q) v /= std::sqrt(norm);
  std::vector<double> alpha, beta;
  double b = 0.0;
  for (int k = 0; k < iterations; ++k) {
    op.apply(q, w);
    ++out.products;
    for (std::size_t i = 0; i < n; ++i) w[i] -= b * previous[i];
    double a = 0.0;
    for (std::size_t i = 0; i < n; ++i) a += q[i] * w[i];
    for (std::size_t i = 0; i < n; ++i) w[i] -= a * q[i];
    double next = 0.0;
    for (double v : w) next += v * v;
    next = std::sqrt(next);
    alpha.push_back(a);
    const Eigen::Index m = Eigen::Index(alpha.size());
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> t;
    Eigen::VectorXd diagonal = Eigen::Map<Eigen::VectorXd>(alpha.data(), m);
    Eigen::VectorXd off = m > 1 ? Eigen::VectorXd(Eigen::Map<Eigen::VectorXd>(beta.data(), m - 1))
                                : Eigen::VectorXd();
    t.computeFromTridiagonal(diagonal, off, Eigen::ComputeEigenvectors);
    out.value = t.eigenvalues()(m - 1);
    const double residual = next * std::abs(t.eigenvectors()(m - 1, m - 1));
    out.residual = out.value > 0.0 ? residual / out.value : 0.0;
    if (!(out.value > 0.0) || out.residual < tolerance || next <= 1e-300) break;
    beta.push_back(next);
    b = next;
    previous.swap(q);
    for (std::size_t i = 0; i < n; ++i) q[i] = w[i] / next;
  }
  return out;
}

}  // namespace

NetworkSpectrum networkSpectrumEstimate(const Simulation& sim, int iterations, double tolerance) {
  const SimulationState& s = SimulationAccess::state(sim);
  const NetworkFrequency bound = networkFrequencyBound(sim);
  NetworkSpectrum out;
  out.contacts = bound.contacts;
  if (s.split.domains || bound.contacts == 0) {
    out.omegaMax = bound.omegaMax;
    out.dampingRate = bound.dampingRate;
    return out;
  }
  const Particles& p = s.particles;
  const Material& material = s.config.material;
  const ContactConstants constants(material, s.config.timeStep);
  const unsigned optional = optionalMask(material);
  std::vector<LinearLink> links;
  visitContacts(
      s,
      [&](const ContactView& c) {
        if (c.overlap < 0.0) return;  // a pull across a gap: no spring (as the bound)
        const std::size_t i = c.particle;
        const bool wall = c.isWall();
        const std::size_t j = wall ? i : c.otherParticle();
        if (!wall && j < i) return;
        LinearContact linear;
        linear.radius =
            wall ? p.radius[i] : p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
        linear.mass = wall ? p.mass[i] : p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
        linear.overlap = c.overlap;
        const double ii = 1.4 * p.mass[i] * p.radius[i] * p.radius[i];  // I + m R²
        const double ij = wall ? 0.0 : 1.4 * p.mass[j] * p.radius[j] * p.radius[j];
        linear.rollingInertia = wall ? ii : 1.0 / (1.0 / ii + 1.0 / ij);
        lineariseContact(constants, s.frictional, optional, linear);
        LinearLink l;
        l.i = std::uint32_t(i);
        l.j = std::uint32_t(j);
        l.wall = wall;
        l.normal = c.normal;
        l.armI = p.radius[i] - 0.5 * c.overlap;
        l.armJ = wall ? 0.0 : p.radius[j] - 0.5 * c.overlap;
        l.stiffness = linear.stiffness;
        l.damping = linear.damping;
        links.push_back(l);
      },
      nullptr);
  const RitzValue k =
      largestEigenvalue(NetworkOperator(links, p, s.frictional, false), iterations, tolerance);
  const RitzValue c =
      largestEigenvalue(NetworkOperator(links, p, s.frictional, true), iterations, tolerance);
  out.omegaMax = std::min(std::sqrt(std::max(k.value, 0.0)), bound.omegaMax);
  out.dampingRate = std::min(std::max(c.value, 0.0), bound.dampingRate);
  out.omegaResidual = k.residual;
  out.dampingResidual = c.residual;
  out.products = k.products + c.products;
  return out;
}

}  // namespace granular
