/// The run split by space among processes (run_partition.hpp): each hook calls the split's
/// own step (domain_split.hpp).
#include <memory>

#include "domain_split.hpp"
#include "run_partition.hpp"
#include "simulation_state.hpp"
#include "state_checks.hpp"

namespace granular {
namespace {

class SplitRun final : public RunPartition {
 public:
  LargestMoves largestMovesInRange(const SimulationState&, std::size_t,
                                   std::size_t) const override {
    // The ghosts' predictions are replaced after the prediction, and the moves taken then.
    return {};
  }
  LargestMoves largestMovesAfterPrediction(SimulationState& s, const LargestMoves&) const override {
    // The ghosts' predictions came from their own (unforced) derivatives: their owners'
    // replace them, and the moves are taken over true positions, each particle by its owner,
    // then over the ranks: the largest, and the second, which is the largest again where two
    // ranks hold it (the same two as one process's).
    refreshSplitGhosts(s);
    const LargestMoves mine =
        largestMoves(s.neighbours, s.particles, 0, s.particles.size(), &s.owned);
    LargestMoves run;
    run.first = s.ranks->maxOverRanks(mine.first);
    std::vector<std::uint64_t> holders{mine.first == run.first ? 1u : 0u};
    s.ranks->sumOverRanks(holders);
    run.second = holders[0] > 1
                     ? run.first
                     : s.ranks->maxOverRanks(mine.first == run.first ? mine.second : mine.first);
    return run;
  }
  void beforeRebuild(SimulationState& s) const override {
    // The particles go where they now belong, with their springs; the list is then rebuilt
    // from what each rank holds.
    redistribute(s);
  }
  void afterRebuild(SimulationState& s) const override { afterSplitRebuild(s); }
  void dropGhostForces(SimulationState& s, std::size_t begin, std::size_t end) const override {
    const bool rotating = s.frictional;
    for (std::size_t i = begin; i < end; ++i) {
      if (s.owned[i]) continue;
      s.force[i] = Vec3::Zero();
      if (rotating) s.torque[i] = Vec3::Zero();
    }
  }
  void beforeStepCheck(SimulationState& s) const override { refreshSplitGhosts(s); }
  std::uint64_t neighbourPairs(const SimulationState& s) const override { return s.split.pairs; }
  std::optional<std::string> brokenParticle(const SimulationState& s) const override {
    const std::optional<std::string> what =
        firstNonFiniteParticle(s.particles, &s.owned, &s.split.globalId);
    if (!what) return std::nullopt;
    return *what + " (on rank " + std::to_string(s.ranks->rank()) + " of " +
           std::to_string(s.ranks->size()) + ")";
  }
  std::unique_ptr<SimulationState> wholeState(const SimulationState& s) const override {
    std::unique_ptr<SimulationState> whole = gatherWhole(s);
    whole->partition = &wholeRun();
    return whole;
  }
  std::uint64_t globalId(const SimulationState& s, std::size_t i) const override {
    return s.split.globalId.at(i);
  }
  const Communicator* ranks(const SimulationState& s) const override { return s.ranks.get(); }
};

}  // namespace

const RunPartition& splitRun() {
  static const SplitRun run;
  return run;
}

}  // namespace granular
