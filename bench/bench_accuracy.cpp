/// granular_bench_accuracy: speed against error of Gear5 and velocity Verlet. At several time
/// steps, each integrator's wall time and its error against a reference run at a much smaller
/// step, on a Hooke and a Hertz two-sphere impact (restitution, duration) and on σ33(t) of the
/// paper's stage 2 restored from the settled checkpoints of `granular paper`. Writes a CSV of
/// every run, a markdown summary and an error-against-wall-time figure (bench/RESULTS.md,
/// "Speed against error").
///
/// Usage: granular_bench_accuracy [--run DIR] [--out DIR] [--scenes DIR] [--quick]
/// Exit status: 0 done, 1 I/O error, 2 missing or unusable checkpoint, bad scene or option.
///
/// Sections: 1. the plan; 2. impacts; 3. stage 2; 4. conclusions; 5. files (CSV, markdown,
/// figure); 6. the program.
///
/// Error metrics (all relative, against the reference run of the same case):
/// - impacts: |e − e_ref| / e_ref for the restitution and |T − T_ref| / T_ref for the overlap
///   duration, the largest over 8 phases of the first touch within a step; the closed form of
///   contact_theory.hpp is reported beside the reference.
/// - stage 2: max over the 0.01 s samples with t ≥ 0.1 s of |σ33(t) − σ33_ref(t)| / |σ33_ref(t)|,
///   for Eq. (1) and for Eq. (2) separately; σ33 is the mean over each 0.01 s interval (the
///   trapezoid rule on every step, for Eq. (1) and for the wall reactions of Eq. (2)). Δt is
///   rounded down to divide the interval, so every run averages over the same windows.
/// Wall time counts the stepping only: building an impact and measuring the stresses are not
/// timed. Everything runs on one thread, so that the two shared cores time less noisily.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "csv_output.hpp"
#include "granular/checkpoint.hpp"
#include "granular/error.hpp"
#include "granular/impact_probe.hpp"
#include "granular/render/plot.hpp"
#include "granular/scene_fingerprint.hpp"
#include "granular/series_error.hpp"
#include "granular/stage.hpp"
#include "granular/stress.hpp"
#include "paper_reference.hpp"
#include "run_header.hpp"

namespace granular::bench {
namespace {

// The app's file writers, number format and exit-status mapping, and the paper's two cases:
// the benchmark's outputs and errors read like `granular paper`'s.
using app::createOutputFolder;
using app::csvNumber;
using app::format;
using app::kPaperCases;
using app::PaperReference;
using app::withErrorMapping;
using app::writeTextFile;

struct Options {
  std::filesystem::path runDir = "runs/paper";  ///< `granular paper --out` folder (checkpoints)
  std::filesystem::path outDir = "runs/bench-accuracy";   ///< where the results go
  std::filesystem::path scenesDir = GRANULAR_SCENES_DIR;  ///< paper-mu0.toml, paper-mu03.toml
  /// Fewer steps, a coarser reference, stage 2 of μ = 0.3 only and cut to 0.3 s: a smoke run
  /// of about 15 s, not a result.
  bool quick = false;
};

using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// 1. The plan -------------------------------------------------------------------------------

/// A step t_c/10 would land on the core's stability limit 0.1·t_c and could be refused by one
/// unit of round-off; this factor keeps every step just inside.
constexpr double kInsideLimit = 1.0 - 1e-9;

struct Plan {
  std::vector<double> impactFractions;  ///< t_c/Δt of the impact runs compared [-]
  std::vector<double> stageFractions;   ///< t_c/Δt of the stage-2 runs compared [-]
  double impactReference = 0;           ///< t_c/Δt of the impacts' reference run [-]
  double stageReference = 0;            ///< t_c/Δt of stage 2's reference run [-]
  double impactTiming = 0;              ///< wall time spent repeating each impact, at least [s]
  double stageDuration = 0;             ///< stage 2 simulated [s] (the paper's: 1)
  double errorFrom = 0.1;               ///< σ33 errors count from this stage-2 time on [s]
  /// Stage 2 at time_step = "auto" (velocity Verlet): its accuracy floors t_c/N [-].
  std::vector<double> autoResolutions;
  std::vector<const PaperReference*> stageCases;  ///< μ = 0.3 first: the main case
};

Plan makePlan(bool quick) {
  Plan p;
  if (quick) {
    p.impactFractions = p.stageFractions = {10, 20, 50};
    p.impactReference = 20000;
    p.stageReference = 200;
    p.impactTiming = 0.01;
    p.stageDuration = 0.3;
    p.stageCases = {&kPaperCases[1]};
    p.autoResolutions = {10};
  } else {
    // The damped Hooke restitution converges at first order only: t_c/400 shows where it
    // reaches 0.1 %. Stage 2 costs 10⁴ times more per step and needs no such fine step.
    p.impactFractions = {10, 15, 20, 30, 50, 100, 200, 400};
    p.stageFractions = {10, 15, 20, 30, 50, 100, 200};
    // Impacts cost microseconds: the reference can afford 10⁵ steps per contact, far below
    // the first-order error of the damped Hooke contact at the finest compared step.
    p.impactReference = 100000;
    p.stageReference = 800;
    p.impactTiming = 0.2;
    p.stageDuration = 1.0;
    p.stageCases = {&kPaperCases[1], &kPaperCases[0]};
    p.autoResolutions = {10, 1};
  }
  return p;
}

const char* integratorName(Integrator i) {
  return i == Integrator::Gear5 ? "gear5" : "verlet";
}
const char* integratorLabel(Integrator i) {
  return i == Integrator::Gear5 ? "Gear5" : "velocity Verlet";
}
constexpr Integrator kIntegrators[] = {Integrator::Gear5, Integrator::VelocityVerlet};

/// Steps the core refuses are not run: Gear5 is limited to t_c/50 (it gains energy in a damped
/// bed above that), velocity Verlet to t_c/10.
bool allowed(Integrator integrator, double fraction) {
  const double limit =
      integrator == Integrator::Gear5 ? kMaxStepFractionGear5 : kMaxStepFractionVerlet;
  return 1.0 / fraction <= limit * (1.0 + 1e-12);
}

/// What a run is for. The reference check (velocity Verlet at the reference step) measures how
/// far the reference itself can be trusted: the two schemes should agree there.
enum class Role { Run, Reference, ReferenceCheck };

const char* roleName(Role r) {
  return r == Role::Run ? "run" : (r == Role::Reference ? "reference" : "reference_check");
}

/// One run of one case: what the CSV and the tables hold. Unused fields stay NaN.
struct Row {
  std::string caseName;  ///< hooke_impact, hertz_impact, stage2_mu03, stage2_mu0
  Integrator integrator = Integrator::Gear5;
  Role role = Role::Run;
  double contactDuration = 0;  ///< t_c [s]
  double fraction = 0;         ///< t_c/Δt [-]; with `automatic`, the floor's N
  bool automatic = false;      ///< time_step = "auto" (stage 2): Δt is the largest step taken
  double timeStep = 0;         ///< Δt [s]
  double wallSeconds = 0;      ///< per impact, or per stage-2 run [s]
  long repetitions = 1;        ///< impacts timed per row
  std::uint64_t steps = 0;     ///< per impact or per stage-2 run
  double restitution = kNaN;   ///< mean over the touch phases [-]
  double duration = kNaN;      ///< overlap duration, mean over the touch phases [s]
  double restitutionError = kNaN, durationError = kNaN;              ///< vs reference [-]
  double restitutionTheoryError = kNaN, durationTheoryError = kNaN;  ///< vs closed form [-]
  double sigma33Eq1 = kNaN, sigma33Eq2 = kNaN;                       ///< at the last sample [Pa]
  double eq1Error = kNaN, eq2Error = kNaN;  ///< max relative deviation over t ≥ 0.1 s [-]

  bool impact() const { return !std::isnan(restitution); }
  /// The larger of the case's two errors: an accuracy target asks both.
  double worstError() const {
    return impact() ? std::max(restitutionError, durationError) : std::max(eq1Error, eq2Error);
  }
};

// 2. Impacts --------------------------------------------------------------------------------

struct ImpactCase {
  const char* name;
  PairImpactSpec spec;
};

std::vector<ImpactCase> impactCases() {
  ImpactCase hooke{"hooke_impact", {}};
  hooke.spec.material = Material{};  // the paper's Table, μ = 0
  ImpactCase hertz{"hertz_impact", {}};
  hertz.spec.material.normalLaw = NormalLaw::Hertz;
  hertz.spec.material.normalDamping = 0.0;  // Hertz has a closed form only without damping
  return {hooke, hertz};
}

/// Each compared impact is run with the first touch at this many phases spread evenly over a
/// step (gapForTouchPhase), and its error is the largest over them.
constexpr int kTouchPhases = 8;

/// An impact row and the measurement at each touch phase.
struct ImpactRun {
  Row row;
  std::vector<ImpactMeasurement> phases;
};

/// Runs the impact at Δt = t_c/fraction for each of `phases` touch phases, repeating the set
/// until `timing` seconds of stepping have been spent (at least three times), so that runs of
/// microseconds are timed reliably.
ImpactRun runImpact(const ImpactCase& c, Integrator integrator, double fraction, int phases,
                    double timing) {
  const ImpactPrediction theory = *predictPairImpact(c.spec);
  PairImpactSpec spec = c.spec;
  spec.integrator = integrator;
  spec.timeStep = theory.forceDuration / fraction * kInsideLimit;
  ImpactRun run;
  Row& row = run.row;
  row.caseName = c.name;
  row.integrator = integrator;
  row.contactDuration = theory.forceDuration;
  row.fraction = fraction;
  row.timeStep = spec.timeStep;
  double spent = 0;
  long reps = 0;
  while ((spent < timing || reps < 3) && reps < 10'000'000) {
    for (int j = 0; j < phases; ++j) {
      spec.initialGap = gapForTouchPhase(spec, (j + 0.5) / phases);
      Simulation sim = makePairImpact(spec);
      const auto start = Clock::now();
      const ImpactMeasurement m =
          measurePairImpact(sim, spec.approachSpeed, 50 * theory.forceDuration);
      spent += secondsSince(start);
      if (!m.separated) {
        throw std::runtime_error(std::string(c.name) + ": the spheres did not separate");
      }
      if (reps == 0) run.phases.push_back(m);
    }
    ++reps;
  }
  row.repetitions = reps * phases;
  row.wallSeconds = spent / double(row.repetitions);
  row.restitution = row.duration = 0;
  row.restitutionTheoryError = row.durationTheoryError = 0;
  for (const ImpactMeasurement& m : run.phases) {
    row.steps = std::max(row.steps, m.steps);
    row.restitution += m.restitution / phases;
    row.duration += m.overlapDuration / phases;
    row.restitutionTheoryError =
        std::max(row.restitutionTheoryError, relativeDeviation(m.restitution, theory.restitution));
    row.durationTheoryError = std::max(
        row.durationTheoryError, relativeDeviation(m.overlapDuration, theory.overlapDuration));
  }
  return run;
}

std::vector<Row> impactRows(const Plan& plan) {
  std::vector<Row> rows;
  for (const ImpactCase& c : impactCases()) {
    std::vector<ImpactRun> runs;
    for (Integrator i : kIntegrators) {
      // The references: one phase, timed once (their cost is not the point).
      runs.push_back(runImpact(c, i, plan.impactReference, 1, 0.0));
      runs.back().row.role = i == Integrator::Gear5 ? Role::Reference : Role::ReferenceCheck;
      for (double f : plan.impactFractions) {
        if (!allowed(i, f)) continue;
        runs.push_back(runImpact(c, i, f, kTouchPhases, plan.impactTiming));
      }
    }
    const ImpactMeasurement ref = runs.front().phases.front();  // Gear5 at the reference step
    for (ImpactRun& run : runs) {
      Row& r = run.row;
      r.restitutionError = r.durationError = 0;
      for (const ImpactMeasurement& m : run.phases) {
        r.restitutionError =
            std::max(r.restitutionError, relativeDeviation(m.restitution, ref.restitution));
        r.durationError =
            std::max(r.durationError, relativeDeviation(m.overlapDuration, ref.overlapDuration));
      }
      std::cout << c.name << ' ' << integratorName(r.integrator) << " t_c/" << r.fraction << ": "
                << format("%.3g", 1e6 * r.wallSeconds) << " us per impact, restitution error "
                << format("%.2e", r.restitutionError) << ", duration error "
                << format("%.2e", r.durationError) << std::endl;  // a line per run, as it ends
      rows.push_back(r);
    }
  }
  return rows;
}

// 3. Stage 2 --------------------------------------------------------------------------------

/// One friction case of the paper, ready to restore.
struct StageCase {
  const PaperReference* paper = nullptr;
  std::filesystem::path checkpoint;
  SceneFingerprint fingerprint;  ///< of the scene: a stale checkpoint is refused
  StageSpec stage;               ///< the scene's stage 2
  OutputSpec output;
};

StageCase loadStageCase(const PaperReference& paper, const Options& options) {
  StageCase c;
  c.paper = &paper;
  c.checkpoint = options.runDir / paper.name / "settled.ckpt";
  const std::filesystem::path sceneFile = options.scenesDir / paper.scene;
  const std::string make = "make it with `granular paper --out " + options.runDir.string() + "`";
  if (!std::filesystem::exists(c.checkpoint)) {
    throw CheckpointError(c.checkpoint.string() + ": no settled checkpoint (--run " +
                          options.runDir.string() + "); " + make);
  }
  const Scene scene = loadScene(sceneFile);
  if (scene.stages.size() != 2 || !scene.stages[1].placeTopWallOnSurface) {
    throw ConfigError(sceneFile.string() + ": not a two-stage compaction scene");
  }
  c.fingerprint = fingerprintScene(scene);
  try {
    readCheckpoint(c.checkpoint, c.fingerprint);
  } catch (const CheckpointError& e) {
    throw CheckpointError(std::string(e.what()) + "; " + make);
  }
  c.stage = scene.stages[1];
  c.output = scene.output;
  c.output.snapshotTimes.clear();
  return c;
}

/// Eq. (1) and the wall reactions averaged over each output interval by the trapezoid rule on
/// every step. The paper command (compaction.cpp) averages ten Eq. (1) samples an interval and
/// takes the reactions from the wall impulses, a right-endpoint sum: both are first order in Δt
/// themselves, and on the slowly changing stresses of stage 2 that quadrature error is as large
/// as the integration error being measured. With the trapezoid rule on the same windows (Δt
/// divides the interval) what differs between runs is the integration alone.
class IntervalMeans {
 public:
  explicit IntervalMeans(const Simulation& sim)
      : previous_(now(sim)), lastStep_(sim.stepCount()), lastTime_(sim.time()) {}

  /// Adds the step just taken (once, however often it is called for that step).
  void advance(const Simulation& sim) {
    if (sim.stepCount() == lastStep_) return;
    lastStep_ = sim.stepCount();
    // Weighted by the step just taken: at time_step = "auto" the steps differ.
    const double dt = sim.time() - lastTime_;
    lastTime_ = sim.time();
    const Point current = now(sim);
    sum_.sums.eq1 += 0.5 * dt * (previous_.sums.eq1 + current.sums.eq1);
    sum_.sums.sideFrictionMoment +=
        0.5 * dt * (previous_.sums.sideFrictionMoment + current.sums.sideFrictionMoment);
    sum_.reactions.resize(current.reactions.size(), Vec3::Zero());
    for (std::size_t w = 0; w < current.reactions.size(); ++w) {
      sum_.reactions[w] += 0.5 * dt * (previous_.reactions[w] + current.reactions[w]);
    }
    previous_ = current;
    duration_ += dt;
    ++steps_;
  }

  /// The mean over the interval ending now (the first, at t = 0, is the instantaneous state);
  /// starts the next interval.
  BoxStress close(const Simulation& sim) {
    advance(sim);
    Point mean = steps_ == 0 ? previous_ : sum_;
    if (steps_ > 0) {
      mean.sums.eq1 /= duration_;
      mean.sums.sideFrictionMoment /= duration_;
      for (Vec3& r : mean.reactions) r /= duration_;
    }
    sum_ = Point{};
    steps_ = 0;
    duration_ = 0;
    return measureBox(sim, mean.reactions, &mean.sums);
  }

 private:
  struct Point {
    BoxContactSums sums;
    std::vector<Vec3> reactions;  ///< per wall [N]
  };
  static Point now(const Simulation& sim) {
    Point p{boxContactSums(sim), {}};
    for (const Wall& w : sim.walls()) p.reactions.push_back(w.reaction);
    return p;
  }
  Point previous_;  ///< at the last step taken
  Point sum_;       ///< trapezoid sums of the current interval
  std::uint64_t lastStep_ = 0;
  double lastTime_ = 0;  ///< the clock at the last step taken [s]
  long steps_ = 0;
  double duration_ = 0;  ///< of the current interval so far [s]
};

struct StageRun {
  Row row;
  SampledSeries eq1, eq2;  ///< σ33 [Pa] against the stage clock [s]
};

/// Stage 2 of `c` from its settled checkpoint (restored afresh), with `integrator` at
/// Δt = t_c/fraction, t_c the stiffest contact's duration; with `automatic`, at
/// time_step = "auto" with the accuracy floor t_c/fraction.
StageRun runStageCase(const StageCase& c, Integrator integrator, double fraction, const Plan& plan,
                      bool automatic = false) {
  Simulation sim = readCheckpoint(c.checkpoint, c.fingerprint);
  sim.setIntegrator(integrator);
  sim.setThreads(1);
  const double tc = sim.contactScale().duration;
  if (automatic) {
    // The stage lands its steps on every output interval itself.
    StepControl control;
    control.automatic = true;
    control.contactResolution = fraction;
    sim.setStepControl(control);
  } else {
    // A whole number of steps per output interval: every run then averages over exactly the
    // same time windows, and what differs between runs is the integration alone.
    const double interval = c.output.interval;
    const double perInterval = std::ceil(interval * fraction / tc);
    sim.setTimeStep(std::min(interval / perInterval,
                             maxStableStep(sim.contactScale(), integrator) * kInsideLimit));
  }
  StageSpec stage = c.stage;
  stage.end.maxTime = plan.stageDuration;

  StageRun run;
  std::optional<IntervalMeans> means;
  double measuring = 0;
  StageObserver observer;
  observer.onSample = [&](const Simulation& s) {
    const auto start = Clock::now();
    if (!means) means.emplace(s);  // at t = 0, once the top wall is in place
    const BoxStress b = means->close(s);
    run.eq1.time.push_back(s.time());
    run.eq1.value.push_back(b.eq1(2, 2));
    run.eq2.time.push_back(s.time());
    run.eq2.value.push_back(b.eq2.z());
    measuring += secondsSince(start);
  };
  observer.progressSteps = 1;
  observer.onProgress = [&](const Simulation& s, const StageSpec&) {
    const auto start = Clock::now();
    if (means) means->advance(s);
    measuring += secondsSince(start);
  };
  const auto start = Clock::now();
  const StageResult result = runStage(sim, stage, c.output, observer);
  Row& row = run.row;
  row.caseName = std::string("stage2_") + c.paper->name;
  row.integrator = integrator;
  row.contactDuration = tc;
  row.fraction = fraction;
  row.automatic = automatic;
  row.timeStep = automatic ? sim.counters().largestStep : sim.config().timeStep;
  row.wallSeconds = secondsSince(start) - measuring;
  row.steps = result.steps;
  row.sigma33Eq1 = run.eq1.value.back();
  row.sigma33Eq2 = run.eq2.value.back();
  return run;
}

/// The rows of every stage-2 run; `series` receives the runs themselves (for their σ33 series).
std::vector<Row> stageRows(const std::vector<StageCase>& cases, const Plan& plan,
                           std::vector<StageRun>& series) {
  std::vector<Row> rows;
  for (const StageCase& c : cases) {
    std::vector<StageRun> runs;
    for (Integrator i : kIntegrators) {
      runs.push_back(runStageCase(c, i, plan.stageReference, plan));
      runs.back().row.role = i == Integrator::Gear5 ? Role::Reference : Role::ReferenceCheck;
      for (double f : plan.stageFractions) {
        if (allowed(i, f)) runs.push_back(runStageCase(c, i, f, plan));
      }
    }
    for (double n : plan.autoResolutions) {
      runs.push_back(runStageCase(c, Integrator::VelocityVerlet, n, plan, true));
    }
    const StageRun& ref = runs.front();  // Gear5 at the reference step
    for (StageRun& r : runs) {
      r.row.eq1Error = maxRelativeDeviation(r.eq1, ref.eq1, plan.errorFrom);
      r.row.eq2Error = maxRelativeDeviation(r.eq2, ref.eq2, plan.errorFrom);
    }
    for (StageRun& r : runs) {
      std::cout << r.row.caseName << ' ' << integratorName(r.row.integrator)
                << (r.row.automatic ? " auto, at most t_c/" : " t_c/") << r.row.fraction << ": "
                << format("%.2f", r.row.wallSeconds) << " s, sigma33 error Eq. (1) "
                << format("%.2e", r.row.eq1Error) << ", Eq. (2) " << format("%.2e", r.row.eq2Error)
                << std::endl;
      rows.push_back(r.row);
      series.push_back(std::move(r));
    }
  }
  return rows;
}

// 4. Conclusions ----------------------------------------------------------------------------

/// The largest step (cheapest run) of `integrator` in `caseName` whose worst error is within
/// `target` and stays within it at every smaller step compared: a step that meets the target by
/// a lucky cancellation, with a finer step failing, does not count.
const Row* cheapestWithin(const std::vector<Row>& rows, const std::string& caseName,
                          Integrator integrator, double target) {
  std::vector<const Row*> runs;
  for (const Row& r : rows) {
    if (r.caseName == caseName && r.integrator == integrator && r.role == Role::Run && !r.automatic)
      runs.push_back(&r);
  }
  std::sort(runs.begin(), runs.end(),
            [](const Row* a, const Row* b) { return a->fraction > b->fraction; });  // fine first
  const Row* best = nullptr;
  for (const Row* r : runs) {
    if (!(r->worstError() <= target)) break;
    best = r;
  }
  return best;
}

std::string percent(double x) {
  return format(x >= 0.01 ? "%.0f %%" : (x >= 0.001 ? "%.1f %%" : "%.2f %%"), 100 * x);
}

/// One line per case and target: the cheapest step of each integrator and which is faster.
std::string conclusions(const std::vector<Row>& rows, const std::vector<std::string>& cases) {
  std::ostringstream out;
  for (const std::string& c : cases) {
    const bool impact = c.find("impact") != std::string::npos;
    // The stage-2 stresses turn out far less sensitive to the step than the impacts: a finer
    // target separates the integrators there.
    const std::vector<double> targets =
        impact ? std::vector<double>{0.01, 0.001} : std::vector<double>{0.01, 0.001, 0.0001};
    for (double target : targets) {
      out << "- " << c << ", " << (impact ? "restitution and duration" : "σ33 Eq. (1) and (2)")
          << " within " << percent(target) << ": ";
      const Row* best[2] = {cheapestWithin(rows, c, Integrator::Gear5, target),
                            cheapestWithin(rows, c, Integrator::VelocityVerlet, target)};
      for (int k = 0; k < 2; ++k) {
        out << (k ? "; " : "") << integratorLabel(kIntegrators[k]) << ' ';
        if (best[k]) {
          out << "t_c/" << best[k]->fraction << " ("
              << format(impact ? "%.3g µs" : "%.3g s", (impact ? 1e6 : 1.0) * best[k]->wallSeconds)
              << ')';
        } else {
          out << "not reached at any step compared";
        }
      }
      if (best[0] && best[1]) {
        const bool gearWins = best[0]->wallSeconds < best[1]->wallSeconds;
        const double ratio = gearWins ? best[1]->wallSeconds / best[0]->wallSeconds
                                      : best[0]->wallSeconds / best[1]->wallSeconds;
        // One run per stage-2 row on a shared machine: under 15 % is within the timing noise.
        // At the same step the ratio is the cost of a step alone, which for two spheres is the
        // engine's fixed overhead and says nothing of the schemes.
        if (best[0]->fraction == best[1]->fraction) {
          out << " → the same step for both (wall-time ratio " << format("%.2f", ratio) << "×, "
              << (gearWins ? "Gear5" : "velocity Verlet") << " ahead)";
        } else if (ratio < 1.15) {
          out << " → equally fast within timing noise (" << format("%.2f", ratio) << "×)";
        } else {
          out << " → " << (gearWins ? "Gear5" : "velocity Verlet") << ' ' << format("%.2g", ratio)
              << "× faster";
        }
      }
      out << '\n';
    }
  }
  return out.str();
}

// 5. Files ----------------------------------------------------------------------------------

std::string cell(double x) {
  return std::isnan(x) ? "" : csvNumber(x);
}

void writeRowsCsv(const std::filesystem::path& path, const std::vector<Row>& rows) {
  std::ostringstream out;
  out << "case,integrator,role,tc_s,dt_s,dt_over_tc,wall_s,repetitions,steps,restitution,"
         "restitution_error,restitution_error_closed_form,duration_s,duration_error,"
         "duration_error_closed_form,s33_eq1_final_Pa,s33_eq1_error,s33_eq2_final_Pa,"
         "s33_eq2_error\n";
  for (const Row& r : rows) {
    out << r.caseName << ',' << integratorName(r.integrator) << ','
        << (r.automatic ? "auto" : roleName(r.role)) << ',' << cell(r.contactDuration) << ','
        << cell(r.timeStep) << ',' << cell(r.timeStep / r.contactDuration) << ','
        << cell(r.wallSeconds) << ',' << r.repetitions << ',' << r.steps << ','
        << cell(r.restitution) << ',' << cell(r.restitutionError) << ','
        << cell(r.restitutionTheoryError) << ',' << cell(r.duration) << ',' << cell(r.durationError)
        << ',' << cell(r.durationTheoryError) << ',' << cell(r.sigma33Eq1) << ','
        << cell(r.eq1Error) << ',' << cell(r.sigma33Eq2) << ',' << cell(r.eq2Error) << '\n';
  }
  writeTextFile(path, out.str());
}

void writeSeriesCsv(const std::filesystem::path& path, const std::vector<StageRun>& series) {
  std::ostringstream out;
  out << "case,integrator,tc_over_dt,time_s,s33_eq1_Pa,s33_eq2_Pa\n";
  for (const StageRun& run : series) {
    const Row& row = run.row;
    for (std::size_t k = 0; k < run.eq1.time.size(); ++k) {
      out << row.caseName << ',' << integratorName(row.integrator) << ','
          << (row.automatic ? "auto_" : "") << row.fraction << ',' << csvNumber(run.eq1.time[k])
          << ',' << csvNumber(run.eq1.value[k]) << ',' << csvNumber(run.eq2.value[k]) << '\n';
    }
  }
  writeTextFile(path, out.str());
}

std::string refTag(const Row& r) {
  return r.role == Role::Reference ? " (reference)"
                                   : (r.role == Role::ReferenceCheck ? " (check)" : "");
}

std::string sci(double x) {
  return std::isnan(x) ? "–" : format("%.1e", x);
}

/// "t_c/10 becomes t_c/10.5" for the coarsest stage-2 run.
std::string roundedStepExample(const std::vector<Row>& rows) {
  for (const Row& r : rows) {
    if (!r.impact() && r.role == Role::Run) {
      return "t_c/" + format("%g", r.fraction) + " becomes t_c/" +
             format("%.3g", r.contactDuration / r.timeStep);
    }
  }
  return "no stage-2 run";
}

std::string markdown(const std::vector<Row>& rows, const Plan& plan,
                     const std::vector<std::string>& cases, const std::string& load) {
  std::ostringstream out;
  out << "Impacts: two spheres R = 0.03 m head-on at 0.5 m/s (ρ = 500 kg/m³, E = 0.3 MPa, "
         "ν = 0.3); reference Gear5 at t_c/"
      << plan.impactReference << "; each run repeated with the first touch at " << kTouchPhases
      << " phases within a step: e and T are their means, the errors their maxima; wall time per "
      << "impact (stepping only, mean of ≥ 3 repetitions and ≥ " << plan.impactTiming << " s).\n\n";
  out << "| case | integrator | Δt | wall per impact [µs] | e | e error | e error (closed form) "
         "| T [ms] | T error | T error (closed form) |\n|---|---|---|---:|---:|---:|---:|---:|"
         "---:|---:|\n";
  for (const Row& r : rows) {
    if (!r.impact()) continue;
    out << "| " << r.caseName << " | " << integratorLabel(r.integrator) << " | t_c/" << r.fraction
        << refTag(r) << " | " << format("%.3g", 1e6 * r.wallSeconds) << " | "
        << format("%.5f", r.restitution) << " | "
        << (r.role == Role::Reference ? "–" : sci(r.restitutionError)) << " | "
        << sci(r.restitutionTheoryError) << " | " << format("%.4f", 1e3 * r.duration) << " | "
        << (r.role == Role::Reference ? "–" : sci(r.durationError)) << " | "
        << sci(r.durationTheoryError) << " |\n";
  }
  out << "\nStage 2: restored from the settled checkpoint, top wall at −0.01 m/s for "
      << plan.stageDuration << " s; t_c = stiffest contact's duration; reference Gear5 at t_c/"
      << plan.stageReference << "; error = max over t ∈ [" << plan.errorFrom << ", "
      << plan.stageDuration << "] s of |σ33 − σ33,ref| / |σ33,ref| (0.01 s interval means, "
      << "trapezoid rule on every step); Δt rounded down so that 0.01 s is a whole number of "
      << "steps (" << roundedStepExample(rows) << "); wall time of the stepping, one thread. "
      << "Rows \"auto\": time_step = \"auto\" with velocity Verlet and the accuracy floor named "
      << "(its steps land on every 0.01 s; Δt is the largest it took).\n\n";
  out << "| case | integrator | Δt | Δt [s] | steps | wall [s] | σ33(t_end) Eq. (1) [Pa] | "
         "σ33 error Eq. (1) | σ33(t_end) Eq. (2) [Pa] | σ33 error Eq. (2) |\n"
         "|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const Row& r : rows) {
    if (r.impact()) continue;
    out << "| " << r.caseName << " | " << integratorLabel(r.integrator)
        << (r.automatic ? " | auto, at most t_c/" : " | t_c/") << r.fraction << refTag(r) << " | "
        << format("%.3g", r.timeStep) << " | " << r.steps << " | " << format("%.2f", r.wallSeconds)
        << " | " << format("%.1f", r.sigma33Eq1) << " | "
        << (r.role == Role::Reference ? "–" : sci(r.eq1Error)) << " | "
        << format("%.1f", r.sigma33Eq2) << " | "
        << (r.role == Role::Reference ? "–" : sci(r.eq2Error)) << " |\n";
  }
  out << "\nCheapest step that reaches each target and keeps it at every finer step compared:\n\n"
      << conclusions(rows, cases) << "\nLoad average (1, 5, 15 min): " << load << '\n';
  return out.str();
}

/// Error against wall time on logarithmic axes (decades labelled 10⁻⁴), one panel per case:
/// colour = integrator, solid circles = restitution or Eq. (1), dashed squares = duration or
/// Eq. (2); each point of the first quantity labelled with its t_c/Δt. The panels fill their
/// grid: one row of up to three (--quick has three cases), two columns for four.
render::Image accuracyFigure(const std::vector<Row>& rows, const std::vector<std::string>& cases,
                             const Plan& plan) {
  constexpr double kDpi = 150.0;
  const render::FigureStyle style = render::FigureStyle::forDpi(kDpi);
  const int count = std::max(1, int(cases.size()));
  const int columns = count <= 3 ? count : 2, panelW = 1050, panelH = 780, titleH = 90;
  const int panelRows = (count + columns - 1) / columns;
  render::Canvas canvas(columns * panelW, titleH + panelRows * panelH);
  render::TextStyle title;
  title.size = style.px(style.titleFontSize * 1.15);
  title.hAlign = render::HAlign::Center;
  title.vAlign = render::VAlign::Middle;
  canvas.text({0.5 * canvas.width(), 0.5 * titleH},
              "Speed against error: Gear5 and velocity Verlet, Δt = t_c/" +
                  format("%g", plan.impactFractions.front()) + " … t_c/" +
                  format("%g", plan.impactFractions.back()) + " (points labelled Δt/t_c)",
              title);
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::string& c = cases[k];
    const bool impact = c.find("impact") != std::string::npos;
    render::PlotSpec p;
    p.style = style;
    p.grid = true;
    p.title = c == "hooke_impact"   ? "Hooke impact (γn = 60 1/s)"
              : c == "hertz_impact" ? "Hertz impact (undamped)"
              : c == "stage2_mu03"  ? "Stage 2, μ = 0.3: σ₃₃(t)"
                                    : "Stage 2, μ = 0: σ₃₃(t)";
    p.xLabel = impact ? "wall time per impact [s]" : "wall time per run [s]";
    p.yLabel = "relative error";
    p.xLog = p.yLog = true;
    const char* quantity[2] = {impact ? "restitution" : "Eq. (1)", impact ? "duration" : "Eq. (2)"};
    struct Label {
      double x, y;  ///< [data units]
      std::string text;
      render::Rgba color;
      bool above;  ///< above the point (else below)
    };
    std::vector<Label> labels;
    for (int i = 0; i < 3; ++i) {  // Gear5, velocity Verlet, velocity Verlet at "auto"
      if (i == 2 && impact) continue;
      for (int q = 0; q < 2; ++q) {
        render::Series s;
        s.color = render::categorical(i);
        s.width = q == 0 ? 2.0 : 1.5;
        s.dash = q == 0 ? render::Series::Solid : render::Series::Dashed;
        s.marker = q == 0 ? render::Marker::Circle : render::Marker::Square;
        s.markerSize = 7.0;
        const bool automatic = i == 2;
        const Integrator integrator = automatic ? Integrator::VelocityVerlet : kIntegrators[i];
        s.label = std::string(integratorLabel(integrator)) + (automatic ? " auto" : "") + ", " +
                  quantity[q];
        for (const Row& r : rows) {
          if (r.caseName != c || r.integrator != integrator || r.role != Role::Run ||
              r.automatic != automatic)
            continue;
          const double e = q == 0 ? (impact ? r.restitutionError : r.eq1Error)
                                  : (impact ? r.durationError : r.eq2Error);
          if (!(e > 0)) continue;  // zero error (identical run) has no logarithm
          s.x.push_back(r.wallSeconds);
          s.y.push_back(e);
          if (q == 0) {
            // A stage-2 error of several per cent is no truncation error: the bed blew up.
            const bool blewUp = !impact && r.worstError() > 0.05;
            labels.push_back({s.x.back(), s.y.back(),
                              (automatic ? "auto ≤1/" : "1/") + format("%g", r.fraction) +
                                  (blewUp ? " unstable" : ""),
                              s.color, i != 1});
          }
        }
        p.series.push_back(s);
      }
    }
    // Room on the right for the labels of the slowest points (in decades: the axis is log).
    double xMin = std::numeric_limits<double>::infinity(), xMax = -xMin;
    for (const render::Series& s : p.series) {
      for (double x : s.x) xMin = std::min(xMin, x), xMax = std::max(xMax, x);
    }
    if (xMax > xMin) {
      const double decades = std::log10(xMax / xMin);
      p.xRange = render::AxisRange{xMin * std::pow(10.0, -0.05 * decades),
                                   xMax * std::pow(10.0, 0.12 * decades)};
    }
    const double target = impact ? 1e-3 : 1e-2;
    render::ReferenceLine line;
    line.y = target;
    line.label = percent(target);
    p.references.push_back(line);
    p.legend = render::LegendPosition::Auto;
    const render::Rect panel{double(k % columns) * panelW, titleH + double(k / columns) * panelH,
                             double(panelW), double(panelH)};
    const render::Axes axes = render::drawPlot(canvas, panel, p);
    render::TextStyle small;
    small.size = style.px(style.fontSize * 0.8);
    small.vAlign = render::VAlign::Bottom;
    canvas.pushClip(axes.area());
    for (const Label& l : labels) {
      // Gear's labels above its points, Verlet's below: where the curves meet they stay apart.
      small.color = l.color;
      small.vAlign = l.above ? render::VAlign::Bottom : render::VAlign::Top;
      const render::Point at = axes.toPixel(l.x, l.y);
      canvas.text({at.x + style.px(4), at.y + style.px(l.above ? -3 : 3)}, l.text, small);
    }
    canvas.popClip();
  }
  return canvas.takeImage();
}

// 6. The program ----------------------------------------------------------------------------

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  double a = 0, b = 0, c = 0;
  if (!(in >> a >> b >> c)) return "unknown";
  return format("%.2f", a) + ", " + format("%.2f", b) + ", " + format("%.2f", c);
}

int runBench(const Options& options) {
  const auto start = Clock::now();
  const Plan plan = makePlan(options.quick);
  // Check every checkpoint first: a missing one should not cost the impacts' minute.
  std::vector<StageCase> stageCases;
  for (const PaperReference* paper : plan.stageCases) {
    stageCases.push_back(loadStageCase(*paper, options));
  }
  createOutputFolder(options.outDir);
  const std::string loadBefore = loadAverage();
  std::cout << "bench-accuracy" << (options.quick ? " --quick" : "")
            << ": single-threaded; load average " << loadBefore << '\n';

  std::vector<Row> rows = impactRows(plan);
  std::vector<StageRun> series;
  const std::vector<Row> stage = stageRows(stageCases, plan, series);
  rows.insert(rows.end(), stage.begin(), stage.end());

  std::vector<std::string> cases;
  for (const Row& r : rows) {
    if (std::find(cases.begin(), cases.end(), r.caseName) == cases.end()) {
      cases.push_back(r.caseName);
    }
  }
  const std::string load = "before " + loadBefore + "; after " + loadAverage();
  writeRowsCsv(options.outDir / "accuracy.csv", rows);
  writeSeriesCsv(options.outDir / "stage2_sigma33.csv", series);
  writeTextFile(options.outDir / "accuracy.md", markdown(rows, plan, cases, load));
  render::writePng(accuracyFigure(rows, cases, plan), options.outDir / "accuracy.png", 150.0, 9);
  std::cout << "\n"
            << conclusions(rows, cases) << "load average " << load << "\nwrote "
            << (options.outDir / "accuracy.md").string() << ", accuracy.csv, stage2_sigma33.csv, "
            << "accuracy.png (" << format("%.0f", secondsSince(start)) << " s wall-clock)\n";
  return 0;
}

}  // namespace
}  // namespace granular::bench

int main(int argc, char** argv) {
  granular::bench::Options options;
  CLI::App app{
      "granular_bench_accuracy: speed against error of Gear5 and velocity Verlet, on "
      "two-sphere impacts and the paper's stage 2 (bench/RESULTS.md)"};
  // `--out ""` would silently mean the default folder.
  const CLI::Validator nonEmptyPath(
      [](std::string& text) -> std::string {
        return text.empty() ? std::string("an empty path; leave the option out for the default")
                            : std::string();
      },
      "PATH");
  app.add_option("--run", options.runDir,
                 "`granular paper --out` folder with the settled checkpoints (default: "
                 "runs/paper)")
      ->check(nonEmptyPath);
  const CLI::Option* out = app.add_option("-o,--out", options.outDir,
                                          "Output folder (default: runs/bench-accuracy, with "
                                          "--quick runs/bench-accuracy-quick)")
                               ->check(nonEmptyPath);
  app.add_option("--scenes", options.scenesDir,
                 "Folder of paper-mu0.toml and paper-mu03.toml (default: the installed "
                 "assets/scenes)");
  app.add_flag("--quick", options.quick,
               "Smoke run (about 15 s): fewer steps, μ = 0.3 only, stage 2 cut to 0.3 s");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; a usage error gets 2, the caller's mistake.
    return app.exit(e) == 0 ? 0 : 2;
  }
  // A smoke run must not overwrite the results of a full one.
  if (options.quick && out->count() == 0) options.outDir = "runs/bench-accuracy-quick";
  return granular::bench::withErrorMapping([&] { return granular::bench::runBench(options); });
}
