/// Simulation: set-up and validation, the step (its passes in order), measurements.
#include "granular/simulation.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <sstream>

#include "domain_split.hpp"
#include "force_pass.hpp"
#include "granular/error.hpp"
#include "integrators.hpp"
#include "network_bound.hpp"
#include "simulation_state.hpp"
#include "state_checks.hpp"

namespace granular {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw ConfigError(what);
}

std::string str(double x) {
  std::ostringstream o;
  o.precision(6);
  o << x;
  return o.str();
}

void validateStepControl(const StepControl& c) {
  require(std::isfinite(c.safety) && c.safety > 0 && c.safety <= 1,
          "step safety = " + str(c.safety) + ": must be in (0, 1]");
  require(std::isfinite(c.contactResolution) && c.contactResolution >= 1,
          "contact resolution = " + str(c.contactResolution) +
              " steps per contact duration: must be >= 1");
  require(c.recheckSteps >= 1, "the step's check interval must be >= 1 step");
}

/// Stops the run at the step that broke the state (design: never lie quietly).
/// Throws NumericalError naming the step and the first broken particle. In a run split by
/// space only the rank that owns a broken particle throws (naming its global id and the rank):
/// a ghost's broken values are its owner's, which reports them, and the others return.
void reportBrokenState(const SimulationState& s) {
  const bool split = s.split.domains != nullptr;
  const std::optional<std::string> what =
      split ? firstNonFiniteParticle(s.particles, &s.owned, &s.split.globalId)
            : firstNonFiniteParticle(s.particles);
  if (split && !what) return;
  std::ostringstream msg;
  msg.precision(9);
  msg << "step " << s.steps
      << " (t = " << s.timeOrigin + double(s.stepsSinceOrigin) * s.config.timeStep
      << " s): " << (what ? *what : std::string("a value is not finite"))
      << (split ? " (on rank " + std::to_string(s.ranks->rank()) + " of " +
                      std::to_string(s.ranks->size()) + ")"
                : std::string())
      << "; the state is broken and the run stops (a time step too large for a contact, or a "
         "NaN in the input)";
  throw BrokenStateError(msg.str());
}

/// The fewest steps between two checks of the step that a rebuild starts.
/// An automatic step follows the contacts closely; a fixed one is only watched, at less cost
/// (every impact of a Gear5 step at t_c/50 spans two such checks).
constexpr std::uint64_t kStepsBetweenChecks = 10, kStepsBetweenFixedChecks = 25;

/// The step asked for or chosen (StepControl), which a landing step may shorten.
double targetStep(const SimulationState& s) {
  return s.targetStep > 0.0 ? s.targetStep : s.config.timeStep;
}

/// The next step's Δt; the clock, timeOrigin + stepsSinceOrigin·Δt, is folded into its origin
/// first so that it runs on unbroken.
void changeStep(SimulationState& s, double dt) {
  if (dt == s.config.timeStep) return;
  s.timeOrigin += static_cast<double>(s.stepsSinceOrigin) * s.config.timeStep;
  s.stepsSinceOrigin = 0;
  s.config.timeStep = dt;
}

double clock(const SimulationState& s) {
  return s.timeOrigin + static_cast<double>(s.stepsSinceOrigin) * s.config.timeStep;
}

/// The accuracy floor t_c / N of the stiffest contact at the approach speed `approach` [m/s]:
/// a Hertz contact is shorter at a higher speed, so the floor follows the run's fastest
/// approach wherever it exceeds the expected one (config.impactSpeed); Hooke's does not depend
/// on it. Gear5 also keeps its binary limit (t_c/50): its interval on a smooth network is long,
/// but contacts that open and close inside a step kick its higher derivatives, and beds gain
/// energy above t_c/40 (bench/RESULTS.md, "Gear in a bed") where the network allows t_c/10.
double accuracyFloor(const SimulationState& s, Integrator integrator, double approach) {
  const bool faster =
      s.config.material.normalLaw == NormalLaw::Hertz && approach > s.config.impactSpeed;
  const ContactScale scale =
      faster ? stiffestContact(s.config.material, s.contactScale.radius, approach) : s.contactScale;
  double floor = scale.duration / s.config.step.contactResolution;
  if (integrator == Integrator::Gear5) floor = std::min(floor, maxStableStep(scale, integrator));
  return floor;
}

/// The network's stable step for `integrator` now, counting the contacts that may form within
/// two check intervals at step `dt` (docs/physics.md §2.16), and the accuracy floor.
StepCheck measureStep(const SimulationState& s, Integrator integrator, double dt) {
  const StepControl& control = s.config.step;
  // Contacts that form within two check intervals count; an automatic step may grow to its
  // floor at the expected speed before the next check, so the interval is measured in that.
  const double longest = control.automatic ? std::max(dt, accuracyFloor(s, integrator, 0.0)) : dt;
  const double lookahead = 2.0 * static_cast<double>(control.recheckSteps) * longest;
  StepCheck c;
  // The power sweeps only tighten the bound, so they stop once it allows what is needed: a
  // fixed step, or the accuracy floor an automatic step cannot exceed anyway. An automatic step
  // takes at most 8 sweeps (within 1.5 % of 32 on the paper's beds, at a fifth of the cost), a
  // fixed one 32 before it is judged above the network's.
  const NetworkFrequency f = networkFrequencyBound(
      s, control.automatic ? 8 : 32, lookahead, [&](const NetworkFrequency& g) {
        const double needed = control.automatic
                                  ? accuracyFloor(s, integrator, g.fastestApproach) / control.safety
                                  : dt;
        return needed <= networkStepOf(integrator, g);
      });
  c.approachSpeed = f.fastestApproach;
  c.accuracyStep = accuracyFloor(s, integrator, f.fastestApproach);
  c.time = clock(s);
  c.omegaMax = f.omegaMax;
  c.dampingRatio = f.dampingRatio;
  c.particle = f.particle;
  c.contacts = f.contacts + f.approaching;
  c.networkStep = networkStepOf(integrator, f);
  c.chosenStep = control.automatic ? std::min(control.safety * c.networkStep, c.accuracyStep) : dt;
  return c;
}

/// Why `dt` is above the network's step `c` (a fixed step's refusal or stop).
std::string aboveNetworkStep(double dt, const StepCheck& c, Integrator integrator) {
  const bool gear = integrator == Integrator::Gear5;
  std::ostringstream msg;
  msg.precision(4);
  msg << "the time step " << dt << " s is above the step the contact network allows, "
      << c.networkStep << " s (" << dt / c.networkStep
      << " × it): " << (gear ? "gear5" : "velocity Verlet")
      << " is stable for ω Δt <= " << c.networkStep * c.omegaMax
      << " at the network's damping ratio " << c.dampingRatio
      << " (physics.md §2.15), and the network's highest frequency is at most " << c.omegaMax
      << " rad/s (bounded from " << c.contacts << " contacts; particle " << c.particle
      << "'s row sets it)";
  return msg.str();
}

/// A fixed step at the start, or after a change of step, integrator or material: refused
/// (ConfigError) above the network's step; with no contact yet, above the binary fallback,
/// which Gear5 keeps throughout (measureStep says why).
StepCheck requireAllowedStep(const SimulationState& s, double dt, Integrator integrator) {
  const StepCheck c = measureStep(s, integrator, dt);
  if (c.contacts == 0 || integrator == Integrator::Gear5) {
    // Nothing to bound yet: the stiffest binary contact's fraction, set from the worst bed
    // measured (bench/RESULTS.md, "Gear in a bed"), stands in until contacts form.
    requireStableStep(dt, s.contactScale, integrator);
    requireStableTangentialDamping(s.config.material, dt, integrator);
    if (c.contacts == 0) return c;
  }
  if (!(dt <= c.networkStep)) {
    throw TimeStepError(aboveNetworkStep(dt, c, integrator) + "; use at most " +
                        str(c.networkStep) + " s, or time_step = \"auto\"");
  }
  return c;
}

/// The check of the step against the network (StepControl): with step.automatic the step is
/// chosen, else a fixed step above the network's stops the run or is counted.
void checkStep(SimulationState& s) {
  s.stepsSinceCheck = 0;
  ++s.counters.stepChecks;
  const double target = targetStep(s);
  StepCheck c = measureStep(s, s.config.integrator, target);
  s.stepCheck = c;
  s.counters.fastestApproach = std::max(s.counters.fastestApproach, c.approachSpeed);

  if (s.config.step.automatic) {
    if (!(c.chosenStep > 0.0) || !std::isfinite(c.chosenStep)) {
      std::ostringstream msg;
      msg << "step " << s.steps << " (t = " << c.time << " s): the contact network allows no "
          << "step (its bound: " << c.omegaMax << " rad/s at damping ratio " << c.dampingRatio
          << ", particle " << c.particle << "); the run stops";
      throw NumericalError(msg.str());
    }
    s.targetStep = c.chosenStep;
    changeStep(s, c.chosenStep);
    return;
  }
  if (s.stepLimitDisabled || c.contacts == 0 || target <= c.networkStep) return;
  if (s.config.step.onUnstable == OnUnstable::Warn) {
    ++s.counters.unstableChecks;
    s.counters.worstStepRatio = std::max(s.counters.worstStepRatio, target / c.networkStep);
    return;
  }
  std::ostringstream msg;
  msg.precision(9);
  msg << "step " << s.steps << " (t = " << c.time
      << " s): " << aboveNetworkStep(target, c, s.config.integrator)
      << "; the run stops before it gains energy (on_unstable = \"stop\"): use a smaller "
         "time_step, time_step = \"auto\", or on_unstable = \"warn\"";
  throw NumericalError(msg.str());
}

void validate(const SimulationConfig& cfg, const Particles& p, const std::vector<Wall>& walls) {
  validateMaterial(cfg.material);
  require(std::isfinite(cfg.timeStep) && cfg.timeStep > 0,
          "time step = " + str(cfg.timeStep) + " s: must be > 0");
  require(std::isfinite(cfg.skin) && cfg.skin >= 0, "skin = " + str(cfg.skin) + " m: must be >= 0");
  validateStepControl(cfg.step);
  require(cfg.gravity.allFinite(), "gravity must be finite");
  require(p.size() > 0, "the scene has no particles");
  require(p.velocity.size() == p.size() && p.angularVelocity.size() == p.size() &&
              p.radius.size() == p.size() && p.mass.size() == p.size(),
          "particle arrays have different lengths");
  for (std::size_t i = 0; i < p.size(); ++i) {
    require(std::isfinite(p.radius[i]) && p.radius[i] > 0,
            "particle " + std::to_string(i) + ": radius " + str(p.radius[i]) + " m must be > 0");
    require(std::isfinite(p.mass[i]) && p.mass[i] > 0,
            "particle " + std::to_string(i) + ": mass " + str(p.mass[i]) + " kg must be > 0");
    require(
        p.position[i].allFinite() && p.velocity[i].allFinite() && p.angularVelocity[i].allFinite(),
        "particle " + std::to_string(i) + ": position or velocity is not finite");
  }
  for (const Wall& w : walls) {
    require(std::abs(w.normal.norm() - 1.0) < 1e-12,
            "wall " + w.name + ": normal must be a unit vector");
    require(w.point.allFinite() && w.velocity.allFinite(), "wall " + w.name + ": not finite");
  }
  // (Nearly) coincident centres, closer than 1e-9 (R_i + R_j), have no line of centres and so
  // no contact normal: refused, naming both particles (a duplicated row is the usual cause).
  // Overlap as such is allowed: a restored packed state overlaps. Positions are binned into
  // cells of the largest such distance, sorted by cell (z, y, x), and each particle is compared
  // with those of its own and the 26 adjacent cells. For each of the 9 (dz, dy) rows the three
  // cells (cx - 1 .. cx + 1) are one contiguous run of the sorted list, and the run's start only
  // moves forward as the particles are visited in sorted order (adding a fixed offset keeps the
  // lexicographic order), so the search is a sort and one linear sweep.
  {
    const std::size_t n = p.size();
    const double rMax = *std::max_element(p.radius.begin(), p.radius.end());
    const double cell = std::max(2e-9 * rMax, 0x1p-1022);  // at least the smallest normal double
    struct Entry {
      long long z, y, x;  // cell coordinates, compared in this order
      std::size_t index;
    };
    auto before = [](const Entry& a, long long z, long long y, long long x) {
      return a.z != z ? a.z < z : a.y != y ? a.y < y : a.x < x;
    };
    auto coord = [cell](double x) {  // clamped before the cast: finite but absurd stays defined
      return static_cast<long long>(std::clamp(std::floor(x / cell), -0x1p60, 0x1p60));
    };
    std::vector<Entry> sorted(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& x = p.position[i];
      sorted[i] = Entry{coord(x.z()), coord(x.y()), coord(x.x()), i};
    }
    std::sort(sorted.begin(), sorted.end(), [&before](const Entry& a, const Entry& b) {
      return before(a, b.z, b.y, b.x) || (!before(b, a.z, a.y, a.x) && a.index < b.index);
    });
    std::size_t runStart[9] = {};
    for (const Entry& e : sorted) {
      const std::size_t i = e.index;
      std::size_t row = 0;
      for (long long dz = -1; dz <= 1; ++dz) {
        for (long long dy = -1; dy <= 1; ++dy, ++row) {
          const long long z = e.z + dz, y = e.y + dy;
          std::size_t& b = runStart[row];
          while (b < n && before(sorted[b], z, y, e.x - 1)) ++b;
          for (std::size_t c = b; c < n && before(sorted[c], z, y, e.x + 2); ++c) {
            const std::size_t j = sorted[c].index;
            if (j == i) continue;
            const double distance = (p.position[j] - p.position[i]).norm();
            if (distance < 1e-9 * (p.radius[i] + p.radius[j])) {
              const std::size_t a = std::min(i, j), k = std::max(i, j);
              std::ostringstream msg;
              msg.precision(17);
              msg << "particles " << a << " and " << k << " have (nearly) coincident centres ("
                  << p.position[a].x() << ", " << p.position[a].y() << ", " << p.position[a].z()
                  << ") and (" << p.position[k].x() << ", " << p.position[k].y() << ", "
                  << p.position[k].z() << "), " << distance
                  << " m apart, less than 1e-9 of their radii sum: the contact has no normal";
              throw ConfigError(msg.str());
            }
          }
        }
      }
    }
  }
}

}  // namespace

double maxStableStep(const ContactScale& scale, Integrator integrator) {
  const double fraction =
      integrator == Integrator::Gear5 ? kMaxStepFractionGear5 : kMaxStepFractionVerlet;
  return fraction * scale.duration;
}

void requireStableStep(double dt, const ContactScale& scale, Integrator integrator) {
  const double limit = maxStableStep(scale, integrator);
  if (!(dt <= limit)) {
    const bool gear = integrator == Integrator::Gear5;
    std::ostringstream msg;
    msg << "time step " << dt << " s is above the stable limit " << limit << " s of "
        << (gear ? "gear5" : "velocity Verlet") << " = 1/" << (gear ? 50 : 10);
    if (scale.tangentialSpring) {
      msg << " of the half-period " << str(scale.duration)
          << " s of a sticking contact's constant tangential spring (the stiffest: radius ";
    } else if (scale.rollingSpring) {
      msg << " of the half-period " << str(scale.duration)
          << " s of a contact's rolling spring (k_r = β_r μ_r² k_n R_ij², shorter than the "
             "normal contact's duration; the stiffest: radius ";
    } else {
      msg << " of the contact duration " << str(scale.duration)
          << " s of the stiffest contact (radius ";
    }
    msg << scale.radius << " m "
        << (scale.againstWall ? "against a wall" : "against an equal particle") << "); use at most "
        << limit << " s"
        << (gear ? " (Gear gains energy in a damped bed above it), or velocity Verlet up to 1/10"
                 : " (1/50 to 1/20 of the duration is usual)");
    throw TimeStepError(msg.str());
  }
}

double maxTangentialDamping(double dt, Integrator integrator) {
  const double stability =
      integrator == Integrator::Gear5 ? kDamperStabilityGear5 : kDamperStabilityVerlet;
  return stability / (kTangentialContactsAtOnce * kTangentialRatePerContact * dt);
}

void requireStableTangentialDamping(const Material& material, double dt, Integrator integrator) {
  if (!material.hasFriction()) return;  // no tangential force: γt acts on nothing
  const double limit = maxTangentialDamping(dt, integrator);
  if (!(material.tangentialDamping <= limit)) {
    const bool gear = integrator == Integrator::Gear5;
    std::ostringstream msg;
    msg << "tangential damping " << material.tangentialDamping << " 1/s is above the stable limit "
        << limit << " 1/s at the time step " << dt << " s of "
        << (gear ? "gear5" : "velocity Verlet")
        << ": a sticking contact's dashpot slows it at 3.5 γt, a bed's contacts act together (up "
           "to 6 at once) and "
        << (gear ? "gear5" : "velocity Verlet") << " keeps a damper stable only for rate·Δt <= "
        << (gear ? kDamperStabilityGear5 : kDamperStabilityVerlet) << "; use at most " << limit
        << " 1/s or a smaller time step";
    throw ConfigError(msg.str());
  }
}

// ---- Sums over the particles ----

ParticleSums particleSums(const SimulationState& s) {
  const Particles& p = s.particles;
  const bool all = s.owned.empty();
  ParticleSums sums;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!all && !s.owned[i]) continue;
    sums.translational.add(0.5 * p.mass[i] * p.velocity[i].squaredNorm());
    sums.potential.add(p.mass[i] * s.config.gravity.dot(p.position[i]));
    if (s.frictional) sums.rotational.add(0.5 * p.inertia(i) * p.angularVelocity[i].squaredNorm());
  }
  if (s.ranks) {
    std::vector<ExactSum> merged{sums.translational, sums.rotational, sums.potential};
    s.ranks->mergeOverRanks(merged);
    sums = {merged[0], merged[1], merged[2]};
  }
  return sums;
}

namespace {

/// The ledger's starting values: the stored energies of a force evaluation at the current
/// state (which advances nothing) and the potential energy.
void startLedger(SimulationState& s) {
  computeContactForces(s, 0.0);
  s.energy.initialPotential = particleSums(s).potential.value();
  for (std::size_t slot = 0; slot < kEnergySlots; ++slot) {
    s.energy.initialStored[slot] = s.powers.energy[slot];
  }
}

}  // namespace

namespace {

/// Rebuilds the neighbour list, carrying the springs.
void rebuildList(SimulationState& s) {
  // Split by space, the particles first go where they now belong, with their springs; the
  // list is then rebuilt from what each rank holds (domain_split.hpp).
  if (s.split.domains) redistribute(s);
  rebuildNeighbourList(s.neighbours, s.particles, s.walls, s.frictional, passThreads(s));
  if (s.split.domains) afterSplitRebuild(s);
  ++s.counters.rebuilds;
}

}  // namespace

// ---- Set-up -------------------------------------------------------------------------------

Simulation::Simulation(Particles particles, std::vector<Wall> walls, const SimulationConfig& config)
    : state_(std::make_unique<SimulationState>()) {
  validate(config, particles, walls);
  SimulationState& s = *state_;
  s.config = config;
  s.particles = std::move(particles);
  s.walls = std::move(walls);
  s.frictional = config.material.hasFriction();
  const Particles& p = s.particles;
  const std::size_t n = p.size();
  const double rMin = *std::min_element(p.radius.begin(), p.radius.end());

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

  rebuildNeighbourList(s.neighbours, s.particles, s.walls, s.frictional, s.config.threads);
  ++s.counters.rebuilds;
  startLedger(s);  // the initial forces too; dt = 0 leaves the springs as they are
  for (std::size_t i = 0; i < n; ++i) {
    s.translation.d2[i] = s.force[i] * (1.0 / p.mass[i]) + config.gravity;
    if (s.frictional) s.rotation.d2[i] = s.torque[i] * (1.0 / p.inertia(i));
  }
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

/// One time step, as named passes:
///   1. predict (Gear) or drift (Verlet) translation and, with friction, rotation;
///   2. move the walls with their prescribed velocities;
///   3. rebuild the neighbour list if particles or walls moved more than the skin allows;
///   4. contact forces and torques, Eq. (5), at the predicted state;
///   5. accelerations from Eqs. (3), (4): a = ΣF/m + g, dω/dt = Σ d×F / I;
///   6. correct (Gear) or kick (Verlet);
///   7. accumulate dissipation and work (trapezoidal rule on the powers of passes 4).
/// With `predictNext`, pass 6 also runs the next step's pass 1 in the same loop (the same bits:
/// each value is computed alone) and the next step skips its own.
void advanceOnce(SimulationState& s, bool predictNext) {
  Particles& p = s.particles;
  const double dt = s.config.timeStep;
  const bool gear = s.config.integrator == Integrator::Gear5;
  // A split run's redistribution at a rebuild changes the particles held: n and the motions
  // are taken again then.
  std::size_t n = p.size();
  const int threads = passThreads(s);
  const std::size_t teams = static_cast<std::size_t>(threads > 0 ? threads : omp_get_max_threads());

  // 1. Predict, translation and rotation in one pass over particle ranges.
  FlatMotion move = FlatMotion::of(&p.position, p.velocity, s.translation);
  FlatMotion turn = FlatMotion::of(nullptr, p.angularVelocity, s.rotation);
  const bool rotating = s.frictional;
  // On the same ranges, each range's largest move since the neighbour list was built (a
  // maximum: the same in any split), so the staleness test needs no pass of its own.
  auto moved = [&](std::size_t b, std::size_t e) {
    // Split by space the ghosts' predictions are replaced and the moves taken again after the
    // refresh (below): nothing to measure here.
    if (s.split.domains) return;
    double& largest = s.rangeMove2[static_cast<std::size_t>(omp_get_thread_num())];
    largest = std::max(largest, largestMove2(s.neighbours, p, b, e));
  };
  bool driftedFinite = true;
  if (s.predictedAhead) {
    driftedFinite = !s.predictedBroken;
    s.predictedAhead = false;
  } else {
    s.rangeMove2.assign(teams, 0.0);
    auto predict = [&](std::size_t b, std::size_t e) {
      int notFinite = 0;  // NotFinite bits
      if (gear) {
        gearPredictRange(move, dt, 3 * b, 3 * e);
        if (rotating) gearPredictRange(turn, dt, 3 * b, 3 * e);
      } else {
        notFinite = verletDriftRange(move, dt, 3 * b, 3 * e);
        if (rotating) notFinite |= verletDriftRange(turn, dt, 3 * b, 3 * e);
      }
      moved(b, e);
      return notFinite;
    };
    driftedFinite = (overRanges(n, threads, predict) & NotFinite::kPredicted) == 0;
  }
  double maxMove2 = *std::max_element(s.rangeMove2.begin(), s.rangeMove2.end());
  if (s.split.domains) {
    // Split by space: the ghosts' predictions came from their own (unforced) derivatives, and
    // their owners' replace them. The largest move is then taken again over true positions,
    // and over the ranks, so that every rank rebuilds when one process would.
    refreshSplitGhosts(s);
    maxMove2 = s.ranks->maxOverRanks(largestMove2(s.neighbours, p, 0, n));
  }
  // 2. Walls.
  for (Wall& w : s.walls) w.point += w.velocity * dt;
  ++s.stepsSinceOrigin;
  ++s.steps;
  // 3. Neighbours.
  bool rebuilt = false;
  if (s.rebuildEveryStep || neighbourListStale(s.neighbours, p, s.walls, maxMove2)) {
    rebuildList(s);
    rebuilt = true;
    n = p.size();
    move = FlatMotion::of(&p.position, p.velocity, s.translation);
    turn = FlatMotion::of(nullptr, p.angularVelocity, s.rotation);
  }
  // The step is checked (and, automatic, chosen) after a rebuild, at most every
  // kStepsBetweenChecks steps (a settling bed rebuilds every few steps; a check costs about one
  // step), and at least every recheckSteps steps, on the corrected state: that step does not
  // predict the next one (it may change Δt).
  const std::uint64_t since = s.stepsSinceCheck + 1;
  const std::uint64_t gap =
      s.config.step.automatic ? kStepsBetweenChecks : kStepsBetweenFixedChecks;
  const bool checking = (s.config.step.automatic || !s.stepLimitDisabled) &&
                        ((rebuilt && since >= gap) || since >= s.config.step.recheckSteps);
  if (checking) predictNext = false;
  // 4. Forces, then 5-6. accelerations (into the force arrays: they are not needed after this)
  // and the corrector, in one pass over particle ranges: a particle's correction needs only its
  // own acceleration. The force pass runs it on its own threads once the forces are complete.
  const ContactPowers before = s.powers;
  const Vec3 g = s.config.gravity;
  if (predictNext) s.rangeMove2.assign(teams, 0.0);  // the next step's moves, from pass 6
  const ParticleRangeLoop correct = [&](std::size_t b, std::size_t e) {
    // (A rank of a split run may hold no particle: no front() then.)
    const double* accel = s.force.empty() ? nullptr : s.force.front().data();
    const double* angularAccel = rotating && !s.torque.empty() ? s.torque.front().data() : nullptr;
    if (s.split.domains) {
      // A ghost's force is the part its own contacts here give: dropped, so that what the
      // corrector makes of it (overwritten by the owner's next prediction) stays finite.
      for (std::size_t i = b; i < e; ++i) {
        if (s.owned[i]) continue;
        s.force[i] = Vec3::Zero();
        if (rotating) s.torque[i] = Vec3::Zero();
      }
    }
    accelerationsRange(s.force, rotating ? &s.torque : nullptr, p, g, b, e);
    int notFinite = 0;  // NotFinite bits: this step's state, the next step's prediction
    if (predictNext) {
      auto both = gear ? gearCorrectPredictRange : verletKickDriftRange;
      notFinite |= both(move, accel, dt, 3 * b, 3 * e);
      if (rotating) notFinite |= both(turn, angularAccel, dt, 3 * b, 3 * e);
      moved(b, e);
    } else if (gear) {
      notFinite |= gearCorrectRange(move, accel, dt, 3 * b, 3 * e);
      if (rotating) notFinite |= gearCorrectRange(turn, angularAccel, dt, 3 * b, 3 * e);
    } else {
      notFinite |= verletKickRange(move, accel, dt, 3 * b, 3 * e);
      if (rotating) notFinite |= verletKickRange(turn, angularAccel, dt, 3 * b, 3 * e);
    }
    return notFinite;
  };
  const int notFinite = computeContactForces(s, dt, &correct);  // `correct`'s bits, ORed
  s.predictedAhead = predictNext;
  s.predictedBroken = (notFinite & NotFinite::kPredicted) != 0;
  if ((notFinite & NotFinite::kCorrected) != 0 || !driftedFinite) reportBrokenState(s);
  // 7. Bookkeeping.
  const ContactPowers& now = s.powers;
  EnergyAccumulators& e = s.energy;
  const double half = 0.5 * dt;
  for (std::size_t slot = 0; slot < kEnergySlots; ++slot) {
    switch (kEnergySlotTable[slot].kind) {
      case EnergyKind::Dissipated:
      case EnergyKind::Work:
        e.account[slot] += half * (before.energy[slot] + now.energy[slot]);
        break;
      case EnergyKind::Supplied:
        e.account[slot] += now.energy[slot];
        break;
      case EnergyKind::Stored:
      case EnergyKind::Slip:
        break;
    }
  }
  e.wallWork += half * (before.wallPower + now.wallPower);
  for (Wall& w : s.walls) w.impulse += w.reaction * dt;
  s.counters.particleContacts = now.particleContacts;
  s.counters.wallContacts = now.wallContacts;
  s.counters.neighbourPairs = s.split.domains ? s.split.pairs : s.neighbours.second.size();
  s.counters.tangentialEvaluations += now.tangentialEvaluations;
  StepCounters& c = s.counters;
  c.smallestStep = c.smallestStep > 0.0 ? std::min(c.smallestStep, dt) : dt;
  c.largestStep = std::max(c.largestStep, dt);
  if (checking) {
    // The ghosts' corrections here came from their partial forces: the check sees their owners'.
    if (s.split.domains) refreshSplitGhosts(s);
    checkStep(s);
  } else {
    ++s.stepsSinceCheck;
  }
}

/// One step (advanceOnce), timed for the thread governor where OpenMP's count is left to it.
void advance(SimulationState& s, bool predictNext) {
  if (s.config.threads != 0 || omp_get_max_threads() == 1) {
    advanceOnce(s, predictNext);
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  advanceOnce(s, predictNext);
  s.governor.stepTook(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace

void Simulation::step() {
  advance(*state_, false);
}

void Simulation::run(std::uint64_t steps) {
  // A step whose state nobody sees between it and the next predicts the next one in its
  // corrector's loop; the last step leaves the state corrected, as step() does.
  for (std::uint64_t k = 0; k < steps; ++k) advance(*state_, k + 1 < steps);
}

void Simulation::advanceTo(double t) {
  SimulationState& s = *state_;
  require(std::isfinite(t) && t >= clock(s) - 1e-9 * targetStep(s),
          "advance to t = " + str(t) + " s: must not be before the clock, " + str(clock(s)) + " s");
  // Landing steps change config.timeStep; the step asked for or chosen is kept apart.
  if (!(s.targetStep > 0.0)) s.targetStep = s.config.timeStep;
  for (;;) {
    const double target = targetStep(s);
    const double remaining = t - clock(s);
    if (remaining <= 1e-9 * target) break;
    // The stretch to t in k equal steps no longer than the target: only the stretch that
    // reaches t is shortened, and by less than one step in all.
    const double k = std::ceil(remaining / target * (1.0 - 1e-12));
    const std::uint64_t steps = static_cast<std::uint64_t>(k);
    changeStep(s, remaining / k);
    const std::uint64_t checks = s.counters.stepChecks;
    for (std::uint64_t j = 0; j < steps; ++j) {
      advance(s, j + 1 < steps);
      // A new choice of step: the rest of the stretch is laid out again.
      if (s.config.step.automatic && s.counters.stepChecks != checks) break;
    }
  }
  s.timeOrigin = t;
  s.stepsSinceOrigin = 0;
  s.config.timeStep = targetStep(s);
}

// ---- Accessors and measurements -----------------------------------------------------------

double Simulation::time() const {
  return clock(*state_);
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
void Simulation::setSkin(double skin) {
  require(std::isfinite(skin) && skin >= 0, "skin = " + str(skin) + " m: must be >= 0");
  SimulationState& s = *state_;
  const Particles& p = s.particles;
  const double rMin = *std::min_element(p.radius.begin(), p.radius.end());
  s.config.skin = skin;
  s.neighbours.skin = skin > 0 ? skin : 0.3 * rMin;
  s.neighbours.valid = false;  // rebuilt (history kept) at the next step
}
double Simulation::skin() const {
  return state_->neighbours.skin;
}
Vec3 Simulation::acceleration(std::size_t i) const {
  return state_->translation.d2.at(i);
}

std::size_t Simulation::addWall(const Wall& wall) {
  require(std::abs(wall.normal.norm() - 1.0) < 1e-12,
          "wall " + wall.name + ": normal must be a unit vector");
  SimulationState& s = *state_;
  s.walls.push_back(wall);
  s.neighbours.valid = false;  // the new wall needs its candidate list
  rebuildList(s);
  return s.walls.size() - 1;
}

void Simulation::setTimeStep(double dt) {
  require(std::isfinite(dt) && dt > 0, "time step = " + str(dt) + " s: must be > 0");
  SimulationState& s = *state_;
  if (!s.stepLimitDisabled && !s.config.step.automatic) {
    requireAllowedStep(s, dt, s.config.integrator);
  }
  s.targetStep = dt;
  changeStep(s, dt);
}

void Simulation::setStepControl(const StepControl& control) {
  validateStepControl(control);
  SimulationState& s = *state_;
  const StepControl before = s.config.step;
  s.config.step = control;
  try {
    if (control.automatic) {
      checkStep(s);
    } else if (!s.stepLimitDisabled) {
      requireAllowedStep(s, targetStep(s), s.config.integrator);
    }
  } catch (...) {
    s.config.step = before;
    throw;
  }
}

const StepCheck& Simulation::stepCheck() const {
  return state_->stepCheck;
}

void Simulation::setMaterial(const Material& material) {
  SimulationState& s = *state_;
  const Material& now = s.config.material;
  if (sameMaterial(material, now)) {
    return;  // nothing changes, not even the bits
  }
  validateMaterial(material);
  const Particles& p = s.particles;
  const double rMin = *std::min_element(p.radius.begin(), p.radius.end());
  const ContactScale scale = stiffestContact(material, rMin, s.config.impactSpeed);
  if (!s.stepLimitDisabled && !s.config.step.automatic) {
    if (material.hasFriction() == s.frictional) {
      // The network under the new law (the contacts are where they are).
      const Material current = s.config.material;
      const ContactScale currentScale = s.contactScale;
      s.config.material = material;
      s.contactScale = scale;
      try {
        requireAllowedStep(s, targetStep(s), s.config.integrator);
      } catch (...) {
        s.config.material = current;
        s.contactScale = currentScale;
        throw;
      }
      s.config.material = current;
      s.contactScale = currentScale;
    } else {
      // Rotations come or go: the binary contacts' limit, as with no contact.
      requireStableStep(targetStep(s), scale, s.config.integrator);
      requireStableTangentialDamping(material, targetStep(s), s.config.integrator);
    }
  }
  // Accepted: nothing above has changed the state.
  s.config.material = material;
  s.contactScale = scale;
  const std::size_t n = p.size();
  if (material.hasFriction() != s.frictional) {
    s.frictional = material.hasFriction();
    if (s.frictional) {  // rotations start at rest, springs unstretched, as in a new run
      s.rotation.d2.assign(n, Vec3::Zero());
      if (s.config.integrator == Integrator::Gear5) {
        for (std::vector<Vec3>* d : {&s.rotation.d3, &s.rotation.d4, &s.rotation.d5}) {
          d->assign(n, Vec3::Zero());
        }
      }
    } else {  // the frictionless path has no rotations
      s.rotation = Derivatives{};
      std::vector<Vec3>().swap(s.torque);
      s.particles.angularVelocity.assign(n, Vec3::Zero());
    }
    // A list built for the other path holds no springs (or ones no longer wanted): start anew.
    NeighbourList& list = s.neighbours;
    for (std::vector<std::uint32_t>* v : {&list.rowStart, &list.second}) v->clear();
    list.springs = PairSprings{};
    list.wallParticles.clear();
    list.wallHistory.clear();
    rebuildList(s);
  }
  // The accelerations under the new law, as a new simulation starts (springs kept: dt = 0).
  computeContactForces(s, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    s.translation.d2[i] = s.force[i] * (1.0 / p.mass[i]) + s.config.gravity;
    if (s.frictional) s.rotation.d2[i] = s.torque[i] * (1.0 / p.inertia(i));
  }
  if (s.config.step.automatic) checkStep(s);  // the step for the new law
}

void Simulation::setIntegrator(Integrator integrator) {
  SimulationState& s = *state_;
  if (integrator == s.config.integrator) return;
  if (!s.stepLimitDisabled && !s.config.step.automatic) {
    requireAllowedStep(s, targetStep(s), integrator);
  }
  const std::size_t n = s.particles.size();
  for (Derivatives* d : {&s.translation, &s.rotation}) {
    if (d->d2.empty()) continue;  // no rotations on the frictionless path
    for (std::vector<Vec3>* higher : {&d->d3, &d->d4, &d->d5}) {
      if (integrator == Integrator::Gear5) {
        higher->assign(n, Vec3::Zero());
      } else {
        std::vector<Vec3>().swap(*higher);  // Verlet keeps only the acceleration
      }
    }
  }
  s.config.integrator = integrator;
  if (s.config.step.automatic) checkStep(s);  // the new integrator's interval
}

void Simulation::setThreads(int threads) {
  require(threads >= 0, "threads = " + std::to_string(threads) + ": must be >= 0");
  state_->config.threads = threads;
}

void Simulation::setExactSums(bool exact) {
  SimulationState& s = *state_;
  s.config.exactSums = exact;
  if (s.steps == 0) startLedger(s);  // the starting values summed alike
}

void Simulation::setOwnership(std::vector<std::uint8_t> owned,
                              std::shared_ptr<const Communicator> ranks) {
  SimulationState& s = *state_;
  require(owned.size() == s.particles.size(),
          "ownership: " + std::to_string(owned.size()) + " flags for " +
              std::to_string(s.particles.size()) + " particles");
  require(ranks != nullptr, "ownership: the ranks to merge over must be given");
  s.owned = std::move(owned);
  s.ranks = std::move(ranks);
  s.config.exactSums = true;
  if (s.steps == 0) startLedger(s);
}

void Simulation::splitAmong(std::shared_ptr<const DomainMap> domains,
                            std::shared_ptr<const Communicator> ranks) {
  SimulationState& s = *state_;
  splitState(s, std::move(domains), std::move(ranks));
  if (s.steps == 0) startLedger(s);
}

Simulation Simulation::wholeState() const {
  const SimulationState& s = *state_;
  if (!s.split.domains) return Simulation(std::make_unique<SimulationState>(s));
  return Simulation(gatherWhole(s));
}

std::uint64_t Simulation::globalId(std::size_t i) const {
  const SimulationState& s = *state_;
  return s.split.globalId.empty() ? i : s.split.globalId.at(i);
}

const Communicator* Simulation::ranks() const {
  return state_->split.domains ? state_->ranks.get() : nullptr;
}

bool Simulation::owns(std::size_t i) const {
  const SimulationState& s = *state_;
  return s.owned.empty() || s.owned.at(i) != 0;
}

void Simulation::setWallVelocity(std::size_t wall, const Vec3& velocity) {
  require(velocity.allFinite(), "wall velocity must be finite");
  state_->walls.at(wall).velocity = velocity;
}

long Simulation::findWall(const std::string& name) const {
  const auto& w = state_->walls;
  for (std::size_t k = 0; k < w.size(); ++k) {
    if (w[k].name == name) return static_cast<long>(k);
  }
  return -1;
}

double Simulation::kineticEnergy() const {
  ParticleSums sums = particleSums(*state_);
  sums.translational.merge(sums.rotational);
  return sums.translational.value();
}

namespace {

/// The Slip of a group: −Work − (Stored − its start) − Dissipated + Supplied, over the group's
/// accounts, in that order.
double slip(const SimulationState& s, std::string_view group) {
  const EnergyAccumulators& e = s.energy;
  double value = 0.0;
  for (EnergyKind kind :
       {EnergyKind::Work, EnergyKind::Stored, EnergyKind::Dissipated, EnergyKind::Supplied}) {
    for (const EnergyAccountSpec& a : energyAccounts()) {
      if (a.account.group != group || a.account.kind != kind) continue;
      switch (kind) {
        case EnergyKind::Work:
          value -= e.account[a.slot];
          break;
        case EnergyKind::Stored:
          value -= s.powers.energy[a.slot] - e.initialStored[a.slot];
          break;
        case EnergyKind::Dissipated:
          value -= e.account[a.slot];
          break;
        case EnergyKind::Supplied:
          value += e.account[a.slot];
          break;
        case EnergyKind::Slip:
          break;
      }
    }
  }
  return value;
}

}  // namespace

EnergyBalance Simulation::energy() const {
  const SimulationState& s = *state_;
  EnergyBalance b;
  const ParticleSums sums = particleSums(s);
  b.kineticTranslational = sums.translational.value();
  b.kineticRotational = sums.rotational.value();
  const double potential = sums.potential.value();
  const EnergyAccumulators& e = s.energy;
  // Each column's value; a Slip account is what its group's forces took from the particles and
  // neither its springs nor its dashpots hold: −W − ΔE_s − D + S.
  for (const EnergyAccountSpec& column : energyColumns(s.config.material)) {
    const std::size_t slot = column.slot;
    double value = 0.0;
    switch (column.account.kind) {
      case EnergyKind::Stored:
        value = s.powers.energy[slot];
        break;
      case EnergyKind::Dissipated:
      case EnergyKind::Supplied:
      case EnergyKind::Work:
        value = e.account[slot];
        break;
      case EnergyKind::Slip:
        value = slip(s, column.account.group);
        break;
    }
    b.contact.push_back({column.account.column, column.account.kind, value});
  }
  b.gravityWork = potential - e.initialPotential;
  b.wallWork = e.wallWork;
  return b;
}

void Simulation::forEachContact(const std::function<void(const ContactView&)>& visit) const {
  visitContacts(*state_, visit, nullptr);
}

std::vector<Vec3> Simulation::netContactForces() const {
  std::vector<Vec3> net;
  visitContacts(*state_, nullptr, &net);
  return net;
}

namespace {

template <class T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}
template <class T>
std::size_t bytes(const std::vector<std::vector<T>>& v) {
  std::size_t total = v.capacity() * sizeof(std::vector<T>);
  for (const auto& inner : v) total += bytes(inner);
  return total;
}

}  // namespace

MemoryUse Simulation::memoryUse() const {
  const SimulationState& s = *state_;
  const Particles& p = s.particles;
  MemoryUse m;
  m.particles = bytes(p.position) + bytes(p.velocity) + bytes(p.angularVelocity) + bytes(p.radius) +
                bytes(p.mass);
  m.integrator = bytes(s.force) + bytes(s.torque);
  for (const Derivatives* d : {&s.translation, &s.rotation}) {
    m.integrator += bytes(d->d2) + bytes(d->d3) + bytes(d->d4) + bytes(d->d5);
  }
  const NeighbourList& l = s.neighbours;
  m.neighbours = bytes(l.rowStart) + bytes(l.second) + bytes(l.wallParticles) +
                 bytes(l.referencePosition) + bytes(l.referenceWallPoint);
  m.history = bytes(l.springs.held) + bytes(l.springs.block) + bytes(l.wallHistory);
  const ForcePlan& x = l.plan;
  m.forcePlan = bytes(l.blockParticle) + bytes(l.blockPair) + bytes(l.blockWord) +
                bytes(x.blockWall) + bytes(x.threadBlock) + bytes(x.crossing) +
                bytes(x.crossingFirst) + bytes(x.incoming) + bytes(x.incomingStart);
  const ContactScratch& c = s.contactScratch;
  m.scratch = bytes(c.crossingSpring) + bytes(c.springsSetAside) + bytes(c.blockPowers) +
              bytes(c.blockReaction) + bytes(c.partPowers);
  for (const ExactPowers& part : c.partPowers) m.scratch += bytes(part.reaction);
  return m;
}

std::uint64_t Simulation::stateHash() const {
  const Particles& p = state_->particles;
  std::uint64_t h = 1469598103934665603ULL;
  auto mix = [&h](const Vec3& v) {
    for (int k = 0; k < 3; ++k) {
      std::uint64_t bits;
      const double x = v[k];
      std::memcpy(&bits, &x, sizeof bits);
      for (int b = 0; b < 8; ++b) {
        h ^= (bits >> (8 * b)) & 0xffU;
        h *= 1099511628211ULL;
      }
    }
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    mix(p.position[i]);
    mix(p.velocity[i]);
    mix(p.angularVelocity[i]);
  }
  return h;
}

}  // namespace granular
