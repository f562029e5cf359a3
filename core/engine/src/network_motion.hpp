#pragma once
/// What the contacts' motion tells the step control (networkMotion, network_bound.hpp), summed
/// as the contacts are visited.
#include "granular/exact_sum.hpp"
#include "granular/network_frequency.hpp"
#include "network_bound.hpp"
#include "pair_motion.hpp"

namespace granular {

/// The counts, the fastest approach and the kinetic energy of the relative motion
/// (NetworkFrequency's fields), summed as contacts are added. A split run counts a contact on
/// the rank that owns its first particle. Tallies of parts of the contacts merge exactly: any
/// split among threads gives the same bits.
class MotionTally {
 public:
  explicit MotionTally(const SimulationState& s) : s_(s) {}
  void add(const NetworkContact& n);
  /// Pairs [0, m) of `c` (pairMotions), as add would count each touching and each approaching
  /// one.
  void addPairs(PairMotionChunk& c, std::size_t m, double lookahead);
  /// Adds what `other` counted (exactly: any split of the contacts gives the same bits).
  void merge(const MotionTally& other);
  /// The tally into `out` (collective in a split run: sums and the largest over the ranks).
  void fill(NetworkFrequency& out);

 private:
  const SimulationState& s_;
  NetworkFrequency out_;
  ExactSum relativeKinetic_;  // exact: the same bits on any rank count
};

}  // namespace granular
