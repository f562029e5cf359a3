/// A run whose process holds every particle (run_partition.hpp), alone or sharing only its
/// sums (Simulation::setOwnership): the hooks do nothing, or give what the state holds.
#include <memory>

#include "run_partition.hpp"
#include "simulation_state.hpp"
#include "state_checks.hpp"

namespace granular {
namespace {

class WholeRun final : public RunPartition {
 public:
  LargestMoves largestMovesInRange(const SimulationState& s, std::size_t begin,
                                   std::size_t end) const override {
    return largestMoves(s.neighbours, s.particles, begin, end);
  }
  LargestMoves largestMovesAfterPrediction(SimulationState&,
                                           const LargestMoves& ranges) const override {
    return ranges;
  }
  void beforeRebuild(SimulationState&) const override {}
  void afterRebuild(SimulationState&) const override {}
  void dropGhostForces(SimulationState&, std::size_t, std::size_t) const override {}
  void beforeStepCheck(SimulationState&) const override {}
  std::uint64_t neighbourPairs(const SimulationState& s) const override {
    return s.neighbours.second.size();
  }
  std::optional<std::string> brokenParticle(const SimulationState& s) const override {
    // The step found a value not finite: it is reported even where no particle shows it.
    return firstNonFiniteParticle(s.particles).value_or("a value is not finite");
  }
  std::unique_ptr<SimulationState> wholeState(const SimulationState& s) const override {
    return std::make_unique<SimulationState>(s);
  }
  std::uint64_t globalId(const SimulationState&, std::size_t i) const override { return i; }
  const Communicator* ranks(const SimulationState&) const override { return nullptr; }
};

}  // namespace

const RunPartition& wholeRun() {
  static const WholeRun run;
  return run;
}

}  // namespace granular
