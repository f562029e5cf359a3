/// What the contacts' motion tells the step control (network_motion.hpp): the scan between
/// checks.
#include "network_motion.hpp"

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "network_contacts.hpp"
#include "simulation_state.hpp"

namespace granular {

void MotionTally::add(const NetworkContact& n) {
  out_.fastestApproach = std::max(out_.fastestApproach, n.approach);
  if (!(s_.owned.empty() || s_.owned[n.i])) return;
  (n.touching ? out_.contacts : out_.approaching) += 1;
  relativeKinetic_.add(0.5 * n.mass * n.relativeSpeed * n.relativeSpeed);
}

void MotionTally::addPairs(PairMotionChunk& c, std::size_t m, double lookahead) {
  const PairMotionCounts counts = pairMotions(c, m, lookahead);
  out_.contacts += static_cast<std::size_t>(counts.touching);
  out_.approaching += static_cast<std::size_t>(counts.approaching);
  out_.fastestApproach = std::max(out_.fastestApproach, counts.fastest);
  relativeKinetic_.addAll(c.energy, m);
}

void MotionTally::merge(const MotionTally& other) {
  out_.contacts += other.out_.contacts;
  out_.approaching += other.out_.approaching;
  out_.fastestApproach = std::max(out_.fastestApproach, other.out_.fastestApproach);
  relativeKinetic_.merge(other.relativeKinetic_);
}

void MotionTally::fill(NetworkFrequency& out) {
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

namespace {

/// The contacts into `tally` from the geometry alone (pairsFromGeometry): the listed pairs a
/// chunk at a time (pair_motion.hpp), the same contacts, speeds and energies as the walk one
/// at a time at a fraction of the cost, and the walls' contacts one at a time. On the pass's
/// threads, each its run of rows and its part of each wall's candidates into a tally of its
/// own, merged after: counts, the largest speed and an exact sum, the same bits on any thread
/// count.
void tallyFromGeometry(const SimulationState& s, double lookahead, MotionTally& tally) {
  const Particles& p = s.particles;
  const NeighbourList& list = s.neighbours;
  const std::size_t n = p.size();
  const NetworkWalk walk(s, lookahead);
  const int teams = networkThreads(s, list.second.size());
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
    if (m > 0) part.addPairs(chunk, m, lookahead);  // pairMotions: no approach at lookahead <= 0
    auto add = [&](const NetworkContact& c) { part.add(c); };
    walk.touchingWalls(add, t, used);
    if (walk.ahead()) walk.wallCandidates(add, t, used);
  }
  for (const MotionTally& part : parts) tally.merge(part);
}

}  // namespace

NetworkFrequency networkMotion(const SimulationState& s, double lookahead) {
  MotionTally tally(s);
  if (pairsFromGeometry(s)) {
    tallyFromGeometry(s, lookahead, tally);
  } else {
    walkNetworkContacts(s, lookahead, [&](const NetworkContact& n) { tally.add(n); });
  }
  NetworkFrequency out;
  tally.fill(out);
  return out;
}

}  // namespace granular
