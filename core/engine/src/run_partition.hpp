#pragma once
/// How a run is shared among processes, as the step sees it: the hooks where a run split by
/// space (domain_split.hpp) does more than one process holding every particle. The step calls
/// each hook unconditionally; the whole run's do nothing, or give what one process has. A hook
/// runs once per step or once per particle range, never per particle, so that the virtual call
/// costs nothing beside the loops it stands between.
///
/// The implementations hold no state of their own (what they act on is the SimulationState's),
/// so a state holds a pointer to one of two shared instances and copies of the state stay
/// valid.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace granular {

class Communicator;
struct SimulationState;
struct LargestMoves;

class RunPartition {
 public:
  virtual ~RunPartition() = default;

  /// The two largest moves² [m²] among the particles [begin, end) since the neighbour list's
  /// build, measured on the predictor's ranges; none where the moves are only known after the
  /// prediction (largestMovesAfterPrediction).
  virtual LargestMoves largestMovesInRange(const SimulationState& s, std::size_t begin,
                                           std::size_t end) const = 0;
  /// After the prediction: the two largest moves² [m²] the staleness test takes, given the
  /// ranges' merged (largestMovesInRange). A split run's ghosts take their owners' predictions
  /// first, and the moves are the whole run's (each particle once, by its owner), so that every
  /// rank rebuilds when one process would.
  virtual LargestMoves largestMovesAfterPrediction(SimulationState& s,
                                                   const LargestMoves& ranges) const = 0;
  /// Just before the neighbour list's rebuild: a split run's particles go where they now belong.
  virtual void beforeRebuild(SimulationState& s) const = 0;
  /// Just after the rebuild: the values the staleness test and the counters take over the run.
  virtual void afterRebuild(SimulationState& s) const = 0;
  /// In the corrector, before the accelerations of the particles [begin, end): a ghost's force
  /// is only the part its contacts here give, and is dropped so that what the corrector makes
  /// of it (overwritten by its owner's next prediction) stays finite.
  virtual void dropGhostForces(SimulationState& s, std::size_t begin, std::size_t end) const = 0;
  /// Before the step is checked on the corrected state: a split run's ghosts take their owners'
  /// corrections (theirs came from partial forces).
  virtual void beforeStepCheck(SimulationState& s) const = 0;
  /// The whole run's count of candidate pairs.
  virtual std::uint64_t neighbourPairs(const SimulationState& s) const = 0;
  /// What a broken state's report names (the first non-finite particle, and where a split run
  /// holds it), or nullopt where another process reports it: a ghost's broken values are its
  /// owner's.
  virtual std::optional<std::string> brokenParticle(const SimulationState& s) const = 0;
  /// The whole run's state, as one process would hold it (collective in a split run).
  virtual std::unique_ptr<SimulationState> wholeState(const SimulationState& s) const = 0;
  /// The index in the whole state of particle i of those held here.
  virtual std::uint64_t globalId(const SimulationState& s, std::size_t i) const = 0;
  /// The processes the run is split among; null for a run in one process.
  virtual const Communicator* ranks(const SimulationState& s) const = 0;
};

/// One process holds every particle (and may share only the sums: Simulation::setOwnership).
const RunPartition& wholeRun();
/// Split by space among processes (Simulation::splitAmong).
const RunPartition& splitRun();

}  // namespace granular
