/// Simulation: set-up, the step (its passes in order), the clock and the accessors. The
/// validation, the step's check, the setters that re-shape the state, the energy ledger, the
/// queries and the run's sharing among processes have their own files beside this one.
#include "granular/simulation.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>

#include "config_validation.hpp"
#include "energy_ledger.hpp"
#include "force_pass.hpp"
#include "granular/error.hpp"
#include "integrators.hpp"
#include "rollback.hpp"
#include "simulation_passes.hpp"
#include "simulation_state.hpp"
#include "step_check.hpp"
#include "wall_motion.hpp"

namespace granular {

// ---- Passes the set-up and the setters share ----------------------------------------------

void rebuildList(SimulationState& s) {
  s.partition->beforeRebuild(s);
  rebuildNeighbourList(s.neighbours, s.particles, s.walls, s.frictional,
                       reachBeyondTouch(s.config.material), passThreads(s));
  s.partition->afterRebuild(s);
  ++s.counters.rebuilds;
}

void startAccelerations(SimulationState& s) {
  const Particles& p = s.particles;
  for (std::size_t i = 0; i < p.size(); ++i) {
    s.translation.d2[i] = s.force[i] * (1.0 / p.mass[i]) + s.config.gravity;
    if (s.frictional) s.rotation.d2[i] = s.torque[i] * (1.0 / p.inertia(i));
  }
}

// ---- Set-up -------------------------------------------------------------------------------

Simulation::Simulation(Particles particles, std::vector<Wall> walls, const SimulationConfig& config)
    : state_(std::make_unique<SimulationState>()) {
  validateScene(config, particles, walls);
  SimulationState& s = *state_;
  s.config = config;
  s.particles = std::move(particles);
  s.walls = std::move(walls);
  s.frictional = config.material.hasFriction();
  const Particles& p = s.particles;
  const std::size_t n = p.size();
  const double rMin = smallestRadius(p, config);
  for (double m : p.mass) {
    s.exchange.startMass.add(m);
    s.exchange.net.add(m);
  }

  // The stiffest binary contact: the accuracy floor's duration, and the step's limit while
  // there is no contact (physics.md §2.7, §2.16).
  s.contactScale = stiffestContact(config.material, rMin, config.impactSpeed);
  s.neighbours.skin = config.skin > 0 ? config.skin : 0.3 * rMin;

  const bool gear = config.integrator == Integrator::Gear5;
  auto allocate = [&](Derivatives& d) {
    d.d2.assign(n, Vec3::Zero());
    if (gear) {
      d.d3.assign(n, Vec3::Zero());
      d.d4.assign(n, Vec3::Zero());
      d.d5.assign(n, Vec3::Zero());
    }
  };
  allocate(s.translation);
  if (s.frictional) {
    allocate(s.rotation);
  } else {
    // The frictionless path never touches rotations: they stay exactly as given.
    s.particles.angularVelocity.assign(n, Vec3::Zero());
  }

  rebuildNeighbourList(s.neighbours, s.particles, s.walls, s.frictional,
                       reachBeyondTouch(s.config.material), s.config.threads);
  ++s.counters.rebuilds;
  startLedger(s);  // the initial forces too; dt = 0 leaves the springs as they are
  startAccelerations(s);
  // The step: chosen from the network, or a fixed one refused above it (physics.md §2.16).
  if (config.step.automatic) {
    checkStep(s);
  } else {
    // The approach speeds it measured are the run's first (StepCounters::fastestApproach).
    const StepCheck c = requireAllowedStep(s, config.timeStep, config.integrator);
    s.counters.fastestApproach = c.approachSpeed;
  }
}

Simulation::Simulation(std::unique_ptr<SimulationState> state) : state_(std::move(state)) {}
Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

// ---- The step -----------------------------------------------------------------------------

namespace {

/// What the passes of one step share: the state, the step's Δt, and the motions the
/// integrators run on.
struct Step {
  explicit Step(SimulationState& state)
      : s(state),
        dt(state.config.timeStep),
        gear(state.config.integrator == Integrator::Gear5),
        rotating(state.frictional),
        threads(passThreads(state)),
        teams(static_cast<std::size_t>(threads > 0 ? threads : omp_get_max_threads())) {
    takeMotions();
  }
  /// The motions as the state now holds them: a rebuild may change the particles held (a run
  /// split among processes redistributes them), and with them the arrays.
  void takeMotions() {
    Particles& p = s.particles;
    move = FlatMotion::of(&p.position, p.velocity, s.translation);
    turn = FlatMotion::of(nullptr, p.angularVelocity, s.rotation);
  }
  /// Folds the two largest moves of the particles [b, e) since the neighbour list's build into
  /// the calling thread's (LargestMoves: the same however the particles are cut into ranges), so
  /// that the staleness test needs no pass of its own.
  void measureMoves(std::size_t b, std::size_t e) const {
    s.rangeMoves[static_cast<std::size_t>(omp_get_thread_num())].merge(
        s.partition->largestMovesInRange(s, b, e));
  }

  SimulationState& s;
  const double dt;
  const bool gear, rotating;
  const int threads;
  const std::size_t teams;  ///< the threads of the passes' ranges
  FlatMotion move, turn;    ///< translation, rotation
};

/// Stops the run at the step that broke the state (design: never lie quietly): throws
/// BrokenStateError naming the step and the first broken particle. Where the run is shared
/// among processes only the one that reports the particle throws (RunPartition::brokenParticle)
/// and the others return.
void reportBrokenState(const SimulationState& s) {
  const std::optional<std::string> what = s.partition->brokenParticle(s);
  if (!what) return;
  std::ostringstream msg;
  msg.precision(9);
  msg << "step " << s.steps << " (t = " << clockNow(s) << " s): " << *what
      << "; the state is broken and the run stops (a time step too large for a contact, or a "
         "NaN in the input)";
  throw BrokenStateError(msg.str());
}

/// Pass 1's outcome: whether the predicted values are finite, and the two largest moves since
/// the neighbour list's build that the staleness test takes.
struct Prediction {
  bool finite = true;
  LargestMoves moves;
};

/// 1. Predict (Gear) or drift (Verlet) translation and, with friction, rotation, in one pass
/// over particle ranges that also measures the moves; or take the prediction the last step's
/// corrector made.
Prediction predict(Step& step) {
  SimulationState& s = step.s;
  Prediction out;
  if (s.predictedAhead) {
    out.finite = !s.predictedBroken;
    s.predictedAhead = false;
  } else {
    s.rangeMoves.assign(step.teams, LargestMoves{});
    auto predictRange = [&step](std::size_t b, std::size_t e) {
      int notFinite = 0;  // NotFinite bits
      if (step.gear) {
        gearPredictRange(step.move, step.dt, 3 * b, 3 * e);
        if (step.rotating) gearPredictRange(step.turn, step.dt, 3 * b, 3 * e);
      } else {
        notFinite = verletDriftRange(step.move, step.dt, 3 * b, 3 * e);
        if (step.rotating) notFinite |= verletDriftRange(step.turn, step.dt, 3 * b, 3 * e);
      }
      step.measureMoves(b, e);
      return notFinite;
    };
    out.finite =
        (overRanges(s.particles.size(), step.threads, predictRange) & NotFinite::kPredicted) == 0;
  }
  LargestMoves ranges;
  for (const LargestMoves& range : s.rangeMoves) ranges.merge(range);
  out.moves = s.partition->largestMovesAfterPrediction(s, ranges);
  return out;
}

/// 2. The walls move with their prescribed translations and turns, and the clock by the step.
void moveWalls(SimulationState& s, double dt) {
  for (Wall& w : s.walls) moveWall(w, dt);
  ++s.stepsSinceOrigin;
  ++s.steps;
}

/// 3. The neighbour list is rebuilt if particles or walls moved more than the skin allows (or
/// at every step, where a study asks it). Returns whether it was.
bool refreshNeighbours(Step& step, const LargestMoves& moves) {
  SimulationState& s = step.s;
  if (!s.rebuildEveryStep && !neighbourListStale(s.neighbours, s.particles, s.walls, moves)) {
    return false;
  }
  rebuildList(s);
  step.takeMotions();
  return true;
}

/// 4. Contact forces, then 5. accelerations (into the force arrays: they are not needed after
/// this) and 6. the corrector, in one pass over particle ranges: a particle's correction needs
/// only its own acceleration, so the force pass runs it on its own threads once the forces are
/// complete. With `predictNext` the corrector's loop also runs the next step's pass 1 (the same
/// bits: each value is computed alone) and the next step skips its own.
void forcesAndCorrect(Step& step, bool predictNext, bool predictedFinite) {
  SimulationState& s = step.s;
  const Particles& p = s.particles;
  const Vec3 g = s.config.gravity;
  if (predictNext) s.rangeMoves.assign(step.teams, LargestMoves{});  // the next step's moves
  const ParticleRangeLoop correct = [&](std::size_t b, std::size_t e) {
    // (A rank of a split run may hold no particle: no front() then.)
    const double* accel = s.force.empty() ? nullptr : s.force.front().data();
    const double* angularAccel =
        step.rotating && !s.torque.empty() ? s.torque.front().data() : nullptr;
    s.partition->dropGhostForces(s, b, e);
    accelerationsRange(s.force, step.rotating ? &s.torque : nullptr, p, g, b, e);
    const double dt = step.dt;
    int notFinite = 0;  // NotFinite bits: this step's state, the next step's prediction
    if (predictNext) {
      auto both = step.gear ? gearCorrectPredictRange : verletKickDriftRange;
      notFinite |= both(step.move, accel, dt, 3 * b, 3 * e);
      if (step.rotating) notFinite |= both(step.turn, angularAccel, dt, 3 * b, 3 * e);
      step.measureMoves(b, e);
    } else if (step.gear) {
      notFinite |= gearCorrectRange(step.move, accel, dt, 3 * b, 3 * e);
      if (step.rotating) notFinite |= gearCorrectRange(step.turn, angularAccel, dt, 3 * b, 3 * e);
    } else {
      notFinite |= verletKickRange(step.move, accel, dt, 3 * b, 3 * e);
      if (step.rotating) notFinite |= verletKickRange(step.turn, angularAccel, dt, 3 * b, 3 * e);
    }
    return notFinite;
  };
  const int notFinite = computeContactForces(s, step.dt, &correct);  // `correct`'s bits, ORed
  s.predictedAhead = predictNext;
  s.predictedBroken = (notFinite & NotFinite::kPredicted) != 0;
  if ((notFinite & NotFinite::kCorrected) != 0 || !predictedFinite) reportBrokenState(s);
}

/// 7. Bookkeeping: the energy ledger (the trapezoid rule on the powers of this force pass and
/// the last, `before`), the walls' impulses and the counters.
void keepBooks(SimulationState& s, const ContactPowers& before, double dt) {
  addStepToLedger(s, before, dt);
  for (Wall& w : s.walls) w.impulse += w.reaction * dt;
  const ContactPowers& now = s.powers;
  StepCounters& c = s.counters;
  c.particleContacts = now.particleContacts;
  c.wallContacts = now.wallContacts;
  c.neighbourPairs = s.partition->neighbourPairs(s);
  c.tangentialEvaluations += now.tangentialEvaluations;
  c.smallestStep = c.smallestStep > 0.0 ? std::min(c.smallestStep, dt) : dt;
  c.largestStep = std::max(c.largestStep, dt);
}

/// 8. The step's check against the contact network, or its scan, where due (stepCheckDue), on
/// the corrected state.
void checkStepIfDue(SimulationState& s, StepReview review) {
  if (review == StepReview::None) {
    ++s.stepsSinceCheck;
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  s.partition->beforeStepCheck(s);
  if (review == StepReview::Scan) {
    ++s.stepControlCost.scans;
    scanStep(s);
  } else {
    ++s.stepControlCost.checks;
    checkStep(s);
  }
  s.stepControlCost.seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// One time step, as named passes:
///   1. predict (Gear) or drift (Verlet) translation and, with friction, rotation;
///   2. move the walls with their prescribed velocities;
///   3. rebuild the neighbour list if particles or walls moved more than the skin allows;
///   4. contact forces and torques, Eq. (5), at the predicted state;
///   5. accelerations from Eqs. (3), (4): a = ΣF/m + g, dω/dt = Σ d×F / I;
///   6. correct (Gear) or kick (Verlet);
///   7. accumulate dissipation and work (trapezoidal rule on the powers of pass 4), impulses
///      and counters;
///   8. check the step against the contact network, where due.
/// With `predictNext`, pass 6 also runs the next step's pass 1 in the same loop, unless this
/// step checks the step (the check may change Δt).
void advance(SimulationState& s, bool predictNext) {
  Step step(s);
  const Prediction predicted = predict(step);                     // 1
  moveWalls(s, step.dt);                                          // 2
  const bool rebuilt = refreshNeighbours(step, predicted.moves);  // 3
  const StepReview review = stepCheckDue(s, rebuilt);
  const bool checking = review != StepReview::None;  // the step may change
  const ContactPowers before = s.powers;
  forcesAndCorrect(step, predictNext && !checking, predicted.finite);  // 4-6
  keepBooks(s, before, step.dt);                                       // 7
  checkStepIfDue(s, review);                                           // 8
}

/// One step (advance), timed for the thread governor where OpenMP's count is left to it.
void stepOnce(SimulationState& s, bool predictNext) {
  if (s.config.threads != 0 || omp_get_max_threads() == 1) {
    advance(s, predictNext);
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  advance(s, predictNext);
  s.governor.stepTook(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace

// Each stepping call counts its steps by the state's `steps`: a growing mode's rollback
// (rollback.hpp) takes it back to a check inside the call, whose steps are then taken again.

void Simulation::step() {
  run(1);
}

void Simulation::run(std::uint64_t steps) {
  SimulationState& s = *state_;
  const SteppingCall call(s);
  const std::uint64_t end = s.steps + steps;
  // A step whose state nobody sees between it and the next predicts the next one in its
  // corrector's loop; the last step leaves the state corrected, as step() does.
  while (s.steps < end) stepOnce(s, s.steps + 1 < end);
}

std::uint64_t Simulation::runBefore(std::uint64_t steps, double t) {
  SimulationState& s = *state_;
  // Whether the next step ends at or before t, the clock after it computed as clockNow will
  // then compute it (a hair of the step's length allowed for the rounding of t).
  auto fits = [&](std::uint64_t ahead) {
    const double end = s.timeOrigin + double(s.stepsSinceOrigin + ahead) * s.config.timeStep;
    return end <= t + 1e-9 * s.config.timeStep;
  };
  const SteppingCall call(s);
  const std::uint64_t start = s.steps;
  while (s.steps - start < steps && fits(1)) {
    // The next step is predicted in this one's corrector only where it will be taken: it fits
    // at this step (a check, which may change the step, takes no prediction).
    stepOnce(s, s.steps + 1 - start < steps && fits(2));
  }
  return s.steps - start;
}

void Simulation::advanceTo(double t) {
  advanceTo(t, nullptr);
}

bool Simulation::advanceTo(double t, const std::function<bool()>& proceed) {
  SimulationState& s = *state_;
  requireConfig(std::isfinite(t) && t >= clockNow(s) - 1e-9 * targetStep(s),
                "advance to t = " + shortNumber(t) + " s: must not be before the clock, " +
                    shortNumber(clockNow(s)) + " s");
  const SteppingCall call(s);
  // Landing steps change config.timeStep; the step asked for or chosen is kept apart.
  if (!(s.targetStep > 0.0)) s.targetStep = s.config.timeStep;
  std::uint64_t sinceAsk = 0;
  for (;;) {
    const double target = targetStep(s);
    const double remaining = t - clockNow(s);
    if (remaining <= 1e-9 * target) break;
    // The stretch to t in k equal steps no longer than the target: only the stretch that
    // reaches t is shortened, and by less than one step in all.
    const double k = std::ceil(remaining / target * (1.0 - 1e-12));
    const std::uint64_t steps = static_cast<std::uint64_t>(k);
    changeStep(s, remaining / k);
    const std::uint64_t checks = s.counters.stepChecks, rollbacks = s.counters.rollbacks;
    for (std::uint64_t j = 0; j < steps; ++j) {
      // A step after which `proceed` is asked does not predict the next one, so that a stop
      // leaves the state corrected (the same bits either way, as run() says).
      const bool ask = proceed && ++sinceAsk >= kStepsBetweenAsks;
      stepOnce(s, j + 1 < steps && !ask);
      if (ask) {
        sinceAsk = 0;
        if (!proceed()) {
          changeStep(s, targetStep(s));
          return false;
        }
      }
      // A new choice of step (or a return to an earlier check): the rest of the stretch is
      // laid out again.
      if (s.config.step.automatic &&
          (s.counters.stepChecks != checks || s.counters.rollbacks != rollbacks)) {
        break;
      }
    }
  }
  s.timeOrigin = t;
  s.stepsSinceOrigin = 0;
  s.config.timeStep = targetStep(s);
  return true;
}

// ---- Accessors ----------------------------------------------------------------------------

double Simulation::time() const {
  return clockNow(*state_);
}
void Simulation::setTime(double t) {
  state_->timeOrigin = t;
  state_->stepsSinceOrigin = 0;
}
std::uint64_t Simulation::stepCount() const {
  return state_->steps;
}
const SimulationConfig& Simulation::config() const {
  return state_->config;
}
const Particles& Simulation::particles() const {
  return state_->particles;
}
const std::vector<Wall>& Simulation::walls() const {
  return state_->walls;
}
const ContactScale& Simulation::contactScale() const {
  return state_->contactScale;
}
bool Simulation::frictional() const {
  return state_->frictional;
}
const StepCounters& Simulation::counters() const {
  return state_->counters;
}
double Simulation::skin() const {
  return state_->neighbours.skin;
}
Vec3 Simulation::acceleration(std::size_t i) const {
  return state_->translation.d2.at(i);
}

const StepCheck& Simulation::stepCheck() const {
  return state_->stepCheck;
}

void Simulation::setThreads(int threads) {
  requireConfig(threads >= 0, "threads = " + std::to_string(threads) + ": must be >= 0");
  state_->config.threads = threads;
}

void Simulation::setExactSums(bool exact) {
  SimulationState& s = *state_;
  s.config.exactSums = exact;
  if (s.steps == 0) startLedger(s);  // the starting values summed alike
}

void Simulation::setWallVelocity(std::size_t wall, const Vec3& velocity) {
  requireConfig(velocity.allFinite(), "wall velocity must be finite");
  SimulationState& s = *state_;
  Wall& w = s.walls.at(wall);
  if (w.velocity == velocity) return;
  w.velocity = velocity;
  // A wall that starts or changes its motion may start an impact: an automatic step is chosen
  // again before the next step, not at the next check (the accuracy floor is for impacts).
  if (s.config.step.automatic) {
    s.partition->beforeStepCheck(s);
    checkStep(s);
  }
}

long Simulation::findWall(const std::string& name) const {
  const auto& w = state_->walls;
  for (std::size_t k = 0; k < w.size(); ++k) {
    if (w[k].name == name) return static_cast<long>(k);
  }
  return -1;
}

}  // namespace granular
