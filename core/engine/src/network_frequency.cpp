/// The contact network's frequency bound (granular/network_frequency.hpp).
#include "granular/network_frequency.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include "contact_linearisation.hpp"
#include "domain_split.hpp"
#include "force_pass.hpp"
#include "granular/exact_sum.hpp"
#include "network_bound.hpp"
#include "pair_motion.hpp"
#include "simulation_state.hpp"
#include "wall_contact.hpp"

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

/// The Collatz–Wielandt bounds of the two gain matrices, tightened one power sweep at a time,
/// both in one walk over the links. In a run split by space (domain_split.hpp) each rank
/// measures the rows of its own particles, whose links it holds whole and in one process's
/// order, and its ghosts take their owners' x after each sweep: the bounds and their rows are
/// the same bits as one process's.
class PowerBounds {
 public:
  /// The bounds of sweep 0 (Gershgorin's).
  PowerBounds(const GainMatrices& m, const SimulationState& s) : m_(m), s_(s) {
    for (Bound& b : bounds_) {
      b.x.assign(m.diagonal[0].size(), 1.0);
      b.y.assign(m.diagonal[0].size(), 0.0);
    }
    measure({true, true});
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
    } else {
      for (std::size_t k = 0; k < 2; ++k) {
        if (!which[k]) continue;
        Bound& b = bounds_[k];
        for (const GainMatrices::Link& l : m_.links) {
          b.y[l.i] += l.weight[k] * b.x[l.j];
          b.y[l.j] += l.weight[k] * b.x[l.i];
        }
      }
    }
    for (std::size_t k = 0; k < 2; ++k) {
      if (which[k]) settle(bounds_[k]);
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
  const SimulationState& s_;
  std::array<Bound, 2> bounds_;
};

/// Whether the neighbour list is built for the particles there are (a rank's list before its
/// first build is not).
bool isListed(const SimulationState& s) {
  return s.neighbours.valid && s.neighbours.rowStart.size() == s.particles.size() + 1;
}

/// Whether the touching pairs come from the listed pairs' geometry alone: listed, and no mesh
/// wall (walkNetworkContacts).
bool pairsFromGeometry(const SimulationState& s) {
  return isListed(s) && std::none_of(s.walls.begin(), s.walls.end(), [](const Wall& w) {
           return w.shape == WallShape::Mesh && !w.removed;
         });
}

/// visitNetworkContacts with the visitor's type known, so that it is called inline (at every
/// check and scan, once a contact).
/// Without kPairs the pairs are left out (the walls' contacts alone): the caller counts them
/// itself (networkMotion's chunks).
template <bool kPairs = true, class Visit>
void walkNetworkContacts(const SimulationState& s, double lookahead, Visit&& visit) {
  const Particles& p = s.particles;
  const Material& material = s.config.material;
  const bool hertz = material.normalLaw == NormalLaw::Hertz;
  const double kappa = material.normalCoefficient();
  // The overlap an impact at closing speed u adds under Hertz's law (Hooke's k_n does not
  // depend on it): ½ m u² = (2/5) κ √R h^(5/2).
  auto impactOverlap = [&](double mass, double reduced, double u) {
    if (!hertz || !(u > 0.0)) return 0.0;
    return std::pow(5.0 * mass * u * u / (4.0 * kappa * std::sqrt(reduced)), 0.4);
  };
  auto pairOf = [&](std::size_t i, std::size_t j, const Vec3& normal, double u, double h,
                    bool touching, double relative) {
    const double reduced = p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
    const double mass = p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
    return NetworkContact{i, j,        normal,  reduced, mass, h + impactOverlap(mass, reduced, u),
                          u, touching, relative};
  };
  auto wallOf = [&](std::size_t i, const Vec3& normal, double u, double h, bool touching,
                    double relative) {
    return NetworkContact{i,           i,         normal,
                          p.radius[i], p.mass[i], h + impactOverlap(p.mass[i], p.radius[i], u),
                          u,           touching,  relative};
  };

  const NeighbourList& list = s.neighbours;
  const bool listed = isListed(s);
  const bool ahead = lookahead > 0.0 && listed;
  // From the geometry alone where no mesh wall is: spheres and analytic walls touch where their
  // surfaces overlap, and the forces, which a measuring pass would evaluate (serially) besides,
  // are not needed. A mesh's sphere may touch several of its triangles: the measuring pass finds
  // them as the force pass does, and the pairs' walk then looks for candidates only.
  const bool geometric = pairsFromGeometry(s);

  // One walk over the list's pairs: touching pairs (from each pair's first side) at
  // their overlap (plus an impact's), and candidates about to touch, which close their gap
  // within the lookahead at their present closing speed (the neighbour list holds every pair
  // that can touch before it is rebuilt). A pair apart and separating is neither, and is passed
  // over before its distance's square root (the margin keeps the comparison of squares on the
  // safe side of the rounding).
  std::vector<NetworkContact> candidates;  // visited after the touching contacts
  if (kPairs && listed && (geometric || ahead)) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      for (std::uint32_t k = list.rowStart[i]; k < list.rowStart[i + 1]; ++k) {
        const std::size_t j = list.second[k];
        const Vec3 d = p.position[j] - p.position[i];
        const Vec3 v = p.velocity[i] - p.velocity[j];
        const double reach = p.radius[i] + p.radius[j], distance2 = d.squaredNorm();
        if (distance2 > reach * reach * (1.0 + 1e-12) && !(ahead && v.dot(d) > 0.0)) continue;
        const double distance = std::sqrt(distance2);
        const double h = reach - distance;
        if (geometric && h > 0.0) {
          const Vec3 normal = d / distance;
          visit(pairOf(i, j, normal, v.dot(normal), h, true, v.norm()));
        }
        if (!ahead) continue;
        const double gap = distance - p.radius[i] - p.radius[j];
        if (!(gap > 0.0)) continue;
        const double u = v.dot(d) / distance;
        if (!(u > 0.0) || gap > u * lookahead) continue;
        candidates.push_back(pairOf(i, j, d / distance, u, 0.0, false, v.norm()));
      }
    }
  }

  if (geometric) {
    for (std::size_t w = 0; w < list.wallParticles.size() && w < s.walls.size(); ++w) {
      const Wall& wall = s.walls[w];
      if (wall.removed) continue;
      for (const std::uint32_t i : list.wallParticles[w]) {
        if (i >= p.size()) continue;
        const WallTouch touch = touchOf(wall, p.position[i]);
        const double h = p.radius[i] - touch.distance;
        if (!(h > 0.0)) continue;
        const Vec3 normal = -touch.normal;  // out of i into the wall
        const Vec3 point = p.position[i] + (p.radius[i] - 0.5 * h) * normal;  // midway
        const Vec3 v = p.velocity[i] - wall.velocityAt(point);
        visit(wallOf(i, normal, v.dot(normal), h, true, v.norm()));
      }
    }
  } else {
    visitContacts(
        s,
        [&](const ContactView& c) {
          // A pull across a gap (a term that reaches beyond touch) has no spring: the pair is
          // a candidate below, about to touch if it approaches.
          if (c.overlap < 0.0) return;
          const std::size_t i = c.particle;
          if (c.isWall()) {
            const Vec3 v = p.velocity[i] - s.walls[c.wall()].velocityAt(c.point);
            visit(wallOf(i, c.normal, v.dot(c.normal), c.overlap, true, v.norm()));
          } else {
            const std::size_t j = c.otherParticle();
            if (j < i) return;
            const Vec3 v = p.velocity[i] - p.velocity[j];
            visit(pairOf(i, j, c.normal, v.dot(c.normal), c.overlap, true, v.norm()));
          }
        },
        nullptr);
  }

  // Candidates, pairs before walls.
  if (!ahead) return;
  for (const NetworkContact& c : candidates) visit(c);
  for (std::size_t w = 0; w < list.wallParticles.size() && w < s.walls.size(); ++w) {
    const Wall& wall = s.walls[w];
    const bool mesh = wall.shape == WallShape::Mesh;
    const bool binned = mesh && w < list.meshGrid.size() && !list.meshGrid[w].empty();
    for (std::size_t k = 0; k < list.wallParticles[w].size(); ++k) {
      const std::uint32_t i = list.wallParticles[w][k];
      if (i >= p.size() || (mesh && k % kMeshContacts != 0)) continue;  // a mesh's first entry
      WallTouch touch;
      if (binned) {
        const MeshNearest nearest =
            nearestOnMesh(wall.mesh->world, wall.mesh->topology, list.meshGrid[w], p.position[i]);
        touch = {nearest.distance, nearest.normal};
      } else {
        touch = touchOf(wall, p.position[i]);
      }
      const double gap = touch.distance - p.radius[i];
      if (!(gap > 0.0)) continue;
      const Vec3 closest = p.position[i] - touch.distance * touch.normal;
      const Vec3 v = p.velocity[i] - wall.velocityAt(closest);
      const double u = -v.dot(touch.normal);
      if (!(u > 0.0) || gap > u * lookahead) continue;
      visit(wallOf(i, -touch.normal, u, 0.0, false, v.norm()));
    }
  }
}

}  // namespace

void visitNetworkContacts(const SimulationState& s, double lookahead,
                          const std::function<void(const NetworkContact&)>& visit) {
  walkNetworkContacts(s, lookahead, visit);
}

LinearContact linearisedContact(const SimulationState& s, const NetworkContact& n,
                                const ContactConstants& constants, unsigned optional) {
  const Particles& p = s.particles;
  const bool wall = n.j == n.i;
  LinearContact linear;
  linear.radius = n.reduced;
  linear.mass = n.mass;
  linear.overlap = std::max(n.overlap, 0.0);
  const double ii = 1.4 * p.mass[n.i] * p.radius[n.i] * p.radius[n.i];  // I + m R²
  const double ij = wall ? 0.0 : 1.4 * p.mass[n.j] * p.radius[n.j] * p.radius[n.j];
  linear.rollingInertia = wall ? ii : 1.0 / (1.0 / ii + 1.0 / ij);
  lineariseContact(constants, s.frictional, optional, linear);
  return linear;
}

namespace {

/// What the contacts' motion tells the step control, summed as they are visited: the counts, the
/// fastest approach and the kinetic energy of the relative motion (NetworkFrequency's fields).
/// A split run counts a contact on the rank that owns its first particle.
class MotionTally {
 public:
  explicit MotionTally(const SimulationState& s) : s_(s) {}
  void add(const NetworkContact& n) {
    out_.fastestApproach = std::max(out_.fastestApproach, n.approach);
    if (!(s_.owned.empty() || s_.owned[n.i])) return;
    (n.touching ? out_.contacts : out_.approaching) += 1;
    relativeKinetic_.add(0.5 * n.mass * n.relativeSpeed * n.relativeSpeed);
  }
  /// Pairs [0, m) of `c` (pairMotions), as add would count each touching and each approaching
  /// one.
  void addPairs(PairMotionChunk& c, std::size_t m, double lookahead) {
    const PairMotionCounts counts = pairMotions(c, m, lookahead);
    out_.contacts += static_cast<std::size_t>(counts.touching);
    out_.approaching += static_cast<std::size_t>(counts.approaching);
    out_.fastestApproach = std::max(out_.fastestApproach, counts.fastest);
    relativeKinetic_.addAll(c.energy, m);
  }
  /// Adds what `other` counted (exactly: any split of the contacts gives the same bits).
  void merge(const MotionTally& other) {
    out_.contacts += other.out_.contacts;
    out_.approaching += other.out_.approaching;
    out_.fastestApproach = std::max(out_.fastestApproach, other.out_.fastestApproach);
    relativeKinetic_.merge(other.relativeKinetic_);
  }
  /// The tally into `out` (collective in a split run: sums and the largest over the ranks).
  void fill(NetworkFrequency& out) {
    if (s_.split.domains) {
      std::vector<std::uint64_t> counts{out_.contacts, out_.approaching};
      s_.ranks->sumOverRanks(counts);
      out_.contacts = counts[0];
      out_.approaching = counts[1];
      out_.fastestApproach = s_.ranks->maxOverRanks(out_.fastestApproach);
      std::vector<ExactSum> sums{relativeKinetic_};
      s_.ranks->mergeOverRanks(sums);
      relativeKinetic_ = sums[0];
    }
    out.contacts = out_.contacts;
    out.approaching = out_.approaching;
    out.fastestApproach = out_.fastestApproach;
    out.relativeKinetic = relativeKinetic_.value();
  }

 private:
  const SimulationState& s_;
  NetworkFrequency out_;
  ExactSum relativeKinetic_;  // exact: the same bits on any rank count
};

/// The listed pairs into `tally`, a chunk at a time (pair_motion.hpp): the same contacts,
/// speeds and energies as walkNetworkContacts's pairs, at a fraction of the cost. On the pass's
/// threads, each its run of rows into a tally of its own, merged after: counts, the largest speed
/// and an exact sum, the same bits on any thread count.
void tallyListedPairs(const SimulationState& s, double lookahead, MotionTally& tally) {
  const Particles& p = s.particles;
  const NeighbourList& list = s.neighbours;
  const std::size_t n = p.size();
  // Below this many pairs (a scan of some 60 µs on one thread) the threads are not started:
  // their start and the merge would be a large share of what they save.
  constexpr std::size_t kPairsForThreads = 4096;
  const int threads = passThreads(s) > 0 ? passThreads(s) : omp_get_max_threads();
  const int teams = list.second.size() < kPairsForThreads ? 1 : std::max(threads, 1);
  std::vector<MotionTally> parts(static_cast<std::size_t>(teams), MotionTally(s));
#pragma omp parallel num_threads(teams)
  {
    const std::size_t t = std::size_t(omp_get_thread_num());
    const std::size_t used = std::size_t(omp_get_num_threads());
    MotionTally& part = parts[t];
    PairMotionChunk chunk;
    std::size_t m = 0;
    for (std::size_t i = n * t / used; i < n * (t + 1) / used; ++i) {
      const Vec3 xi = p.position[i], vi = p.velocity[i];
      const double ri = p.radius[i], mi = p.mass[i];
      const double mine = s.owned.empty() || s.owned[i] ? 1.0 : 0.0;
      for (std::uint32_t k = list.rowStart[i]; k < list.rowStart[i + 1]; ++k) {
        const std::size_t j = list.second[k];
        const Vec3 d = p.position[j] - xi, v = vi - p.velocity[j];
        chunk.dx[m] = d.x(), chunk.dy[m] = d.y(), chunk.dz[m] = d.z();
        chunk.vx[m] = v.x(), chunk.vy[m] = v.y(), chunk.vz[m] = v.z();
        chunk.ri[m] = ri, chunk.rj[m] = p.radius[j];
        chunk.mi[m] = mi, chunk.mj[m] = p.mass[j];
        chunk.owned[m] = mine;
        if (++m == PairMotionChunk::kSize) part.addPairs(chunk, std::exchange(m, 0), lookahead);
      }
    }
    if (m > 0) part.addPairs(chunk, m, lookahead);
  }
  for (const MotionTally& part : parts) tally.merge(part);
}

}  // namespace

NetworkFrequency networkMotion(const SimulationState& s, double lookahead) {
  MotionTally tally(s);
  if (pairsFromGeometry(s)) {
    tallyListedPairs(s, lookahead, tally);  // pairMotions: no approach at lookahead <= 0
    walkNetworkContacts<false>(s, lookahead, [&](const NetworkContact& n) { tally.add(n); });
  } else {
    walkNetworkContacts(s, lookahead, [&](const NetworkContact& n) { tally.add(n); });
  }
  NetworkFrequency out;
  tally.fill(out);
  return out;
}

NetworkFrequency networkFrequencyBound(const SimulationState& s, int sweeps, double lookahead,
                                       const std::function<bool(const NetworkFrequency&)>& enough) {
  const Particles& p = s.particles;
  const Material& material = s.config.material;
  const bool rotations = s.frictional;
  const ContactConstants constants(material, s.config.timeStep);
  const unsigned optional = optionalMask(material);
  GainMatrices gains(p.size());
  gains.links.reserve(s.neighbours.second.size());
  NetworkFrequency out;

  auto body = [&](std::size_t i, double h) {
    return ContactBody{p.mass[i], p.inertia(i), p.radius[i] - 0.5 * h};
  };
  bool added = false;    // a contact added here
  MotionTally tally(s);  // a split run counts a contact on the rank of its first particle
  // One contact between i and j (j = i: a wall), at overlap h: the terms' springs and dashpots
  // on its modes (contact_linearisation.hpp), and their gains on each body.
  walkNetworkContacts(s, lookahead, [&](const NetworkContact& n) {
    const std::size_t i = n.i, j = n.j;
    const double h = n.overlap;
    tally.add(n);
    LinearContact linear = linearisedContact(s, n, constants, optional);
    // A contact with no normal spring yet (Hertz at touch) has no normal ratio: the least so
    // far stands in for it.
    if (!(linear.stiffness.normal > 0.0)) linear.leastDampingRatio(out.smallestDampingRatio);
    const double smallest = linear.leastRatio;
    out.smallestDampingRatio = added ? std::min(out.smallestDampingRatio, smallest) : smallest;
    added = true;
    const ContactModes &k = linear.stiffness, &c = linear.damping;
    const ContactBody bi = body(i, h);
    if (j == i) {
      gains.wall(i, contactGain(k, bi, rotations), contactGain(c, bi, rotations));
      return;
    }
    const ContactBody bj = body(j, h);
    gains.pair(i, j, contactGain(k, bi, rotations), contactGain(k, bj, rotations),
               contactGain(c, bi, rotations), contactGain(c, bj, rotations));
  });

  tally.fill(out);
  if (s.split.domains) {
    // The least ratio over the ranks (each contact is on one rank or on two alike).
    const double least = -s.ranks->maxOverRanks(added ? -out.smallestDampingRatio
                                                      : -std::numeric_limits<double>::infinity());
    out.smallestDampingRatio =
        std::isfinite(least) ? least : NetworkFrequency{}.smallestDampingRatio;
  }
  PowerBounds bounds(gains, s);
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
