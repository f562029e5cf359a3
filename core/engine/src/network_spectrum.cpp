/// The network's extreme eigenvalues by Lanczos (granular/network_spectrum.hpp).
#include "granular/network_spectrum.hpp"

#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "contact_linearisation.hpp"
#include "granular/network_frequency.hpp"
#include "message_bytes.hpp"
#include "network_bound.hpp"
#include "simulation_state.hpp"

namespace granular {

namespace {

/// One contact linearised, in the estimate's own numbering: its bodies (j = i for a wall), its
/// normal from i towards j, each body's lever arm R − h/2, and its modes' springs and dashpots.
struct LinearLink {
  std::uint32_t i = 0, j = 0;
  bool wall = false;
  Vec3 normal;
  double armI = 0, armJ = 0;
  ContactModes stiffness, damping;
};

/// A contact as every process of a run sees it alike: its bodies by global id (the smaller
/// first: the normal points from it; a wall's j is its particle's id), then its numbers. All
/// fields are 8 bytes wide, so the record has no padding and compares as bytes.
struct CanonicalLink {
  std::uint64_t i = 0, j = 0, wall = 0;
  double normal[3] = {0, 0, 0};
  double armI = 0, armJ = 0;
  double stiffness[3] = {0, 0, 0}, damping[3] = {0, 0, 0};
};
static_assert(sizeof(CanonicalLink) == 14 * 8, "CanonicalLink must have no padding");

/// A body of the network by global id: its mass [kg] and moment of inertia [kg m²].
struct CanonicalBody {
  std::uint64_t id = 0;
  double mass = 0, inertia = 0;
};
static_assert(sizeof(CanonicalBody) == 3 * 8, "CanonicalBody must have no padding");

bool before(const CanonicalLink& a, const CanonicalLink& b) {
  if (a.i != b.i) return a.i < b.i;
  if (a.j != b.j) return a.j < b.j;
  return std::memcmp(&a, &b, sizeof a) < 0;
}

/// The network as every process sees it alike: the links in the order of their bodies' global
/// ids (ties by their bytes: two links with the same bytes sum alike in either order), the
/// bodies ascending by id. A contact is the same bits from either of its sides (negations and
/// symmetric products), so this is the same on one process, any split of the run, and any
/// spatial order of its particles: an estimate on it is too.
struct CanonicalNetwork {
  std::vector<CanonicalLink> links;
  std::vector<CanonicalBody> bodies;
};

/// The network's contacts linearised as the bound counts them, in canonical form. In a run
/// split by space each process keeps the contacts whose first body (by global id) it owns and
/// every process receives all of them.
CanonicalNetwork canonicalNetwork(const SimulationState& s, double lookahead) {
  const Particles& p = s.particles;
  const ContactConstants constants(s.config.material, s.config.timeStep);
  const unsigned optional = optionalMask(s.config.material);
  const bool split = s.split.domains != nullptr;
  auto id = [&](std::size_t i) -> std::uint64_t { return split ? s.split.globalId[i] : i; };
  auto mine = [&](std::size_t i) { return !split || s.owned.empty() || s.owned[i] != 0; };
  CanonicalNetwork net;
  visitNetworkContacts(s, lookahead, [&](const NetworkContact& n) {
    const bool wall = n.j == n.i;
    const bool flip = !wall && id(n.j) < id(n.i);
    const std::size_t first = flip ? n.j : n.i, second = flip ? n.i : n.j;
    if (!mine(first)) return;
    const LinearContact linear = linearisedContact(s, n, constants, optional);
    CanonicalLink l;
    l.i = id(first);
    l.j = id(second);
    l.wall = wall ? 1 : 0;
    const Vec3 normal = flip ? Vec3(-n.normal) : n.normal;
    for (int c = 0; c < 3; ++c) l.normal[c] = normal[c];
    l.armI = p.radius[first] - 0.5 * linear.overlap;
    l.armJ = wall ? 0.0 : p.radius[second] - 0.5 * linear.overlap;
    const ContactModes& k = linear.stiffness;
    const ContactModes& d = linear.damping;
    l.stiffness[0] = k.normal, l.stiffness[1] = k.tangential, l.stiffness[2] = k.rolling;
    l.damping[0] = d.normal, l.damping[1] = d.tangential, l.damping[2] = d.rolling;
    net.links.push_back(l);
    net.bodies.push_back({l.i, p.mass[first], p.inertia(first)});
    if (!wall) net.bodies.push_back({l.j, p.mass[second], p.inertia(second)});
  });
  if (split && s.ranks) {
    std::vector<std::byte> mineBytes;
    putArray(mineBytes, net.links);
    putArray(mineBytes, net.bodies);
    const std::vector<std::vector<std::byte>> outgoing(std::size_t(s.ranks->size()), mineBytes);
    const std::vector<std::vector<std::byte>> all = s.ranks->exchange(outgoing);
    net = CanonicalNetwork{};
    for (const std::vector<std::byte>& bytes : all) {
      std::size_t at = 0;
      getArray(bytes, at, net.links);
      getArray(bytes, at, net.bodies);
    }
  }
  // By first body in one counting pass (ids are below the run's particle count), then each
  // body's few links by the rest; the bodies by id the same way.
  std::uint64_t top = 0;
  for (const CanonicalBody& b : net.bodies) top = std::max(top, b.id + 1);
  std::vector<std::size_t> first(top + 1, 0);
  for (const CanonicalLink& l : net.links) ++first[l.i + 1];
  for (std::size_t b = 0; b < top; ++b) first[b + 1] += first[b];
  std::vector<CanonicalLink> sorted(net.links.size());
  std::vector<std::size_t> next(first.begin(), first.end() - 1);
  for (const CanonicalLink& l : net.links) sorted[next[l.i]++] = l;
  for (std::size_t b = 0; b < top; ++b) {
    std::sort(sorted.begin() + std::ptrdiff_t(first[b]),
              sorted.begin() + std::ptrdiff_t(first[b + 1]), before);
  }
  net.links.swap(sorted);
  std::vector<CanonicalBody> byId(top);
  std::vector<std::uint8_t> present(top, 0);
  for (const CanonicalBody& b : net.bodies) byId[b.id] = b, present[b.id] = 1;
  net.bodies.clear();
  for (std::size_t b = 0; b < top; ++b) {
    if (present[b]) net.bodies.push_back(byId[b]);
  }
  return net;
}

/// The canonical network's links in the numbering of its bodies (their places in `bodies`).
std::vector<LinearLink> numberedLinks(const CanonicalNetwork& net) {
  std::vector<LinearLink> links;
  links.reserve(net.links.size());
  const std::uint64_t top = net.bodies.empty() ? 0 : net.bodies.back().id + 1;
  std::vector<std::uint32_t> placeOf(top, 0);
  for (std::size_t b = 0; b < net.bodies.size(); ++b) placeOf[net.bodies[b].id] = std::uint32_t(b);
  auto place = [&](std::uint64_t id) { return placeOf[id]; };
  for (const CanonicalLink& c : net.links) {
    LinearLink l;
    l.i = place(c.i);
    l.wall = c.wall != 0;
    l.j = l.wall ? l.i : place(c.j);
    l.normal = Vec3(c.normal[0], c.normal[1], c.normal[2]);
    l.armI = c.armI;
    l.armJ = c.armJ;
    l.stiffness = {c.stiffness[0], c.stiffness[1], c.stiffness[2]};
    l.damping = {c.damping[0], c.damping[1], c.damping[2]};
    links.push_back(l);
  }
  return links;
}

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
  NetworkOperator(const std::vector<LinearLink>& links, const std::vector<CanonicalBody>& bodies,
                  bool rotations, bool damping, int threads)
      : links_(links),
        rotations_(rotations),
        damping_(damping),
        threads_(threads),
        per_(rotations ? 6 : 3),
        pushes_(links.size()) {
    const std::size_t n = bodies.size();
    invSqrtMass_.resize(n);
    invSqrtInertia_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      invSqrtMass_[i] = 1.0 / std::sqrt(bodies[i].mass);
      invSqrtInertia_[i] = 1.0 / std::sqrt(bodies[i].inertia);
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
  return networkSpectrumEstimate(s, lookahead, networkFrequencyBound(s, 0, lookahead, nullptr),
                                 start, iterations, tolerance);
}

NetworkSpectrum networkSpectrumEstimate(const SimulationState& s, double lookahead,
                                        const NetworkFrequency& bound, NetworkSpectrumStart* start,
                                        int iterations, double tolerance) {
  NetworkSpectrum out;
  out.contacts = bound.contacts;
  out.approaching = bound.approaching;
  if (bound.contacts + bound.approaching == 0) {
    out.omegaMax = bound.omegaMax;
    out.dampingRate = bound.dampingRate;
    return out;
  }
  const CanonicalNetwork net = canonicalNetwork(s, lookahead);
  const std::vector<LinearLink> links = numberedLinks(net);
  // A start kept for other bodies (the network changed its members) is not this one's.
  std::vector<std::uint64_t> ids(net.bodies.size());
  for (std::size_t b = 0; b < ids.size(); ++b) ids[b] = net.bodies[b].id;
  if (start && start->bodies != ids) {
    start->stiffness.clear();
    start->damping.clear();
  }
  const int threads = passThreads(s) > 0 ? passThreads(s) : omp_get_max_threads();
  const RitzValue k =
      largestEigenvalue(NetworkOperator(links, net.bodies, s.frictional, false, threads),
                        iterations, tolerance, start ? &start->stiffness : nullptr);
  const RitzValue c =
      largestEigenvalue(NetworkOperator(links, net.bodies, s.frictional, true, threads), iterations,
                        tolerance, start ? &start->damping : nullptr);
  if (start) start->bodies = std::move(ids);
  out.omegaMax = std::min(std::sqrt(std::max(k.value, 0.0)), bound.omegaMax);
  out.dampingRate = std::min(std::max(c.value, 0.0), bound.dampingRate);
  out.omegaResidual = k.residual;
  out.dampingResidual = c.residual;
  out.products = k.products + c.products;
  return out;
}

}  // namespace granular
