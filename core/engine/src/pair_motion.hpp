#pragma once
/// The listed pairs' relative motion for the step control's scan (networkMotion,
/// docs/physics.md §2.16), in chunks of arrays: each pair computed alone, with selects instead of
/// branches, so that the loop runs in vector registers. Built for the baseline and for AVX2, the
/// same bits (simd_build.hpp), and the same bits as the walk over the contacts one at a time
/// (Eigen's order of a 3-vector's dot product, left to right).
#include <cstddef>

namespace granular {

/// Up to kSize pairs of the neighbour list (i, j), gathered, and what pairMotions makes of them.
struct PairMotionChunk {
  static constexpr std::size_t kSize = 128;
  // In: x_j − x_i [m], v_i − v_j [m/s], the radii [m] and masses [kg], and 1 where i is this
  // rank's particle (else 0: the pair is counted on the rank that owns i).
  alignas(64) double dx[kSize], dy[kSize], dz[kSize];
  alignas(64) double vx[kSize], vy[kSize], vz[kSize];
  alignas(64) double ri[kSize], rj[kSize], mi[kSize], mj[kSize];
  alignas(64) double owned[kSize];
  /// Out: each pair's ½ m* |v_i − v_j|², m* = m_i m_j / (m_i + m_j), the kinetic energy of its
  /// relative motion [J], once for each way it counts (touching, approaching) where i is owned,
  /// else 0.
  alignas(64) double energy[kSize];
};

/// What pairMotions counts over a chunk. A pair touches where its overlap is positive, and
/// approaches where it is apart and closes its gap within the lookahead at its present closing
/// speed: one at the edge of touch may be both, as the walk one at a time counts it.
struct PairMotionCounts {
  double touching = 0, approaching = 0;  ///< of the owned pairs (whole numbers)
  /// The fastest closing speed along the centres' line of the pairs counted, owned or not: of the
  /// contact where a pair touches, of the approach where it approaches; 0 if none is positive
  /// [m/s].
  double fastest = 0;
};

/// Fills the energies of pairs [0, m) of `c` and counts them; with `lookahead` ≤ 0 no pair
/// approaches.
PairMotionCounts pairMotions(PairMotionChunk& c, std::size_t m, double lookahead);

}  // namespace granular
