#pragma once
/// The time-stepping engine: contact search, contact forces (docs/physics.md §1), integration,
/// energy bookkeeping and wall reactions. One step runs the passes
///   predict → move walls → update neighbour lists → contact forces → correct → measure.
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "granular/communicator.hpp"
#include "granular/contact_theory.hpp"
#include "granular/domain_map.hpp"
#include "granular/material.hpp"
#include "granular/particles.hpp"
#include "granular/vec3.hpp"
#include "granular/wall.hpp"

namespace granular {

/// Time integration scheme.
enum class Integrator {
  Gear5,           ///< Gear's 5th-order (6-value) predictor-corrector, the paper's choice
  VelocityVerlet,  ///< velocity Verlet, forces evaluated at the half-step velocity
};

/// The largest time step the engine accepts for this integrator and stiffest contact [s]:
/// kMaxStepFractionVerlet or kMaxStepFractionGear5 of the contact duration.
double maxStableStep(const ContactScale& scale, Integrator integrator);
/// Throws ConfigError, naming the limit, the contact duration and the integrator, when `dt` is
/// above maxStableStep (the engine's own check; the scene loader uses it too).
void requireStableStep(double dt, const ContactScale& scale, Integrator integrator);
/// The largest tangential damping γt [1/s] the engine accepts at step `dt` [s]: the bed's
/// dashpots, rate kTangentialContactsAtOnce · kTangentialRatePerContact · γt, must stay within
/// the integrator's explicit stability (kDamperStabilityGear5, kDamperStabilityVerlet).
double maxTangentialDamping(double dt, Integrator integrator);
/// Throws ConfigError, naming the limit, the step and the integrator, when the material has
/// friction and its γt is above maxTangentialDamping (without friction γt acts on nothing).
void requireStableTangentialDamping(const Material& material, double dt, Integrator integrator);

/// What a run does when its fixed time step is above the step the contact network allows.
enum class OnUnstable {
  Stop,  ///< the run stops with a NumericalError naming the step, the bound and the particle
  Warn,  ///< the run goes on; StepCounters::unstableChecks counts the checks that found it so
};

/// How the engine chooses its time step (docs/physics.md §2.16). A fixed step is checked against
/// the network's stable step (network_step.hpp) at the start and whenever the step is checked;
/// an automatic one is re-chosen then. The step is checked when the neighbour list is rebuilt
/// (at most every 10 steps; a fixed step every 25, and an automatic one above its floor every
/// 25, then twice as far apart at each check that leaves it within 1 %) and at least every
/// `recheckSteps` steps, never inside a step.
struct StepControl {
  bool automatic = false;  ///< Δt chosen from the live contacts (time_step = "auto")
  /// Δt = safety × the network's stable step, (0, 1]: the bound's, or with velocity Verlet the
  /// spectrum's estimate where the bound (1.3–1.5 × the exact ω_max on settled beds) would
  /// refuse it (docs/physics.md §2.16). The 10 % margin is for what the linearisation leaves
  /// out (contacts that open or close inside a step) and for the network stiffening between
  /// two checks; a step from the estimate that grows a mode all the same is undone.
  double safety = 0.9;
  /// Accuracy floor: Δt ≤ t_c / N, t_c the stiffest contact's duration (contactScale()), so
  /// that an impact is resolved in at least N steps however stable a longer step would be.
  /// 10: restitution within 3 % (damped Hooke) and 0.5 % (Hertz) (bench/RESULTS.md). It is
  /// for impacts: where the kinetic energy of the contacts' relative motion is under 1 % of what
  /// their springs store, it stretches and the network's step governs (docs/physics.md §2.16).
  double contactResolution = 10.0;
  OnUnstable onUnstable = OnUnstable::Stop;  ///< for a fixed step
  std::uint64_t recheckSteps = 100;          ///< the longest run of steps between checks
};

/// Everything the engine needs besides the particles and walls.
struct SimulationConfig {
  Material material;                     ///< particle and wall material
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);  ///< gravitational acceleration g [m/s²]
  Integrator integrator = Integrator::Gear5;
  /// Δt [s]: fixed, refused above the network's stable step (or, with no contact yet, above
  /// maxStableStep()); with step.automatic the first step, after that the chosen one.
  double timeStep = 1e-4;
  StepControl step;
  double skin = 0.0;  ///< neighbour-list skin [m]; 0 picks 0.3·smallest radius
  /// Largest expected approach speed [m/s] (Hertz only: its contact is shorter at a higher
  /// speed): the binary step limit and the accuracy floor use it, and the step control's checks
  /// use the faster of it and the speeds they measure.
  double impactSpeed = 1.0;
  /// Threads for the force pass and the integrator [-]; 0 = OpenMP's default (OMP_NUM_THREADS
  /// or all cores). Results are identical, bit for bit, for any count.
  int threads = 0;
  /// The contact energies, their powers and the walls' reactions summed exactly (ExactSum,
  /// docs/physics.md §2.9): the same bits however the particles are split, among threads or
  /// among processes, which a run on several processes needs. Off, they are summed in double,
  /// block by block, which is the same for any thread count only and cheaper (bench/RESULTS.md).
  /// The particles' motion does not depend on it; sums over the particles (kinetic and
  /// potential energy) are always exact.
  bool exactSums = false;
  /// The smallest radius the run will ever hold [m], where particles inserted later
  /// (Simulation::exchangeParticles) may be smaller than those it starts with, or it starts
  /// with none: the accuracy floor, the skin and the step's limit with no contact follow it.
  /// 0: the starting particles' smallest (then there must be some).
  double smallestRadius = 0.0;
};

/// One account of the contact energy ledger, as its term declares it (granular/contact_terms/).
struct EnergyAccount {
  std::string_view column;  ///< the time series' column, e.g. "dissipated_normal_J"
  EnergyKind kind;
  double value = 0;  ///< [J]
};

/// Energy bookkeeping. Stored energies are instantaneous; dissipation and work are accumulated
/// since the start (trapezoidal rule on the powers). For an exact integrator `total()` is constant;
/// its drift measures the integrator's truncation error.
struct EnergyBalance {
  double kineticTranslational = 0;  ///< Σ ½ m v² [J]
  double kineticRotational = 0;     ///< Σ ½ I ω² [J]
  /// The accounts of the contact terms the scene uses, in column order
  /// (energyColumns(material): stored, dissipated, slip, supplied) [J].
  std::vector<EnergyAccount> contact;
  double gravityWork = 0;  ///< work of gravity on the particles, Σ m g·(x - x₀) [J]
  double wallWork = 0;     ///< work of the moving walls on the particles [J]
  /// Kinetic and contact-stored energy the particles inserted brought in minus what those
  /// removed took out (Simulation::exchangeParticles), since the start [J]. Gravity's work on
  /// a removed particle while it was held stays in gravityWork.
  double exchanged = 0;

  /// The account with this column ("elastic_tangential_J"); throws std::out_of_range if the
  /// contact model declares none.
  double of(std::string_view column) const {
    for (const EnergyAccount& a : contact) {
      if (a.column == column) return a.value;
    }
    throw std::out_of_range("no energy account '" + std::string(column) + "'");
  }
  /// The accounts of one kind, summed [J].
  double sum(EnergyKind kind) const {
    double total = 0;
    for (const EnergyAccount& a : contact) total += a.kind == kind ? a.value : 0.0;
    return total;
  }
  /// Kinetic + stored + dissipated (slip included) − supplied − work of gravity and walls:
  /// constant up to the integrator's truncation error [J].
  double total() const {
    double sum = kineticTranslational + kineticRotational;
    for (const EnergyAccount& a : contact)
      sum += a.kind == EnergyKind::Supplied ? -a.value : a.value;
    return sum - gravityWork - wallWork - exchanged;
  }
  double kinetic() const { return kineticTranslational + kineticRotational; }
};

/// Bytes held by a Simulation's arrays (their capacity), by what they are for. Transient
/// buffers of a neighbour-list rebuild are not included: they live only during the rebuild.
struct MemoryUse {
  std::size_t particles = 0;   ///< positions, velocities, ω, radii, masses [B]
  std::size_t integrator = 0;  ///< forces, torques and the integrator's derivatives [B]
  std::size_t neighbours = 0;  ///< candidate pairs, wall candidates, reference positions [B]
  std::size_t history = 0;     ///< tangential springs (frictional only) [B]
  std::size_t forcePlan = 0;   ///< how the force pass splits its work among threads [B]
  std::size_t scratch = 0;     ///< force-pass results of pairs straddling two threads [B]
  /// The state an automatic step from the spectrum's estimate keeps to return to, all of the
  /// above again (docs/physics.md §2.16) [B].
  std::size_t rollback = 0;
  std::size_t total() const {
    return particles + integrator + neighbours + history + forcePlan + scratch + rollback;
  }
};

/// Counters of the last step and of the run.
struct StepCounters {
  /// Particle pairs with overlap > 0 in the last step's force evaluation (at the predicted
  /// state), those the no-pull clamp holds at zero force included [-].
  std::size_t particleContacts = 0;
  std::size_t wallContacts = 0;             ///< particle-wall contacts counted alike [-]
  std::size_t neighbourPairs = 0;           ///< candidate pairs in the neighbour list
  std::uint64_t rebuilds = 0;               ///< neighbour-list rebuilds since the start
  std::uint64_t tangentialEvaluations = 0;  ///< tangential force evaluations since the start
  std::uint64_t stepChecks = 0;             ///< checks of the step against the network
  /// Checks that found a fixed step above the network's (OnUnstable::Warn) [-].
  std::uint64_t unstableChecks = 0;
  double worstStepRatio = 0;  ///< the largest Δt / network step those checks found [-]
  /// The fastest closing speed any check found (StepCheck::approachSpeed) [m/s].
  double fastestApproach = 0;
  /// The smallest and largest step taken since the start [s] (with step.automatic, the chosen
  /// range; steps shortened to land on a time included).
  double smallestStep = 0, largestStep = 0;
  /// Growing modes an automatic step from the spectrum's estimate met (docs/physics.md §2.16):
  /// those undone, the steps since the last check taken again at a shorter step, and those
  /// kept, where the caller had seen the state since that check (the step shrank from then on,
  /// and the energy they created stays in the ledger's residual) [-].
  std::uint64_t rollbacks = 0, keptGrowths = 0;
};

/// The last check of the step against the network (StepControl).
struct StepCheck {
  double time = 0;           ///< when [s]
  double networkStep = 0;    ///< the network's stable step [s] (+∞ with no contacts)
  double omegaMax = 0;       ///< the network's frequency bound [rad/s]
  double dampingRatio = 0;   ///< Γ / (2 ω_max) [-]
  std::size_t particle = 0;  ///< whose row set ω_max
  std::size_t contacts = 0;  ///< touching contacts, and those about to form, counted
  /// t_c / N [s], t_c at the faster of approachSpeed and impactSpeed; stretched (to +∞) where
  /// no contact is an impact (StepControl::contactResolution).
  double accuracyStep = 0;
  /// The fastest closing speed among the contacts touching or about to touch [m/s]: a Hertz
  /// contact's duration, hence the accuracy floor, follows it where it exceeds the expected
  /// config.impactSpeed.
  double approachSpeed = 0;
  double chosenStep = 0;  ///< the step taken from then on [s]
  /// Whether ω_max and the damping ratio are the Lanczos estimate's (the bound scaled by its
  /// calibration, NetworkCalibration) rather than the bound's: where the bound refuses the
  /// step asked for (velocity Verlet).
  bool estimated = false;
};

/// The network's spectrum estimated against its bound at one check (docs/physics.md §2.16):
/// the bound's ω_max and Γ then and Lanczos's (granular/network_spectrum.hpp). Between
/// calibrations each check scales its bound by estimate / bound, and calibrates again where
/// the bound has moved by more than 5 % (ω) or 10 % (Γ) since: the bound follows the network,
/// the ratio of the two is slow (1.44–1.46 on the paper's stage 2). 0: none yet.
struct NetworkCalibration {
  double boundOmega = 0, boundDamping = 0;  ///< [rad/s], [1/s]
  double omega = 0, damping = 0;            ///< the estimate's [rad/s], [1/s]
  /// Growing modes met on this calibration's steps; each raised `omega` and `damping` by
  /// 1 / 0.8, but for a first one that the accuracy floor's return shortened anyway
  /// (docs/physics.md §2.16).
  std::uint32_t rollbacks = 0;
};

/// The particles a run has held, taken in and let out (Simulation::exchangeParticles).
struct ParticleTally {
  std::uint64_t held = 0;      ///< particles now [-]
  std::uint64_t inserted = 0;  ///< inserted since the start [-]
  std::uint64_t removed = 0;   ///< removed since the start [-]
  double heldMass = 0;         ///< Σ m of the particles now [kg]
  double startMass = 0;        ///< Σ m of the particles the run started with [kg]
  double insertedMass = 0;     ///< Σ m inserted since the start [kg]
  double removedMass = 0;      ///< Σ m removed since the start [kg]
  /// start + inserted − removed − held, each sum exact and the difference rounded once: zero,
  /// exactly, unless a particle was made or lost outside an exchange [kg].
  double massBalance = 0;
};

/// What one exchange does to the particles: removes some and inserts others.
struct ParticleExchange {
  /// Indices (of the whole state, Simulation::wholeState(), in a split run) of the particles
  /// to remove, ascending and distinct.
  std::vector<std::size_t> remove;
  /// The particles to insert, appended after those that stay; they start with no contact
  /// history and at rest in rotation unless given a spin.
  Particles insert;
  /// Which source inserts them (Simulation::insertedBy counts per source) [-].
  std::size_t source = 0;
};

/// One contact as seen from particle i, for stress averaging (Eq. 1), figures and the
/// per-contact files. The other body is a particle j or a wall: ask isWall(), then read
/// otherParticle() or wall().
struct ContactView {
  /// What particle i touches.
  enum class Other : std::uint8_t { Particle, Wall };

  std::size_t particle = 0;           ///< i
  Other otherKind = Other::Particle;  ///< a particle or a wall
  /// The other body's index: j in Simulation::particles(), or the wall's in walls().
  std::size_t otherIndex = 0;
  Vec3 point;          ///< contact point C_ij [m]
  Vec3 force;          ///< F_ij, force on i [N]
  Vec3 normal;         ///< unit normal from i towards j, or out of i into the wall [-]
  double overlap = 0;  ///< h > 0 [m]; negative: a gap a term acting beyond touch spans (a
                       ///< liquid bridge), the point then midway across it

  bool isWall() const { return otherKind == Other::Wall; }
  /// The bodies touch (h > 0); false for a gap that a term acting beyond touch spans.
  bool touching() const { return overlap > 0.0; }
  /// j, for a contact with a particle (!isWall()).
  std::size_t otherParticle() const { return otherIndex; }
  /// The wall's index in Simulation::walls(), for a contact with a wall (isWall()).
  std::size_t wall() const { return otherIndex; }
};

struct SimulationState;  // private: core/engine/src/simulation_state.hpp

class Simulation {
 public:
  /// Validates the configuration (ConfigError on a bad value or an unstable time step) and
  /// computes the initial forces.
  Simulation(Particles particles, std::vector<Wall> walls, const SimulationConfig& config);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  /// Advances one time step.
  void step();
  /// Advances to simulated time `t` [s] (>= time()): with step.automatic, in steps of the chosen
  /// Δt, the last ones of each stretch between checks shortened alike to land on t; with a fixed
  /// step, in whole steps, the last one shortened. The clock reads t exactly afterwards.
  void advanceTo(double t);
  /// advanceTo(t), asking `proceed` every kStepsBetweenAsks steps whether to go on; where it
  /// says no, the run stops there, between two steps, short of t, its state corrected and its
  /// step the one asked for or chosen (a state that steps on or is saved as any other). Returns
  /// whether it reached t. For a driver that a user may interrupt (Python's Ctrl-C).
  bool advanceTo(double t, const std::function<bool()>& proceed);
  static constexpr std::uint64_t kStepsBetweenAsks = 32;
  /// Advances n steps: the same bits as n calls of step(), faster, as each step but the last
  /// predicts the next one in its corrector's loop (one pass over the integrator's arrays a
  /// step instead of two). Drivers that look at the state only every so often should prefer it.
  void run(std::uint64_t steps);
  /// run(steps), stopping before a step that would end after t [s] (an automatic step may grow
  /// at any check, so how many steps fit before t is known only step by step). The same bits
  /// as run(k) for the k steps it takes; returns k.
  std::uint64_t runBefore(std::uint64_t steps, double t);

  double time() const;              ///< simulated time [s]
  void setTime(double t);           ///< resets the clock (a stage's own time scale)
  std::uint64_t stepCount() const;  ///< steps taken since construction
  const SimulationConfig& config() const;
  const Particles& particles() const;
  const std::vector<Wall>& walls() const;
  /// Adds a wall (e.g. the top wall of stage 2); returns its index.
  std::size_t addWall(const Wall& wall);
  /// Changes the time step Δt [s] from the next step on (e.g. to rerun a restored state at
  /// another step); refused like the constructor refuses it (ConfigError). Gear's derivatives
  /// are stored unscaled, so the change needs no rescaling.
  void setTimeStep(double dt);
  /// Changes the material (E, ν, G, μ, damping, normal law) from the next step on, e.g. from a
  /// front end that steers a run. Refused (ConfigError, nothing changed) on a value out of range
  /// or if the current step is above the new contacts' limit. Switching friction on starts the
  /// rotations at rest and the springs unstretched; switching it off drops them. The
  /// accelerations are recomputed under the new law. The energy balance sees the jump of the
  /// stored elastic energy a stiffness change causes. Density changes do not re-mass particles.
  void setMaterial(const Material& material);
  /// Continues with another integrator from the current state (e.g. to compare Gear and Verlet
  /// from one restored checkpoint, contact history included). Gear → Verlet keeps the
  /// acceleration, all Verlet needs; Verlet → Gear starts Gear's higher derivatives at zero, as
  /// a new simulation does. Refused (ConfigError) if the current step is above the new
  /// integrator's limit.
  void setIntegrator(Integrator integrator);
  /// Threads for the following steps (0 = OpenMP's default); results do not depend on it.
  void setThreads(int threads);
  /// Sums the energies and wall reactions exactly from the next force pass on
  /// (SimulationConfig::exactSums); the motion is the same bits either way.
  void setExactSums(bool exact);
  /// For a run split among processes: `owned[i]` (one per particle) says whether this process
  /// owns particle i (1) or holds a copy of it as a ghost (0); `ranks` are the processes whose
  /// sums are merged. Each contact is then accounted for once over the ranks: a pair by the
  /// owner of its first particle (the lower index), a wall contact by its particle's owner;
  /// the energies, powers, wall reactions, contact counts and sums over the particles are
  /// merged over `ranks` (exact sums, which this switches on), so every rank holds the whole
  /// run's. Before the first step it also re-takes the ledger's starting values. Throws
  /// ConfigError unless `owned` has one entry per particle and `ranks` is given.
  void setOwnership(std::vector<std::uint8_t> owned, std::shared_ptr<const Communicator> ranks);
  /// Splits the run by space among `ranks` (collective: every rank calls it on the same whole
  /// state): from then on each rank holds the particles `domains` gives it and, as ghosts, the
  /// others within the reach of a contact of its domain, in ascending global id (the index in
  /// the whole state). Each step the ghosts take their owners' motion, and at each rebuild of
  /// the neighbour list the particles move to the ranks where they now belong with their
  /// contact springs. The motion, the springs, the energies, the walls' reactions and the
  /// counters are the same bits as one process's on any number of ranks (docs/physics.md
  /// §2.9). particles() is then this rank's share; wholeState() gathers the run. Throws
  /// ConfigError if the domains are not one per rank, or on more than 64 walls.
  void splitAmong(std::shared_ptr<const DomainMap> domains,
                  std::shared_ptr<const Communicator> ranks);
  /// The whole run's state (collective in a split run: every rank gets it, as one process
  /// would hold it); a copy otherwise.
  Simulation wholeState() const;
  /// The global id of particle i of particles(): its index in the whole state.
  std::uint64_t globalId(std::size_t i) const;
  /// Whether this rank owns particle i of particles() (always, unless the run is split).
  bool owns(std::size_t i) const;
  /// The ranks a split run is shared among (splitAmong); null for a run in one process.
  const Communicator* ranks() const;
  /// Removes and inserts particles between two steps (a silo's outlet and its filling):
  /// `decide` gets the whole run's particles (gathered in a split run, where every rank calls
  /// this with the same `decide`) and says what to remove and insert. The surviving pairs and
  /// wall contacts keep their springs; the contact forces and accelerations are re-evaluated at
  /// the current state; the energy ledger's `exchanged` account takes the kinetic and stored
  /// energy that came and went, so the balance stays closed; the tallies count the particles
  /// and their mass exactly (particleTally). Throws ConfigError, nothing changed, on an index
  /// out of range or not ascending, or on an inserted particle that is not valid (radius, mass,
  /// finite motion; smaller than SimulationConfig::smallestRadius). Particle indices after it
  /// are those of the survivors in their order, then the inserted ones.
  void exchangeParticles(const std::function<ParticleExchange(const Particles& whole)>& decide);
  /// Whether any particle's position passes `test` (collective in a split run: each rank tests
  /// the particles it owns). Lets a caller skip an exchange with nothing to do, which in a
  /// split run would gather the whole state for nothing.
  bool anyParticleWhere(const std::function<bool(const Vec3& position)>& test) const;
  /// The particles held, inserted and removed, and their masses (collective in a split run).
  ParticleTally particleTally() const;
  /// Particles inserted by `source` since the start (ParticleExchange::source) [-].
  std::uint64_t insertedBy(std::size_t source) const;
  /// Takes a wall away (a gate opened): it touches nothing from the next step on and keeps its
  /// index and name, with a zero reaction (Wall::removed). Its contacts' springs are dropped.
  void removeWall(std::size_t wall);
  /// Sets a wall's prescribed velocity [m/s]; a changed one re-chooses an automatic step.
  void setWallVelocity(std::size_t wall, const Vec3& velocity);
  /// Index of the wall with this name, or -1.
  long findWall(const std::string& name) const;

  /// The step control (time_step = "auto", safety, accuracy floor, on_unstable); the step is
  /// checked, and with step.automatic chosen, at once. Refused like setTimeStep (ConfigError).
  void setStepControl(const StepControl& control);
  /// The last check of the step against the network.
  const StepCheck& stepCheck() const;

  /// Stiffest contact and its duration: the accuracy floor's t_c, and the step's limit while
  /// the scene has no contact.
  const ContactScale& contactScale() const;
  /// True when the tangential force and rotations are integrated (μ > 0).
  bool frictional() const;

  EnergyBalance energy() const;
  double kineticEnergy() const;  ///< translational + rotational [J]
  const StepCounters& counters() const;
  /// Acceleration of particle i at the current state (forces / m + g) [m/s²].
  Vec3 acceleration(std::size_t i) const;

  /// Calls `visit` for every contact at the current state (overlap > 0), once from each side of
  /// a particle pair and once for each particle-wall contact; with a term that acts beyond touch
  /// (a liquid bridge) also for each gap it spans (overlap <= 0: ContactView::touching() is
  /// false).
  void forEachContact(const std::function<void(const ContactView&)>& visit) const;
  /// Σ_j F_ij per particle (contact forces only, walls included) from the same evaluation as
  /// forEachContact [N].
  std::vector<Vec3> netContactForces() const;

  /// Neighbour-list skin [m] (>= 0; 0 picks 0.3 × the smallest radius). A performance knob
  /// only: the list is rebuilt at the next step with the contact history kept, and the contact
  /// forces do not depend on it (tests/test_simulation.cpp).
  void setSkin(double skin);
  double skin() const;  ///< the skin in use [m]

  /// Memory held by the state's arrays [B].
  MemoryUse memoryUse() const;

  /// FNV-1a hash of positions, velocities and angular velocities, bit for bit.
  std::uint64_t stateHash() const;

 private:
  friend struct SimulationAccess;   // the engine's own files (core/engine/src/simulation_state.hpp)
  friend struct SimulationStudies;  // the switches of granular/engine_studies.hpp
  explicit Simulation(std::unique_ptr<SimulationState> state);
  std::unique_ptr<SimulationState> state_;
};

}  // namespace granular
