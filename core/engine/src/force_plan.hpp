#pragma once
/// How the force pass splits its work among threads (private to the engine): the plan, built
/// from the neighbour lists at a rebuild or when the thread count changes.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace granular {

/// How the force pass splits its work among threads (force_pass.cpp), derived from the lists
/// and the thread count, rebuilt with them (not checkpointed).
///
/// The pass works on the list's particle blocks (NeighbourList::blockParticle) and, per wall w,
/// their wall candidates [blockWall[b·W + w], blockWall[(b+1)·W + w]). The blocks depend on the
/// lists only, never on the thread count: each block sums its contact powers in contact order,
/// and the blocks are summed in order, so the sums are the same bits for any thread count.
///
/// Each thread owns a run of blocks [threadBlock[t], threadBlock[t+1]) and adds the forces of
/// its contacts straight to its own particles. A pair whose second particle belongs to a later
/// thread "crosses" (crossing[c], ascending pair index; crossingFirst[c] its first particle): its
/// first's thread computes it as any other pair, and the owner of the second particle computes it
/// again from the same inputs (the spring as it was before the pass,
/// ContactScratch::crossingSpring) and adds the second's share of `incoming[incomingStart[t] ..]`
/// (sorted by second particle, then first) before its own pairs. Every particle thus receives its
/// contacts in one order whatever the thread count: the pairs where it is second (ascending first),
/// those where it is first (ascending second), then its walls (ascending wall).
struct ForcePlan {
  std::vector<std::uint32_t> blockWall;
  std::vector<std::uint32_t> threadBlock;
  std::vector<std::uint32_t> crossing, crossingFirst, incoming, incomingStart;
  int threads = 0;
  bool valid = false;  ///< built for the current lists and `threads`
};

struct NeighbourList;  // simulation_state.hpp

/// Builds list.plan for the list's particles, `walls` walls and `threads` parts.
void buildForcePlan(NeighbourList& list, std::size_t walls, int threads);

}  // namespace granular
