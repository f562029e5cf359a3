/// The contact network's frequency bound (granular/network_frequency.hpp).
#include "granular/network_frequency.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "contact_linearisation.hpp"
#include "domain_split.hpp"
#include "network_bound.hpp"
#include "network_contacts.hpp"
#include "network_motion.hpp"
#include "simulation_state.hpp"

namespace granular {

ContactStiffness contactStiffness(const Material& material, double reducedRadius, double overlap) {
  LinearContact c;
  c.radius = reducedRadius;
  c.overlap = std::max(overlap, 0.0);
  lineariseContact(ContactConstants(material, 0.0), material.hasFriction(), optionalMask(material),
                   c);
  return c.stiffness;
}

double contactGain(const ContactStiffness& k, const ContactBody& body, bool rotations) {
  // G G^T for the outputs (normal, tangential in the tangent plane, rolling): the normal row
  // sees only the translation, k_n/m; the tangential rows see the translation (1/m) and the
  // rotation through the lever arm (a²/I), on the same two tangent directions; the rolling rows
  // see the rotation (1/I) on those directions too. In the contact's frame (n, t1, t2) the
  // tangential and rolling rows of one tangent direction couple only with each other (the
  // rotation about t2 moves the contact point along t1), so G G^T is diag(k_n/m) and, per
  // tangent direction, the 2×2 [[k_t (1/m + a²/I), √(k_t k_r) a/I], [·, k_r/I]].
  const double normal = k.normal / body.mass;
  if (!rotations) return std::sqrt(normal);
  const double kt = k.tangential, kr = k.rolling, m = body.mass, inertia = body.inertia;
  // The 2×2 [[a, b], [b, c]]'s larger eigenvalue in closed form (at every check, per contact);
  // without rolling resistance it is a.
  const double a = kt * (1.0 / m + body.arm * body.arm / inertia);
  if (kr == 0.0) return std::sqrt(std::max(normal, a));
  const double b = std::sqrt(kt * kr) * body.arm / inertia, c = kr / inertia;
  const double half = 0.5 * (a - c);
  const double tangent = 0.5 * (a + c) + std::sqrt(half * half + b * b);
  return std::sqrt(std::max(normal, tangent));
}

namespace {

/// The network's two gain matrices, of its springs (stiffness) and of its dashpots (damping),
/// on one set of links. Each is a matrix B with B_ii = its diagonal[i] and, per link,
/// B_ij = B_ji = gi gj: it dominates the block norms of the mass-weighted contact matrix
/// entrywise, so that matrix's largest eigenvalue is at most ρ(B) ≤ max_i (B x)_i / x_i for any
/// positive x (Collatz–Wielandt). x = 1 is Gershgorin's bound; each sweep x ← B x tightens it.
struct GainMatrices {
  static constexpr std::size_t kStiffness = 0, kDamping = 1;
  struct Link {
    std::uint32_t i, j;
    std::array<double, 2> weight;  ///< gi gj of the stiffness and of the damping
  };
  std::array<std::vector<double>, 2> diagonal;
  std::vector<Link> links;

  explicit GainMatrices(std::size_t n) : diagonal{std::vector<double>(n), std::vector<double>(n)} {}
  /// A wall contact of body i: its gains on the stiffness and on the damping.
  void wall(std::size_t i, double k, double c) {
    diagonal[kStiffness][i] += k * k;
    diagonal[kDamping][i] += c * c;
  }
  /// A pair's contact: each body's gains on the stiffness (ki, kj) and on the damping (ci, cj).
  void pair(std::size_t i, std::size_t j, double ki, double kj, double ci, double cj) {
    diagonal[kStiffness][i] += ki * ki;
    diagonal[kStiffness][j] += kj * kj;
    diagonal[kDamping][i] += ci * ci;
    diagonal[kDamping][j] += cj * cj;
    links.push_back(
        {static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), {ki * kj, ci * cj}});
  }
};

/// The links of the gain matrices by row: each row's off-diagonal entries in the links' order,
/// so that a row's product B x, summed along it, adds the same terms in the same order as a
/// walk over the links that adds each to both its rows: the same bits, each row alone (on any
/// thread).
struct GainRows {
  struct Entry {
    std::uint32_t other;
    std::array<double, 2> weight;
  };
  std::vector<std::uint32_t> start;
  std::vector<Entry> entries;

  GainRows() = default;
  GainRows(const GainMatrices& m, std::size_t n) : start(n + 1, 0), entries(2 * m.links.size()) {
    for (const GainMatrices::Link& l : m.links) ++start[l.i + 1], ++start[l.j + 1];
    for (std::size_t r = 0; r < n; ++r) start[r + 1] += start[r];
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    for (const GainMatrices::Link& l : m.links) {
      entries[next[l.i]++] = {l.j, l.weight};
      entries[next[l.j]++] = {l.i, l.weight};
    }
  }
};

/// The Collatz–Wielandt bounds of the two gain matrices, tightened one power sweep at a time,
/// both in one pass over the rows, on `threads` threads (each row alone: the same bits on any
/// count). In a run split by space (domain_split.hpp) each rank measures the rows of its own
/// particles, whose links it holds whole and in one process's order, and its ghosts take their
/// owners' x after each sweep: the bounds and their rows are the same bits as one process's.
class PowerBounds {
 public:
  /// The bounds of sweep 0 (Gershgorin's), on one thread: the sweeps after it on `threads`.
  PowerBounds(const GainMatrices& m, const SimulationState& s, int threads)
      : m_(m), s_(s), threads_(threads) {
    for (Bound& b : bounds_) {
      b.x.assign(m.diagonal[0].size(), 1.0);
      b.y.assign(m.diagonal[0].size(), 0.0);
    }
    linkProducts({true, true});
    for (Bound& b : bounds_) settle(b);
  }
  /// One more sweep of each: x ← B x (scaled), and the bound again; the bound kept is the
  /// smallest. A matrix without gains (B x = 0) keeps its bound.
  void next() {
    std::array<bool, 2> moved{};
    for (std::size_t k = 0; k < 2; ++k) {
      Bound& b = bounds_[k];
      double scale = 0.0;
      for (std::size_t i = 0; i < b.y.size(); ++i)
        scale = mine(i) ? std::max(scale, b.y[i]) : scale;
      if (split()) scale = s_.ranks->maxOverRanks(scale);
      if (!(scale > 0.0)) continue;
      for (std::size_t i = 0; i < b.x.size(); ++i) b.x[i] = std::max(b.y[i] / scale, 1e-300);
      if (split()) refreshGhostValues(s_, b.x);
      moved[k] = true;
    }
    measure(moved);
  }
  /// The bound on λ_max of matrix k (GainMatrices::kStiffness or kDamping).
  double value(std::size_t k) const { return bounds_[k].best; }
  /// The particle whose row sets matrix k's bound (its global id in a split run).
  std::size_t row(std::size_t k) const { return bounds_[k].row; }

 private:
  struct Bound {
    std::vector<double> x, y;
    double best = 0.0;
    std::size_t row = 0;
    bool first = true;
  };
  bool split() const { return s_.split.domains != nullptr; }
  bool mine(std::size_t i) const { return s_.owned.empty() || s_.owned[i]; }
  /// y = B x for the matrices `which`, then their bounds.
  void measure(std::array<bool, 2> which) {
    if (threads_ > 1 && rows_.start.empty()) rows_ = GainRows(m_, m_.diagonal[0].size());
    if (threads_ <= 1) {
      linkProducts(which);
    } else if (which[0] && which[1]) {
      products<true, true>();
    } else if (which[0]) {
      products<true, false>();
    } else if (which[1]) {
      products<false, true>();
    }
    for (std::size_t k = 0; k < 2; ++k) {
      if (which[k]) settle(bounds_[k]);
    }
  }
  /// y = B x on one thread: a walk over the links, each added to both its rows (the same terms
  /// in the same order as a row's product).
  void linkProducts(std::array<bool, 2> which) {
    for (std::size_t k = 0; k < 2; ++k) {
      if (!which[k]) continue;
      Bound& b = bounds_[k];
      for (std::size_t i = 0; i < b.x.size(); ++i) b.y[i] = m_.diagonal[k][i] * b.x[i];
    }
    if (which[0] && which[1]) {
      Bound &a = bounds_[0], &c = bounds_[1];
      for (const GainMatrices::Link& l : m_.links) {
        a.y[l.i] += l.weight[0] * a.x[l.j];
        a.y[l.j] += l.weight[0] * a.x[l.i];
        c.y[l.i] += l.weight[1] * c.x[l.j];
        c.y[l.j] += l.weight[1] * c.x[l.i];
      }
      return;
    }
    for (std::size_t k = 0; k < 2; ++k) {
      if (!which[k]) continue;
      Bound& b = bounds_[k];
      for (const GainMatrices::Link& l : m_.links) {
        b.y[l.i] += l.weight[k] * b.x[l.j];
        b.y[l.j] += l.weight[k] * b.x[l.i];
      }
    }
  }
  /// y = B x of the stiffness (kStiffness) and of the damping (kDamping), row by row: each
  /// row's two sums run side by side (a row's sum is a chain of additions, which the other
  /// hides), through local pointers (the rows' stores alias nothing the loop reads).
  template <bool kStiffness, bool kDamping>
  void products() {
    const long n = static_cast<long>(m_.diagonal[0].size());
    const std::uint32_t* start = rows_.start.data();
    const GainRows::Entry* entries = rows_.entries.data();
    const double *d0 = m_.diagonal[0].data(), *d1 = m_.diagonal[1].data();
    const double *x0 = bounds_[0].x.data(), *x1 = bounds_[1].x.data();
    double *y0 = bounds_[0].y.data(), *y1 = bounds_[1].y.data();
#pragma omp parallel for schedule(static) num_threads(threads_)
    for (long r = 0; r < n; ++r) {
      double a = kStiffness ? d0[r] * x0[r] : 0.0;
      double c = kDamping ? d1[r] * x1[r] : 0.0;
      for (std::uint32_t e = start[r]; e < start[r + 1]; ++e) {
        const GainRows::Entry& entry = entries[e];
        if constexpr (kStiffness) a += entry.weight[0] * x0[entry.other];
        if constexpr (kDamping) c += entry.weight[1] * x1[entry.other];
      }
      if constexpr (kStiffness) y0[r] = a;
      if constexpr (kDamping) y1[r] = c;
    }
  }
  /// The largest ratio (B x)_i / x_i over the run's particles, kept where it is the smallest
  /// bound so far.
  void settle(Bound& b) {
    // A particle without contacts has a zero row: x stays positive there (1), and its ratio 0.
    double largest = 0.0;
    std::size_t at = 0;
    bool found = false;
    for (std::size_t i = 0; i < b.x.size(); ++i) {
      const double ratio = b.y[i] / b.x[i];
      if (mine(i) && ratio > largest) largest = ratio, at = i, found = true;
    }
    if (split()) {
      // The first particle (by global id) of the largest ratio over the ranks, or particle 0.
      const double run = s_.ranks->maxOverRanks(largest);
      const double id = found && largest == run ? double(s_.split.globalId[at]) : 1e300;
      at = run > 0.0 ? static_cast<std::size_t>(-s_.ranks->maxOverRanks(-id)) : 0;
      largest = run;
    }
    if (b.first || largest < b.best) b.best = largest, b.row = at;
    b.first = false;
  }

  const GainMatrices& m_;
  GainRows rows_;  ///< with several threads, from the first sweep on
  const SimulationState& s_;
  const int threads_;
  std::array<Bound, 2> bounds_;
};

/// The fewest sweeps a bound makes on threads (PowerBounds): fewer run on one.
constexpr int kSweepsForThreads = 16;

/// One contact's share of the bound, computed alone (on any thread): its bodies (j = i for a
/// wall), its gains on each body's springs and dashpots (contactGain), and its least damping
/// ratio as the terms give it (LinearContact::leastRatio, `damped`), which a contact with no
/// normal spring yet (Hertz at touch) completes from the contacts before it (BoundSums).
struct ContactShare {
  std::uint32_t i = 0, j = 0;
  double ki = 0, kj = 0, ci = 0, cj = 0;
  double leastRatio = 0;
  bool damped = false, springless = false;
};

/// Computes contact shares (ContactShare).
class ShareOf {
 public:
  explicit ShareOf(const SimulationState& s)
      : s_(s),
        constants_(s.config.material, s.config.timeStep),
        optional_(optionalMask(s.config.material)) {}
  ContactShare operator()(const NetworkContact& n) const {
    const Particles& p = s_.particles;
    const std::size_t i = n.i, j = n.j;
    const double h = n.overlap;
    const bool rotations = s_.frictional;
    const LinearContact linear = linearisedContact(s_, n, constants_, optional_);
    ContactShare share;
    share.i = static_cast<std::uint32_t>(i);
    share.j = static_cast<std::uint32_t>(j);
    share.leastRatio = linear.leastRatio;
    share.damped = linear.damped;
    share.springless = !(linear.stiffness.normal > 0.0);
    const ContactModes &k = linear.stiffness, &c = linear.damping;
    const ContactBody bi{p.mass[i], p.inertia(i), p.radius[i] - 0.5 * h};
    share.ki = contactGain(k, bi, rotations);
    share.ci = contactGain(c, bi, rotations);
    if (j != i) {
      const ContactBody bj{p.mass[j], p.inertia(j), p.radius[j] - 0.5 * h};
      share.kj = contactGain(k, bj, rotations);
      share.cj = contactGain(c, bj, rotations);
    }
    return share;
  }

 private:
  const SimulationState& s_;
  const ContactConstants constants_;
  const unsigned optional_;
};

/// The shares into the gain matrices and the least damping ratio, one at a time in the walk's
/// order (the diagonal's sums and the links' order are those of the walk).
class BoundSums {
 public:
  explicit BoundSums(std::size_t n) : gains(n) {}
  void add(const ContactShare& c) {
    double least = c.leastRatio;
    // With no normal spring the least so far stands in for the normal ratio (as
    // LinearContact::leastDampingRatio would keep it).
    if (c.springless) {
      const double r = smallestDampingRatio;
      least = c.damped ? (r < c.leastRatio ? r : c.leastRatio) : r;
    }
    smallestDampingRatio = added ? std::min(smallestDampingRatio, least) : least;
    added = true;
    if (c.j == c.i) {
      gains.wall(c.i, c.ki, c.ci);
    } else {
      gains.pair(c.i, c.j, c.ki, c.kj, c.ci, c.cj);
    }
  }
  GainMatrices gains;
  double smallestDampingRatio = NetworkFrequency{}.smallestDampingRatio;
  bool added = false;  ///< a contact added
};

}  // namespace

NetworkFrequency networkFrequencyBound(const SimulationState& s, int sweeps, double lookahead,
                                       const std::function<bool(const NetworkFrequency&)>& enough) {
  const Particles& p = s.particles;
  const NetworkWalk walk(s, lookahead);
  const ShareOf shareOf(s);
  const int teams = networkThreads(s, s.neighbours.second.size());
  BoundSums sums(p.size());
  sums.gains.links.reserve(s.neighbours.second.size());
  MotionTally tally(s);  // a split run counts a contact on the rank of its first particle
  auto one = [&](const NetworkContact& n) {
    tally.add(n);
    sums.add(shareOf(n));
  };
  if (teams <= 1) {
    walkNetworkContacts(s, lookahead, one);  // each contact added as the walk finds it
  } else {
    // The walk's order, its rows on the threads: each part's touching and approaching pairs,
    // linearised as they are found, into buffers of its own, then added in the parts' order
    // (the walls, few, on one thread between them).
    struct Part {
      std::vector<ContactShare> touching, approaching;
      MotionTally tally;
    };
    std::vector<Part> parts(static_cast<std::size_t>(teams), Part{{}, {}, MotionTally(s)});
    if (walk.walksPairs()) {
#pragma omp parallel num_threads(teams)
      {
        const std::size_t t = std::size_t(omp_get_thread_num());
        const std::size_t used = std::size_t(omp_get_num_threads());
        const std::size_t begin = p.size() * t / used, end = p.size() * (t + 1) / used;
        Part& part = parts[t];
        part.touching.reserve(s.neighbours.rowStart[end] - s.neighbours.rowStart[begin]);
        walk.pairs(
            begin, end,
            [&](const NetworkContact& n) {
              part.tally.add(n);
              part.touching.push_back(shareOf(n));
            },
            [&](const NetworkContact& n) {
              part.tally.add(n);
              part.approaching.push_back(shareOf(n));
            });
      }
    }
    for (const Part& part : parts) {
      for (const ContactShare& c : part.touching) sums.add(c);
    }
    if (walk.geometric()) {
      walk.touchingWalls(one);
    } else {
      walk.touchingFromPass(one);
    }
    if (walk.ahead()) {
      for (const Part& part : parts) {
        for (const ContactShare& c : part.approaching) sums.add(c);
      }
      walk.wallCandidates(one);
    }
    for (const Part& part : parts) tally.merge(part.tally);
  }

  NetworkFrequency out;
  tally.fill(out);
  out.smallestDampingRatio = sums.smallestDampingRatio;
  if (s.split.domains) {
    // The least ratio over the ranks (each contact is on one rank or on two alike).
    const double least = -s.ranks->maxOverRanks(
        sums.added ? -out.smallestDampingRatio : -std::numeric_limits<double>::infinity());
    out.smallestDampingRatio =
        std::isfinite(least) ? least : NetworkFrequency{}.smallestDampingRatio;
  }
  // The rows the threads sweep cost about six sweeps over the links to lay out: on two threads
  // they pay from some twelve sweeps on, so a check of an automatic step (8 at most) sweeps on
  // one thread. The same bits on any count.
  const int sweepThreads =
      sweeps >= kSweepsForThreads ? networkThreads(s, sums.gains.links.size()) : 1;
  PowerBounds bounds(sums.gains, s, sweepThreads);
  auto fill = [&] {
    out.omegaMax = std::sqrt(bounds.value(GainMatrices::kStiffness));
    out.particle = bounds.row(GainMatrices::kStiffness);
    out.dampingRate = bounds.value(GainMatrices::kDamping);
    out.dampingRatio = out.omegaMax > 0.0 ? out.dampingRate / (2.0 * out.omegaMax) : 0.0;
  };
  fill();
  for (int sweep = 0; sweep < sweeps && !(enough && enough(out)); ++sweep) {
    bounds.next();
    fill();
  }
  return out;
}

NetworkFrequency networkFrequencyBound(const Simulation& sim, int sweeps, double lookahead) {
  return networkFrequencyBound(SimulationAccess::state(sim), sweeps, lookahead, nullptr);
}

}  // namespace granular
