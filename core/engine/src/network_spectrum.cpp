/// The network's extreme eigenvalues by Lanczos (granular/network_spectrum.hpp).
#include "granular/network_spectrum.hpp"

#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "contact_linearisation.hpp"
#include "granular/network_frequency.hpp"
#include "network_bound.hpp"
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
/// y = Σ G^T diag(k) G x, the matrix tests/test_network_frequency.cpp assembles. The contacts'
/// forces are computed on the threads, then each particle sums its own in the contacts' order:
/// the same bits on any thread count.
class NetworkOperator {
 public:
  NetworkOperator(const std::vector<LinearLink>& links, const Particles& p, bool rotations,
                  bool damping, int threads)
      : links_(links),
        rotations_(rotations),
        damping_(damping),
        threads_(threads),
        per_(rotations ? 6 : 3),
        pushes_(links.size()) {
    const std::size_t n = p.size();
    invSqrtMass_.resize(n);
    invSqrtInertia_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      invSqrtMass_[i] = 1.0 / std::sqrt(p.mass[i]);
      invSqrtInertia_[i] = 1.0 / std::sqrt(p.inertia(i));
    }
    // Each particle's contacts, in the contacts' order: 2 l for side i of contact l, 2 l + 1
    // for side j.
    start_.assign(n + 1, 0);
    for (const LinearLink& l : links) {
      ++start_[l.i + 1];
      if (!l.wall) ++start_[l.j + 1];
    }
    for (std::size_t i = 0; i < n; ++i) start_[i + 1] += start_[i];
    sides_.resize(start_[n]);
    std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
    for (std::size_t k = 0; k < links.size(); ++k) {
      sides_[next[links[k].i]++] = std::uint32_t(2 * k);
      if (!links[k].wall) sides_[next[links[k].j]++] = std::uint32_t(2 * k + 1);
    }
  }
  std::size_t size() const { return invSqrtMass_.size() * per_; }
  int threads() const { return threads_; }

  void apply(const std::vector<double>& x, std::vector<double>& y) const {
    const std::ptrdiff_t links = std::ptrdiff_t(links_.size());
#pragma omp parallel for num_threads(threads_) schedule(static)
    for (std::ptrdiff_t k = 0; k < links; ++k) pushes_[std::size_t(k)] = push(links_[k], x);
    const std::ptrdiff_t n = std::ptrdiff_t(invSqrtMass_.size());
#pragma omp parallel for num_threads(threads_) schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
      for (std::uint32_t s = start_[i]; s < start_[i + 1]; ++s) {
        const Push& push = pushes_[sides_[s] / 2];
        const bool sideJ = (sides_[s] & 1u) != 0;
        force += sideJ ? Vec3(-push.force) : push.force;
        torque += sideJ ? push.torqueJ : push.torqueI;
      }
      const std::size_t b = std::size_t(i) * per_;
      for (int c = 0; c < 3; ++c) y[b + c] = force[c] * invSqrtMass_[i];
      if (rotations_) {
        for (int c = 0; c < 3; ++c) y[b + 3 + c] = torque[c] * invSqrtInertia_[i];
      }
    }
  }

 private:
  /// One contact's forces on body i (−force on j) and torques, from x.
  struct Push {
    Vec3 force, torqueI, torqueJ;
  };
  Push push(const LinearLink& l, const std::vector<double>& x) const {
    const ContactModes& c = damping_ ? l.damping : l.stiffness;
    const Vec3& n = l.normal;
    const Vec3 du = translation(x, l.i) - (l.wall ? Vec3::Zero() : translation(x, l.j));
    Push out{c.normal * n.dot(du) * n, Vec3::Zero(), Vec3::Zero()};
    if (!rotations_) return out;
    const Vec3 pi = rotation(x, l.i);
    const Vec3 pj = l.wall ? Vec3::Zero() : rotation(x, l.j);
    const Vec3 ft = c.tangential * (du - n.dot(du) * n - n.cross(l.armI * pi + l.armJ * pj));
    const Vec3 dphi = pi - pj;
    const Vec3 fr = c.rolling * (dphi - n.dot(dphi) * n);
    out.force += ft;
    // The stretch's rotation part −a n × φ has the transpose a n × (·) on the force.
    const Vec3 turn = n.cross(ft);
    out.torqueI = l.armI * turn + fr;
    out.torqueJ = l.armJ * turn - fr;
    return out;
  }
  Vec3 translation(const std::vector<double>& x, std::uint32_t i) const {
    const std::size_t b = i * per_;
    return Vec3(x[b], x[b + 1], x[b + 2]) * invSqrtMass_[i];
  }
  Vec3 rotation(const std::vector<double>& x, std::uint32_t i) const {
    const std::size_t b = i * per_ + 3;
    return Vec3(x[b], x[b + 1], x[b + 2]) * invSqrtInertia_[i];
  }

  const std::vector<LinearLink>& links_;
  bool rotations_, damping_;
  int threads_;
  std::size_t per_;
  std::vector<double> invSqrtMass_, invSqrtInertia_;
  std::vector<std::uint32_t> start_, sides_;
  mutable std::vector<Push> pushes_;
};

/// Σ a_k b_k in blocks of a fixed length summed in order: the same bits on any thread count.
double dot(const std::vector<double>& a, const std::vector<double>& b, int threads) {
  constexpr std::size_t kBlock = 4096;
  const std::size_t blocks = (a.size() + kBlock - 1) / kBlock;
  std::vector<double> partial(blocks, 0.0);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(blocks); ++k) {
    double sum = 0.0;
    const std::size_t end = std::min(a.size(), (std::size_t(k) + 1) * kBlock);
    for (std::size_t i = std::size_t(k) * kBlock; i < end; ++i) sum += a[i] * b[i];
    partial[std::size_t(k)] = sum;
  }
  double sum = 0.0;
  for (double v : partial) sum += v;
  return sum;
}

/// The Lanczos basis is kept, for the Ritz vector a later estimate starts from, up to this
/// many doubles (64 MB); a larger network starts cold each time.
constexpr std::size_t kBasisDoubles = std::size_t(8) << 20;

struct RitzValue {
  double value = 0, residual = 0;  ///< θ and ‖A y − θ y‖ / θ
  int products = 0;
};

/// Lanczos for the largest eigenvalue of a symmetric positive semidefinite operator: the
/// tridiagonal's largest eigenvalue after each step, stopped when its Ritz pair's residual
/// β_k |s_k| is below `tolerance` of it. Without reorthogonalisation: lost orthogonality
/// repeats converged Ritz values but does not move the largest one. Starts from `warm` when it
/// has the operator's size, and leaves the Ritz vector there when the basis fits.
RitzValue largestEigenvalue(const NetworkOperator& op, int iterations, double tolerance,
                            std::vector<double>* warm) {
  const std::size_t n = op.size();
  const int threads = op.threads();
  RitzValue out;
  if (n == 0) return out;
  std::vector<double> q(n), previous(n, 0.0), w(n);
  if (warm && warm->size() == n) {
    q = *warm;
  } else {
    // A fixed start with a part along every coordinate (a linear congruential sequence).
    std::uint64_t state = 0x9E3779B97F4A7C15ull;
    for (double& v : q) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      v = 0.5 + double(state >> 11) * 0x1.0p-53;
    }
  }
  const double norm = std::sqrt(dot(q, q, threads));
  if (!(norm > 0.0)) return out;
  for (double& v : q) v /= norm;
  const bool keep = warm && n * std::size_t(iterations) <= kBasisDoubles;
  std::vector<std::vector<double>> basis;
  std::vector<double> alpha, beta;
  Eigen::VectorXd ritz;
  double b = 0.0;
  for (int k = 0; k < iterations; ++k) {
    if (keep) basis.push_back(q);
    op.apply(q, w);
    ++out.products;
    for (std::size_t i = 0; i < n; ++i) w[i] -= b * previous[i];
    const double a = dot(q, w, threads);
    for (std::size_t i = 0; i < n; ++i) w[i] -= a * q[i];
    const double next = std::sqrt(dot(w, w, threads));
    alpha.push_back(a);
    const Eigen::Index m = Eigen::Index(alpha.size());
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> t;
    Eigen::VectorXd diagonal = Eigen::Map<Eigen::VectorXd>(alpha.data(), m);
    Eigen::VectorXd off = m > 1 ? Eigen::VectorXd(Eigen::Map<Eigen::VectorXd>(beta.data(), m - 1))
                                : Eigen::VectorXd();
    t.computeFromTridiagonal(diagonal, off, Eigen::ComputeEigenvectors);
    out.value = t.eigenvalues()(m - 1);
    ritz = t.eigenvectors().col(m - 1);
    const double residual = next * std::abs(ritz(m - 1));
    out.residual = out.value > 0.0 ? residual / out.value : 0.0;
    if (!(out.value > 0.0) || out.residual < tolerance || next <= 1e-300) break;
    beta.push_back(next);
    b = next;
    previous.swap(q);
    for (std::size_t i = 0; i < n; ++i) q[i] = w[i] / next;
  }
  if (warm) {
    if (keep) {
      warm->assign(n, 0.0);
      for (std::size_t k = 0; k < basis.size(); ++k) {
        for (std::size_t i = 0; i < n; ++i) (*warm)[i] += ritz(Eigen::Index(k)) * basis[k][i];
      }
    } else {
      warm->clear();
    }
  }
  return out;
}

}  // namespace

NetworkSpectrum networkSpectrumEstimate(const Simulation& sim, double lookahead,
                                        NetworkSpectrumStart* start, int iterations,
                                        double tolerance) {
  const SimulationState& s = SimulationAccess::state(sim);
  // The outer limit: Gershgorin's bound, without the sweeps (any upper bound caps).
  const NetworkFrequency bound = networkFrequencyBound(s, 0, lookahead, nullptr);
  NetworkSpectrum out;
  out.contacts = bound.contacts;
  out.approaching = bound.approaching;
  if (s.split.domains || bound.contacts + bound.approaching == 0) {
    out.omegaMax = bound.omegaMax;
    out.dampingRate = bound.dampingRate;
    return out;
  }
  const Particles& p = s.particles;
  const Material& material = s.config.material;
  const ContactConstants constants(material, s.config.timeStep);
  const unsigned optional = optionalMask(material);
  std::vector<LinearLink> links;
  visitNetworkContacts(s, lookahead, [&](const NetworkContact& n) {
    const std::size_t i = n.i, j = n.j;
    const bool wall = j == i;
    const LinearContact linear = linearisedContact(s, n, constants, optional);
    LinearLink l;
    l.i = std::uint32_t(i);
    l.j = std::uint32_t(j);
    l.wall = wall;
    l.normal = n.normal;
    l.armI = p.radius[i] - 0.5 * linear.overlap;
    l.armJ = wall ? 0.0 : p.radius[j] - 0.5 * linear.overlap;
    l.stiffness = linear.stiffness;
    l.damping = linear.damping;
    links.push_back(l);
  });
  const int threads = passThreads(s) > 0 ? passThreads(s) : omp_get_max_threads();
  const RitzValue k = largestEigenvalue(NetworkOperator(links, p, s.frictional, false, threads),
                                        iterations, tolerance, start ? &start->stiffness : nullptr);
  const RitzValue c = largestEigenvalue(NetworkOperator(links, p, s.frictional, true, threads),
                                        iterations, tolerance, start ? &start->damping : nullptr);
  out.omegaMax = std::min(std::sqrt(std::max(k.value, 0.0)), bound.omegaMax);
  out.dampingRate = std::min(std::max(c.value, 0.0), bound.dampingRate);
  out.omegaResidual = k.residual;
  out.dampingResidual = c.residual;
  out.products = k.products + c.products;
  return out;
}

}  // namespace granular
