/// The listed pairs' relative motion in chunks (pair_motion.hpp).
#include "pair_motion.hpp"

#include <cmath>

#include "granular/simd_build.hpp"

namespace granular {
namespace {

// The conditions of the walk one at a time (network_contacts.hpp, NetworkWalk::pairs), as
// selects: a pair touches where h = (r_i + r_j) − |d| > 0; it approaches where, with a lookahead,
// its gap (|d| − r_i) − r_j is positive, its closing speed u = (v·d) / |d| too, and the gap no
// more than u times the lookahead. Every value is computed for every pair; those that do not
// count are dropped by the selects (a division by a zero distance among them: nothing reads the
// floating-point flags). The sums are of whole numbers and the largest speed is taken from 0 up:
// any order of the lanes gives the same bits.
[[gnu::always_inline]] inline PairMotionCounts motionsBody(PairMotionChunk& c, std::size_t m,
                                                           double lookahead) {
  const bool ahead = lookahead > 0.0;
  double touching = 0.0, approaching = 0.0, fastest = 0.0;
#pragma omp simd reduction(+ : touching, approaching) reduction(max : fastest)
  for (std::size_t k = 0; k < m; ++k) {
    const double dx = c.dx[k], dy = c.dy[k], dz = c.dz[k];
    const double vx = c.vx[k], vy = c.vy[k], vz = c.vz[k];
    const double distance = std::sqrt((dx * dx + dy * dy) + dz * dz);
    const double h = (c.ri[k] + c.rj[k]) - distance;
    const double along = (vx * (dx / distance) + vy * (dy / distance)) + vz * (dz / distance);
    const double gap = (distance - c.ri[k]) - c.rj[k];
    const double u = ((vx * dx + vy * dy) + vz * dz) / distance;
    const bool touches = h > 0.0;
    const bool approaches = ahead & (gap > 0.0) & (u > 0.0) & !(gap > u * lookahead);
    const double speed = std::sqrt((vx * vx + vy * vy) + vz * vz);
    const double mass = c.mi[k] * c.mj[k] / (c.mi[k] + c.mj[k]);
    const double ways = (touches ? c.owned[k] : 0.0) + (approaches ? c.owned[k] : 0.0);
    c.energy[k] = ways > 0.0 ? ways * (0.5 * mass * speed * speed) : 0.0;
    touching += touches ? c.owned[k] : 0.0;
    approaching += approaches ? c.owned[k] : 0.0;
    const double closing = touches && along > 0.0 ? along : 0.0;
    fastest = fastest > closing ? fastest : closing;
    const double approach = approaches ? u : 0.0;
    fastest = fastest > approach ? fastest : approach;
  }
  return {touching, approaching, fastest};
}

}  // namespace

PairMotionCounts pairMotions(PairMotionChunk& c, std::size_t m, double lookahead) {
  return simdDispatch<motionsBody>(c, m, lookahead);
}

}  // namespace granular
