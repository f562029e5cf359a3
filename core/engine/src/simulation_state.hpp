#pragma once
/// Private state of a Simulation (tests may include it). Sections:
///   1. contact history and the neighbour lists that carry it
///   2. integrator derivatives
///   3. energy accumulators
///   4. SimulationState itself
#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "force_plan.hpp"
#include "granular/communicator.hpp"
#include "granular/contact_model.hpp"
#include "granular/domain_map.hpp"
#include "granular/engine_studies.hpp"
#include "granular/exact_sum.hpp"
#include "granular/simulation.hpp"
#include "rollback.hpp"
#include "run_partition.hpp"
#include "thread_governor.hpp"
#include "triangle_grid.hpp"

namespace granular {

// ---- 1. Contact history -------------------------------------------------------------------

/// Tangential springs of the candidate pairs that touched at the last force pass (with a term
/// that reaches beyond touch: that were within its reach, a zero spring across a gap), and of no
/// others. A candidate list holds about 5 pairs a particle of which 2-3 touch in a dense bed: a
/// spring per candidate (32 B) was the largest array of a frictional bed, and a stretch that is
/// not held is simply zero. The springs of a particle block (NeighbourList::blockParticle) lie
/// in their own array in ascending pair order, so one thread owns each array in the force pass
/// and it may grow there; a pair's spring is found by counting the holding pairs before it in
/// its block (pair_springs.hpp).
///
/// Which pairs hold one is a bit per pair, in 64-bit words of 64 consecutive pairs counted from
/// each block's first pair: block b's pair blockPair[b] + 64 w + i is bit i of word
/// blockWord[b] + w. A word is one chunk of the force pass, whose thread owns it.
///
/// A held spring is a record of `slots` doubles: the history slots of the terms the scene's law
/// includes (those of an optional term it leaves off are not stored: a frictional scene without
/// rolling resistance keeps 4 doubles a contact, not 8); `optional` says which optional terms
/// (kOptional's bits). pair_springs.hpp turns a record into a ContactHistory and back.
struct PairSprings {
  std::vector<std::uint64_t> held;
  std::vector<std::vector<double>> block;  ///< per particle block, ascending pair, `slots` each
  unsigned optional = 0;                   ///< the optional terms whose slots records hold
  std::size_t slots = 0;                   ///< doubles a record (historyRecordSlots(optional))
};

/// Candidate contacts within R_i + R_j + skin, rebuilt when particles (or walls) have moved more
/// than the skin allows. Pairs are sorted by (first, second) so that the history of a pair can be
/// carried to the rebuilt list by a merge, without hashing. The first particles are stored as
/// compressed rows: the pairs (i, j) of particle i, j > i, are [rowStart[i], rowStart[i+1]) with
/// j = second[k]: 4 bytes a particle instead of 4 a pair (≈ 5 pairs a particle in a dense bed),
/// both in the list and in the transient of a rebuild, which holds the old list beside the new.
///
/// Particle blocks are runs of consecutive particles [blockParticle[b], blockParticle[b+1]) with
/// their pairs [blockPair[b], blockPair[b+1]) (buildPairBlocks, built with the list): the unit of
/// the force pass's work and of its ordered sums, and of the springs' storage (blockWord: the
/// first word of the block's bits in PairSprings::held).
struct NeighbourList {
  std::vector<std::uint32_t> rowStart;  ///< n + 1 entries: particle i's pairs
  std::vector<std::uint32_t> second;    ///< j of each candidate pair
  std::vector<std::uint32_t> blockParticle, blockPair, blockWord;
  PairSprings springs;  ///< empty on the frictionless path
  /// Per wall: candidate particles (sorted) and their tangential history. A mesh wall lists
  /// each candidate kMeshContacts times in a row, one entry per contact it may have with the
  /// mesh, and keeps each entry's contact normal (from the mesh towards the particle; zero for
  /// an entry holding no contact), by which a contact finds its entry again at the next step.
  std::vector<std::vector<std::uint32_t>> wallParticles;
  std::vector<std::vector<ContactHistory>> wallHistory;
  std::vector<std::vector<Vec3>> wallNormal;  ///< per wall; empty but for meshes with friction
  /// Per wall: a mesh's triangles binned by where they are at the build, each reaching the
  /// largest radius plus the skin and the model's reach (derived: rebuilt when missing).
  std::vector<TriangleGrid> meshGrid;
  /// Per wall: the pose of the mesh its grid was binned from (null where unknown). A fixed mesh
  /// keeps its pose, and its grid is kept from one build to the next while the reach is the same.
  std::vector<std::shared_ptr<const WallMesh>> meshGridPose;
  /// Per mesh wall: each candidate's triangles within its radius plus the skin and the model's
  /// reach at the build, every triangle it can touch before the next (candidate c, the entries
  /// [c, c+1)·kMeshContacts, holds [meshTriangleStart[w][c], meshTriangleStart[w][c + 1]) of
  /// meshTriangles[w]). Derived: empty where a list was not built here (read from a checkpoint,
  /// laid out by a split run, renumbered by an exchange), and then the grid's cell serves.
  std::vector<std::vector<std::uint32_t>> meshTriangleStart, meshTriangles;
  /// Particle positions at the last build, rounded to single precision [m]: half the memory of
  /// doubles, the one array a list has per particle. The staleness test adds the rounding's
  /// bound, referenceRounding, to the largest move it measures from them, so that it never
  /// misses a contact.
  std::vector<Eigen::Vector3f> referencePosition;
  double referenceRounding = 0.0;        ///< bound on |reference - position at the build| [m]
  std::vector<Vec3> referenceWallPoint;  ///< wall points at the last build [m]
  /// Each shell wall's Wall::travel at the last build [m] (planes: unused).
  std::vector<double> referenceWallTravel;
  double skin = 0.0;  ///< [m]
  bool valid = false;
  ForcePlan plan;  ///< derived from the lists (not checkpointed), built by the force pass
};

/// Splits n particles and the list's pairs into particle blocks (NeighbourList::blockParticle).
void buildPairBlocks(NeighbourList& list, std::size_t n);
/// The list's rows from the first particle of each pair (the checkpoint's layout) for n
/// particles; false (rows left empty) unless `first` ascends and every entry is below n.
bool rowsFromFirst(NeighbourList& list, const std::vector<std::uint32_t>& first, std::size_t n);
/// The first particle of each pair, the inverse of rowsFromFirst.
std::vector<std::uint32_t> firstOfPairs(const NeighbourList& list);

/// Walks a list's rows over consecutive runs of pairs, from a particle's first pair on, giving
/// each pair's first particle without a branch per pair: the rows that start in a run are
/// counted at their first pair, and a pair's particle is the previous pair's plus that count
/// (rows with no pairs start where the next one does). Use:
///   std::uint32_t i = walker.mark(begin, count, starts);
///   for (e = 0; e < count; ++e) { i += starts[e]; ... pair begin + e is (i, second[..]) ... }
///   walker.reached(i);
class RowWalker {
 public:
  /// From the first pair of `particle` (rowStart[particle]) on.
  RowWalker(const std::vector<std::uint32_t>& rowStart, std::size_t particle)
      : rowStart_(rowStart.data()),
        row_(static_cast<std::uint32_t>(particle)),
        last_(static_cast<std::uint32_t>(particle) - 1U) {}
  /// The longest run: the force pass's chunk of pairs.
  static constexpr std::size_t kMaxRun = 64;
  /// For the next run of pairs [begin, begin + count), count <= kMaxRun (the first run starts
  /// at the walker's particle's first pair): starts[e] = the rows starting at pair begin + e.
  /// Returns the particle before the run's first pair's (unsigned: it wraps before particle 0).
  std::uint32_t mark(std::size_t begin, std::size_t count, std::uint32_t (&starts)[kMaxRun]) {
    // The whole array, a constant size: a few vector stores rather than a string instruction.
    std::fill_n(starts, kMaxRun, 0U);
    const std::uint32_t end = static_cast<std::uint32_t>(begin + count);
    std::uint32_t row = row_;  // a local: stores to `starts` could alias the members
    // rowStart[n] is the pair count, so the walk ends there at the latest.
    for (; rowStart_[row] < end; ++row) ++starts[rowStart_[row] - begin];
    row_ = row;
    return last_;
  }
  /// The particle of the run's last pair, where the next run goes on.
  void reached(std::uint32_t particle) { last_ = particle; }

 private:
  const std::uint32_t* rowStart_;
  std::uint32_t row_;   ///< the next row whose start is not yet counted
  std::uint32_t last_;  ///< the particle of the last pair of the last run
};
/// Sets the list's reference positions to `position` rounded to single precision, and their
/// rounding bound referenceRounding.
void setReferencePositions(NeighbourList& list, const std::vector<Vec3>& position);
/// Builds the list for the current positions, carrying tangential history of surviving pairs:
/// the pairs within R_i + R_j + beyond + skin, the wall candidates within R_i + beyond + skin
/// (beyond: how far beyond touch the contact model acts, reachBeyondTouch). The candidate
/// search runs on `threads` threads (0: OpenMP's default); the list is the same for any count.
void rebuildNeighbourList(NeighbourList& list, const Particles& particles,
                          const std::vector<Wall>& walls, bool keepHistory, double beyond,
                          int threads = 1);
/// The two largest squared displacements of particles since the list's build [m²], first ≥
/// second: two particles close a gap by at most the sum of their displacements, so the list
/// holds every contact that can form while the two largest sum to less than the skin (one
/// particle thrown through a still bed no longer rebuilds the list at half the skin). Any cut
/// of the particles into parts, each added and then merged, gives the same two.
struct LargestMoves {
  double first = 0.0, second = 0.0;
  void add(double move2) {
    if (move2 > first) {
      second = first;
      first = move2;
    } else if (move2 > second) {
      second = move2;
    }
  }
  void merge(const LargestMoves& other) {
    add(other.first);
    add(other.second);
  }
};
/// True when some pair within the list's reach may have come into contact unseen, given the
/// two largest squared displacements of particles since the build (largestMoves).
bool neighbourListStale(const NeighbourList& list, const Particles& particles,
                        const std::vector<Wall>& walls, const LargestMoves& moves);
/// The two largest squared displacements since the build among the particles [begin, end)
/// (none if the list was built for another particle count: it is stale then anyway), of those
/// `owned` marks where it is given (1: this process's).
LargestMoves largestMoves(const NeighbourList& list, const Particles& particles, std::size_t begin,
                          std::size_t end, const std::vector<std::uint8_t>* owned = nullptr);

/// Resizes an array whose contents are rewritten before they are read (per-contact scratch),
/// allocating 1/8 more than asked instead of doubling, and giving memory back when the list
/// has shrunk to under half of it (a bed that starts on a lattice has ~6 candidate pairs a
/// particle, settled ~4.5): the memory follows the contacts, not their historical maximum.
template <class T>
void resizeScratch(std::vector<T>& v, std::size_t size) {
  if (size > v.capacity() || v.capacity() > 2 * size + 1024) {
    std::vector<T> fresh;
    fresh.reserve(size + size / 8);
    v.swap(fresh);
  }
  v.resize(size);
}

/// Gives a per-particle array exactly `size` elements (value-initialised when it changes size):
/// the particles do not come and go, so there is nothing to grow into, and no slack is kept.
template <class T>
void resizeExactly(std::vector<T>& v, std::size_t size) {
  if (v.size() != size) std::vector<T>(size).swap(v);
}

// ---- 2. Integrator derivatives ------------------------------------------------------------

/// Time derivatives beyond the velocity of one kind of motion (translation or rotation):
/// acceleration, and for Gear the 3rd, 4th and 5th derivatives (unscaled, so the step may change).
struct Derivatives {
  std::vector<Vec3> d2, d3, d4, d5;
};

// ---- 3. Energy accumulators ---------------------------------------------------------------

/// One force evaluation, summed over contacts: each energy account's value (kEnergySlotTable:
/// the stored energy [J], a power [W] or an increment [J], by its kind; Slip slots stay 0).
struct ContactPowers {
  double energy[kEnergySlots] = {};
  double wallPower = 0;  ///< work rate of the walls' velocity on the particles [W]
  std::size_t particleContacts = 0;
  std::size_t wallContacts = 0;
  std::uint64_t tangentialEvaluations = 0;
};

/// One part's share of a force pass's sums with SimulationConfig::exactSums: exact (ExactSum),
/// so that the totals are the same bits however the contacts are split among threads, blocks or
/// processes. A particle's pair energies are summed in its contact order (ascending second
/// particle) and that subtotal is added exactly; each wall contact's energies, power and push
/// are added exactly one by one.
struct ExactPowers {
  ExactSum energy[kEnergySlots];
  ExactSum wallPower;
  std::vector<ExactSum> reaction;  ///< 3 per wall: x, y, z of the push on it [N]
  std::size_t particleContacts = 0;
  std::size_t wallContacts = 0;
  std::uint64_t tangentialEvaluations = 0;
  /// Empties the sums for `walls` walls.
  void clear(std::size_t walls);
  /// Adds another part's sums.
  void merge(const ExactPowers& other);
  /// Merges every rank's sums into this one (the same on every rank).
  void mergeOverRanks(const Communicator& ranks);
};

/// Results of the force pass kept between its phases and its blocks (ForcePlan).
struct ContactScratch {
  /// Per crossing pair (friction only): its stored spring as it was before the pass, which the
  /// second particle's part reads while the first's part advances the stored one.
  std::vector<ContactHistory> crossingSpring;
  /// Per thread of the pass (friction only): the springs of its block not yet read when the
  /// block's new springs would overwrite them (force_pass.cpp, SpringCursor).
  std::vector<std::vector<double>> springsSetAside;
  std::vector<ContactPowers> blockPowers;  ///< per particle block (in double)
  std::vector<Vec3> blockReaction;         ///< per particle block and wall: push on the wall [N]
  std::vector<ExactPowers> partPowers;     ///< per part of the pass (with exactSums)
};

/// The ledger since the start, per energy account: Dissipated and Work integrated (trapezoid
/// on the powers), Supplied summed; and each Stored account's value at the start, against which
/// its group's Slip is reckoned.
struct EnergyAccumulators {
  double account[kEnergySlots] = {};
  double initialStored[kEnergySlots] = {};
  double wallWork = 0;
  double initialPotential = 0;  ///< -Σ m g·x at the start [J]
  double exchanged = 0;         ///< EnergyBalance::exchanged [J]
};

/// The particles' comings and goings (Simulation::exchangeParticles): counts, and masses summed
/// exactly so that start + inserted − removed − held is zero to the bit.
struct ExchangeTally {
  ExactSum startMass, insertedMass, removedMass;
  ExactSum net;  ///< start + inserted − removed, term by term
  std::uint64_t inserted = 0, removed = 0;
  std::vector<std::uint64_t> insertedBy;  ///< per source
  /// Whether the run has exchanged any particle (the checkpoint's section is written then).
  bool any() const { return inserted > 0 || removed > 0; }
};

// ---- 4. The state -------------------------------------------------------------------------

/// A run split by space among processes (Simulation::splitAmong, domain_split.hpp): the domains,
/// the particles' global ids, and who sends which ghosts to whom after each prediction.
struct DomainSplit {
  std::shared_ptr<const DomainMap> domains;  ///< null: the run is not split by space
  std::vector<std::uint64_t> globalId;       ///< per particle held, ascending
  /// Ghosts are the particles within this of a domain at a rebuild: the reach of the largest
  /// pair, 2 R_max + skin, and a hair [m].
  double halo = 0.0;
  /// Per rank: the particles this rank owns that rank holds as ghosts, and the ghosts here that
  /// rank owns, both ascending (so that messages need no ids).
  std::vector<std::vector<std::uint32_t>> sendTo, receiveFrom;
  std::uint64_t pairs = 0;  ///< the whole run's candidate pairs
  /// Load balance: when the rank owning the most particles owns more than `rebalanceAbove`
  /// times the mean at a rebuild, the next rebuild moves the domains first
  /// (DomainMap::rebalanced); the bar then stands a little above the imbalance that move left.
  bool rebalanceDue = false;
  bool justMoved = false;  ///< the domains moved at this rebuild
  double rebalanceAbove = 1.10;
};

struct SimulationState {
  SimulationConfig config;
  /// Between all threads and one, for a run left to OpenMP's count (config.threads = 0): the
  /// faster now (thread_governor.hpp; not checkpointed, the results do not depend on it).
  ThreadGovernor governor;
  Particles particles;
  std::vector<Wall> walls;
  /// The clock is timeOrigin + stepsSinceOrigin·Δt rather than a running sum, so that sampled
  /// times carry no accumulated round-off.
  double timeOrigin = 0.0;
  std::uint64_t stepsSinceOrigin = 0;
  std::uint64_t steps = 0;
  bool frictional = false;
  /// The switches of granular/engine_studies.hpp (not checkpointed).
  bool rebuildEveryStep = false;
  bool stepLimitDisabled = false;
  double estimateScale = 1.0;  ///< studies::scaleSpectrumEstimate
  ContactScale contactScale;
  /// The step asked for (fixed) or chosen (automatic) [s]; config.timeStep is the next step's,
  /// shorter than this one when advanceTo lands on a time. 0: config.timeStep.
  double targetStep = 0.0;
  std::uint64_t stepsSinceCheck = 0;  ///< steps since the step was last checked
  /// The fewest steps between two checks at rebuilds of an automatic step (stepCheckDue):
  /// above its floor, doubled at each check that leaves the step within 1 %, up to
  /// StepControl::recheckSteps (0: the least, 25); set by its floor with the network's margin,
  /// 25; else 0 (every 10).
  std::uint64_t checkGap = 0;
  StepCheck stepCheck;                       ///< the last check
  NetworkCalibration calibration;            ///< the estimate against the bound
  studies::StepControlCost stepControlCost;  ///< the reviews inside the steps (not checkpointed)
  /// The state at the last check whose step came from the estimate (rollback.hpp; not
  /// checkpointed: a restored run keeps it again where it starts at such a check).
  RollbackSlot rollback;
  /// `steps` when the stepping call began (SteppingCall, rollback.hpp); kBetweenCalls outside.
  std::uint64_t stepsAtCallStart = kBetweenCalls;

  // Per-step accumulators. (1/m and 1/I are recomputed where needed: a division per particle
  // and step costs less than 16 bytes per particle of memory traffic.)
  std::vector<Vec3> force, torque;  ///< contact forces [N] and torques [N m] of the last pass
  Derivatives translation;          ///< d2 = acceleration [m/s²]
  /// d2 = angular acceleration [rad/s²]; frictional only. Gear's rotational "position" ∫ω dt
  /// is not kept: nothing depends on it (spheres have no orientation that matters).
  Derivatives rotation;

  NeighbourList neighbours;
  ContactScratch contactScratch;
  std::vector<LargestMoves> rangeMoves;  ///< per thread of the predictor: its largest moves
  /// Simulation::run's steps but the last predict the next step in their corrector's loop: the
  /// state then holds the next step's prediction (never seen outside run) and whether a
  /// predicted position was not finite.
  bool predictedAhead = false, predictedBroken = false;
  /// A run split among processes (Simulation::setOwnership): which particles this process
  /// owns (1) or holds as ghosts (0), empty for all; and the ranks its sums are merged over
  /// (null: this process alone).
  std::vector<std::uint8_t> owned;
  std::shared_ptr<const Communicator> ranks;
  DomainSplit split;
  /// The step's hooks for how the run is shared among processes (run_partition.hpp): the
  /// whole run's, or the split's once splitAmong has split it.
  const RunPartition* partition = &wholeRun();
  ContactPowers powers;  ///< of the last force evaluation
  EnergyAccumulators energy;
  ExchangeTally exchange;
  StepCounters counters;
};

/// Sums over the particles, exact (ExactSum): the same bits whatever the particles' split.
struct ParticleSums {
  ExactSum translational;  ///< Σ ½ m v² [J]
  ExactSum rotational;     ///< Σ ½ I ω² [J] (frictional only; 0 otherwise)
  ExactSum potential;      ///< Σ m g·x [J]
};
/// Over the particles this process owns, merged over the ranks.
ParticleSums particleSums(const SimulationState& s);

/// The engine's own files' way into a Simulation's state (checkpoint I/O, the network's bound).
struct SimulationAccess {
  static const SimulationState& state(const Simulation& sim) { return *sim.state_; }
  static Simulation make(std::unique_ptr<SimulationState> s) { return Simulation(std::move(s)); }
};

/// The threads the engine's passes take (0: all of OpenMP's): the configured count, or the
/// governor's choice where none is configured.
inline int passThreads(const SimulationState& s) {
  return s.config.threads > 0 ? s.config.threads : s.governor.threads();
}

}  // namespace granular
