#pragma once
/// A run split by space among processes (Simulation::splitAmong, docs/physics.md §2.9): each
/// rank holds the particles its domain owns and, as ghosts, those within a halo of it, in
/// ascending global id. Particles and the springs of their pairs travel between ranks as
/// records; a rank's state is assembled from the records it holds.
#include <cstdint>
#include <memory>
#include <vector>

#include "granular/domain_map.hpp"
#include "particle_fields.hpp"
#include "simulation_state.hpp"

namespace granular {

/// One particle's whole state, as it travels: identity, its fields (particle_fields.hpp: motion,
/// the integrator's derivatives, its last forces), its reference position in the neighbour
/// list, and its wall contacts.
struct ParticleRecord {
  std::uint64_t id = 0;
  /// The fields of the particles and the integrator, where forEachRecordField puts them; zero
  /// for those the state does not hold.
  double value[recordDoubles()];
  float reference[3];
  std::uint64_t wallCandidate = 0;  ///< bit w: a candidate of wall w in the neighbour list
  std::uint64_t wallHistoryAt = 0;  ///< its wall entries in the batch's pool (friction only)
};

/// One entry of a wall candidate (a mesh's candidate has kMeshContacts of them): its spring,
/// and for a mesh the normal of the contact it holds (zero for none).
struct WallEntryRecord {
  ContactHistory spring;
  double normal[3];
};

/// A candidate pair by global ids, with its spring (zero when it holds none).
struct PairRecord {
  std::uint64_t first = 0, second = 0;
  ContactHistory spring;
};

/// Records as a rank holds them before assembling its state.
struct RecordBatch {
  std::vector<ParticleRecord> particles;
  /// Per record, its wall candidates' entries, ascending wall (friction only).
  std::vector<WallEntryRecord> wallEntries;
  std::vector<PairRecord> pairs;
};

/// Splits the whole state every rank holds: this rank keeps the particles its domain owns and
/// their ghosts, the neighbour list's pairs among them and their springs, and the list as it
/// is (it is rebuilt when it would have been in one process).
void splitState(SimulationState& s, std::shared_ptr<const DomainMap> domains,
                std::shared_ptr<const Communicator> ranks);
/// At a rebuild, after the prediction: every particle goes to the rank whose domain holds it
/// now and to those it is a ghost of, with the springs of its pairs; the list is then rebuilt
/// from the state assembled, carrying them.
void redistribute(SimulationState& s);
/// After the list's rebuild on every rank: the values the staleness test and the counters take
/// over the whole run (the reference positions' rounding, the count of candidate pairs).
void afterSplitRebuild(SimulationState& s);
/// The ghosts take their owners' position, velocity and spin.
void refreshSplitGhosts(SimulationState& s);
/// The ghosts' entries of a per-particle array take their owners'.
void refreshGhostValues(const SimulationState& s, std::vector<double>& values);
/// The whole run's state, on every rank, as one process would hold it.
std::unique_ptr<SimulationState> gatherWhole(const SimulationState& s);

}  // namespace granular
