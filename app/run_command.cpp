/// `granular run` (see run_command.hpp).
/// Sections: 1. output names; 2. running the stages; 3. summary.
#include "run_command.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "contact_csv.hpp"
#include "csv_output.hpp"
#include "granular/bricks.hpp"
#include "granular/checkpoint.hpp"
#include "granular/engine_studies.hpp"
#include "granular/error.hpp"
#include "granular/mpi_session.hpp"
#include "granular/run_checks.hpp"
#include "granular/scene.hpp"
#include "granular/scene_fingerprint.hpp"
#include "granular/stage.hpp"
#include "progress.hpp"
#include "run_figures.hpp"
#include "run_folder.hpp"
#include "run_header.hpp"
#include "run_progress.hpp"
#include "stop_signals.hpp"
#include "vtk_snapshot.hpp"

namespace granular::app {

namespace {

// 1. Output names ---------------------------------------------------------------------------------

/// <kind>_<stage>_<step>.csv: named by the step the state was written at (a snapshot is taken
/// at the first step at or after its time); the stage is in the name because snapshot times are
/// on each stage's own clock.
std::filesystem::path snapshotPath(const std::filesystem::path& outDir, const char* kind,
                                   const std::string& stage, std::uint64_t step) {
  return outDir /
         (std::string(kind) + "_" + fileSafeName(stage) + "_" + std::to_string(step) + ".csv");
}

/// paraview/<stage>_<step>_<kind>.vtp, relative to the run folder (the .pvd files refer to it so).
std::filesystem::path paraviewPath(const std::string& stage, std::uint64_t step, const char* kind) {
  return std::filesystem::path("paraview") /
         (fileSafeName(stage) + "_" + std::to_string(step) + "_" + kind + ".vtp");
}

constexpr const char* kParaviewKinds[] = {"particles", "contacts", "walls"};

/// The time since the run began of the state of `sim`, in stage `k`: the finished stages'
/// durations and the time into this one [s]. It runs on across stages whatever their clocks.
double runTime(const RunProgress& progress, std::size_t k, const Simulation& sim) {
  double before = 0.0;
  for (std::size_t j = 0; j < k && j < progress.finished.size(); ++j) {
    before += progress.finished[j].result.duration;
  }
  return before + (sim.time() - progress.stageOrigin);
}

/// Writes the ParaView files of a snapshot of stage `k` (the state of `sim`), adds it to the
/// run's frames, then rewrites particles.pvd, contacts.pvd and walls.pvd from the frames: this
/// run's snapshots and no others, whatever else the folder holds.
void writeParaviewSnapshot(const std::filesystem::path& outDir, const Scene& scene,
                           RunProgress& progress, std::size_t k, const Simulation& sim) {
  createOutputFolder(outDir / "paraview");
  const std::string& stage = scene.stages[k].name;
  writeParticlesVtp(outDir / paraviewPath(stage, sim.stepCount(), "particles"), sim);
  writeContactsVtp(outDir / paraviewPath(stage, sim.stepCount(), "contacts"), sim);
  writeWallsVtp(outDir / paraviewPath(stage, sim.stepCount(), "walls"), sim, scene.box.min,
                scene.box.max);
  progress.frames.push_back({k, sim.stepCount(), runTime(progress, k, sim)});
  for (const char* kind : kParaviewKinds) {
    std::vector<PvdEntry> entries;
    for (const ParaviewFrame& frame : progress.frames) {
      entries.push_back(
          {frame.runTime, paraviewPath(scene.stages[frame.stage].name, frame.step, kind)});
    }
    writePvd(outDir / (std::string(kind) + ".pvd"), entries);
  }
}

const char* reasonText(StageEndReason reason) {
  return reason == StageEndReason::KineticEnergy ? "kinetic energy below threshold" : "max time";
}

// 2. Running the stages ---------------------------------------------------------------------------

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The state hash as 16 hex digits: equal hashes mean bit-identical positions and velocities.
std::string hexHash(std::uint64_t h) {
  char buffer[24];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(h));
  return buffer;
}

/// GRANULAR_INJECT_NAN=STEP:PARTICLE (run_command.hpp), or nothing.
std::optional<std::pair<std::uint64_t, std::size_t>> injectedFault() {
  const char* text = std::getenv("GRANULAR_INJECT_NAN");
  if (!text || !*text) return std::nullopt;
  unsigned long long step = 0, particle = 0;
  char tail = 0;
  if (std::sscanf(text, "%llu:%llu%c", &step, &particle, &tail) != 2) {
    throw ConfigError(std::string("GRANULAR_INJECT_NAN = '") + text + "': expected STEP:PARTICLE");
  }
  return std::pair{std::uint64_t(step), std::size_t(particle)};
}

/// Where a run starts: a fresh simulation, or the checkpoint of an interrupted one.
struct Start {
  Simulation sim;
  RunProgress progress;
  bool resumed = false;
};

/// The checkpoint of an interrupted run, refused (CheckpointError) when it is damaged or was
/// written for another scene, or for this one before an edit that changes the run.
CheckpointContents readResumable(const std::filesystem::path& checkpoint,
                                 const SceneFingerprint& fingerprint) {
  try {
    return readCheckpointWithData(checkpoint, fingerprint);
  } catch (const CheckpointError& e) {
    throw CheckpointError(std::string(e.what()) + "; remove " + checkpoint.string() +
                          " (or run without --resume) to start again");
  }
}

Start startOrResume(const RunOptions& options, const Scene& scene,
                    const SceneFingerprint& fingerprint, const std::filesystem::path& checkpoint,
                    bool root) {
  if (options.resume && std::filesystem::exists(checkpoint)) {
    CheckpointContents c = readResumable(checkpoint, fingerprint);
    RunProgress progress = decodeRunProgress(c.appData, checkpoint.string());
    if (progress.stage > scene.stages.size()) {
      throw CheckpointError(checkpoint.string() + ": names stage " +
                            std::to_string(progress.stage + 1) + " of a scene with " +
                            std::to_string(scene.stages.size()));
    }
    // A checkpoint holds the state, not how the sums are taken: the scene says that (a run
    // under mpirun takes them exactly whatever it says, Simulation::splitAmong).
    c.simulation.setExactSums(scene.simulation.exactSums);
    return {std::move(c.simulation), std::move(progress), true};
  }
  // A fresh start: the folder must not hold an earlier run's files, which the new run would
  // mix with its own (--force removes them first).
  if (root && options.force) removeEarlierRun(checkpoint.parent_path());
  if (root) refuseEarlierRun(checkpoint.parent_path(), options.resume);
  if (options.resume && root) {
    std::cout << "no checkpoint " << checkpoint.string() << ": starting from the beginning\n";
  }
  return {buildSimulation(scene), RunProgress{}, false};
}

/// After a stop signal, with the checkpoint written: the way back, then Interrupted.
[[noreturn]] void stopAndSayHowToResume(const RunOptions& options,
                                        const std::filesystem::path& outDir,
                                        const Simulation& sim) {
  throw Interrupted(
      stopSignal(),
      "stopped by " + signalName(stopSignal()) + " at t = " + format("%.9g", sim.time()) +
          " s, step " + std::to_string(sim.stepCount()) + "; checkpoint " +
          (outDir / "checkpoint.bin").string() + " written. Continue with: granular run " +
          options.scene.string() + " --out " + outDir.string() + " --resume");
}

/// What a run starts from: its scene, output folder and state.
struct Prepared {
  Scene scene;
  SceneFingerprint fingerprint;
  std::optional<std::pair<std::uint64_t, std::size_t>> fault;
  std::filesystem::path outDir, checkpoint;
  Start start;
};

Prepared prepare(const RunOptions& options, bool root) {
  if (!(options.checkpointEvery >= 0.0)) {
    throw ConfigError("--checkpoint-every must be >= 0 seconds (0: no checkpoints)");
  }
  Scene scene = loadScene(options.scene);
  // The scene's values and the bytes of its particle files: a checkpoint of this scene before
  // an edit that changes the run is refused, an edit of a comment is not.
  SceneFingerprint fingerprint = fingerprintScene(scene);
  const auto fault = injectedFault();
  const std::filesystem::path outDir = options.outDir.empty()
                                           ? std::filesystem::path("runs") / options.scene.stem()
                                           : options.outDir;
  if (root) createOutputFolder(outDir);
  const std::filesystem::path checkpoint = outDir / "checkpoint.bin";
  Start start = startOrResume(options, scene, fingerprint, checkpoint, root);
  return {std::move(scene), std::move(fingerprint), fault, outDir, checkpoint, std::move(start)};
}

/// Under mpirun every rank prepares alike, and none goes on if one failed (a file it could not
/// read): the lowest failing rank says why, and every rank ends with its status.
void agreeOnSetup(const Communicator* ranks, const std::exception_ptr& failed) {
  if (!ranks) {
    if (failed) std::rethrow_exception(failed);
    return;
  }
  const std::string mine =
      failed ? std::to_string(ranks->rank()) + " " + std::to_string(reportOf(failed).status) : "";
  const std::string first = ranks->firstOverRanks(mine);
  if (first.empty()) return;
  if (first == mine) std::rethrow_exception(failed);
  throw SilentExit{std::stoi(first.substr(first.find(' ') + 1))};
}

/// The box cut into one brick per rank, each holding about as many particles (bricks.hpp).
std::shared_ptr<const DomainMap> bricksFor(const Scene& scene, const Simulation& sim, int ranks) {
  auto bricks = std::make_shared<Bricks>(ranks, scene.box.min, scene.box.max);
  const std::vector<double>& radius = sim.particles().radius;
  // A run that starts empty (its stages insert the particles) balances later, at its rebuilds.
  const double rMax =
      radius.empty() ? sim.contactScale().radius : *std::max_element(radius.begin(), radius.end());
  bricks->balance(sim.particles().position, 2.0 * rMax);
  return bricks;
}

int runScene(const RunOptions& options) {
  catchStopSignals();
  const auto started = std::chrono::steady_clock::now();
  const Communicator* ranks = options.ranks.get();
  const bool root = !ranks || ranks->rank() == 0;
  std::optional<Prepared> prepared;
  {
    std::exception_ptr failed;
    try {
      prepared.emplace(prepare(options, root));
    } catch (...) {
      failed = std::current_exception();
    }
    agreeOnSetup(ranks, failed);
  }
  const Scene& scene = prepared->scene;
  const SceneFingerprint& fingerprint = prepared->fingerprint;
  const auto& fault = prepared->fault;
  const std::filesystem::path& outDir = prepared->outDir;
  const std::filesystem::path& checkpoint = prepared->checkpoint;
  Start& start = prepared->start;
  Simulation& sim = start.sim;
  RunProgress& progress = start.progress;
  // Only rank 0 prints to stdout and writes files.
  std::ostringstream elsewhere;
  std::ostream& out = root ? std::cout : elsewhere;
  if (start.resumed) {
    out << "resuming " << checkpoint.string() << " at t = " << format("%.9g", sim.time())
        << " s, step " << sim.stepCount() << ", stage "
        << std::min(progress.stage + 1, scene.stages.size()) << " of " << scene.stages.size()
        << "\n";
  }
  const bool complete = progress.stage == scene.stages.size();
  if (complete) {
    // Killed after its last checkpoint, perhaps before its final files: they are written again.
    out << "the run in " << outDir.string()
        << " is already complete: writing its final state and summary again\n";
  } else {
    printHeader(out, scene, sim, outDir);
    if (!start.resumed) printSavedStateStart(out, scene, sim);
  }
  // Under mpirun the run is split by space: each rank steps the particles of its brick, and
  // the whole state is gathered for the files (Simulation::splitAmong).
  if (ranks) sim.splitAmong(bricksFor(scene, sim, ranks->size()), options.ranks);

  const bool exchanges = exchangesParticles(scene);
  const std::filesystem::path seriesPath = outDir / "timeseries.csv";
  std::optional<TimeSeriesWriter> series;
  if (!root) {
  } else if (start.resumed) {
    series.emplace(seriesPath, reactionWallNames(scene), progress.seriesBytes, progress.seriesHash,
                   exchanges);
  } else {
    series.emplace(seriesPath, reactionWallNames(scene), scene.simulation.material, exchanges);
  }
  // A file written from the whole state: gathered from every rank in a split run.
  auto withWhole = [&](const Simulation& s, const std::function<void(const Simulation&)>& write) {
    if (!s.ranks()) {
      write(s);
      return;
    }
    const Simulation whole = s.wholeState();
    if (root) write(whole);
  };
  // A stop signal reaches the ranks at different steps: they stop together at the first of them.
  auto stopped = [&] {
    const bool mine = stopSignal() != 0;
    return ranks ? ranks->anyOverRanks(mine) : mine;
  };
  ProgressReporter reporter(!options.quiet, ranks);
  // The run checks itself at each sample (energy balance, particles outside the box): a
  // warning on stderr and in summary.txt, or exit 3 under on_failed_check = "stop".
  RunChecks checks(scene.output.checks, scene.box,
                   progress.energyReference.value_or(sim.energy().total()));
  progress.energyReference = checks.referenceTotal();
  std::vector<std::string> warnings;
  // What the loader found legal but likely wrong (an overlap beyond a radius no step mends).
  for (const std::string& warning : scene.warnings) {
    if (root) std::cerr << "warning: " << warning << "\n";
    warnings.push_back(warning);
  }
  bool unstableReported = false, approachReported = false, growthReported = false;

  // Checkpoints: every `checkpointEvery` seconds of wall clock inside a stage, and at each
  // stage's end. The last one written is the last good state if the run breaks.
  auto lastWritten = std::chrono::steady_clock::now();
  std::optional<std::pair<double, std::uint64_t>> lastGood;  // its time and step
  auto save = [&](const Simulation& s) {
    // The checkpoint counts the series' bytes: they must be on the disk before it is.
    if (series) {
      series->sync();
      progress.seriesBytes = series->bytes();
      progress.seriesHash = series->hash();
    }
    withWhole(s, [&](const Simulation& whole) {
      writeCheckpoint(whole, checkpoint, fingerprint, encodeRunProgress(progress));
    });
    lastWritten = std::chrono::steady_clock::now();
    lastGood = std::pair{s.time(), s.stepCount()};
  };

  try {
    for (std::size_t k = progress.stage; k < scene.stages.size(); ++k) {
      const StageSpec& stage = scene.stages[k];
      StageObserver observer;
      observer.onSample = [&](const Simulation& s) {
        if (series) {
          series->write(stage.name, s);
        } else {
          (void)s.energy();  // the row's energies: every rank takes part in their sums
          if (exchanges) (void)s.particleTally();
        }
        if (s.counters().unstableChecks > 0 && !unstableReported) {
          // on_unstable = "warn": said once; the summary gives the count.
          unstableReported = true;
          const StepCheck& c = s.stepCheck();
          const std::string warning =
              "the time step " + csvNumber(s.config().timeStep) +
              " s is above the step the contact network allows (" + format("%.4g", c.networkStep) +
              " s at t = " + format("%.6g", c.time) + " s, particle " + std::to_string(c.particle) +
              "); the run goes on (on_unstable = \"warn\") and may gain energy";
          reporter.finish();
          if (root) std::cerr << "warning: " << warning << "\n";
          warnings.push_back(warning);
        }
        if (s.counters().keptGrowths > 0 && !growthReported) {
          // An automatic step grew a mode the run could not undo (it was found after samples
          // of it were taken): said once; the summary gives the count.
          growthReported = true;
          const std::string warning =
              "a growing mode of the automatic step was found at t = " +
              format("%.6g", s.stepCheck().time) +
              " s after the state had been sampled, so it was not undone: the step shrank from "
              "then on, and the energy it created stays in the ledger (energy_total_J)";
          reporter.finish();
          if (root) std::cerr << "warning: " << warning << "\n";
          warnings.push_back(warning);
        }
        const SimulationConfig& config = s.config();
        if (!approachReported && !config.step.automatic &&
            config.material.normalLaw == NormalLaw::Hertz &&
            s.counters().fastestApproach > config.impactSpeed) {
          // A fixed step was judged at the declared speed; at the measured one a Hertz contact
          // is shorter, and the step may be above its limit there. An automatic step's floor
          // follows the measured speeds by itself.
          const double speed = s.counters().fastestApproach;
          const ContactScale at = stiffestContact(config.material, s.contactScale().radius, speed);
          const double limit = maxStableStep(at, config.integrator);
          if (config.timeStep > limit) {
            approachReported = true;
            const std::string warning =
                "contacts approach at up to " + format("%.4g", speed) +
                " m/s, above simulation.impact_speed = " + format("%.4g", config.impactSpeed) +
                " m/s that the time step was judged at: a Hertz contact at that speed lasts " +
                format("%.4g", at.duration) + " s, and the step of " + csvNumber(config.timeStep) +
                " s is above its limit there, " + format("%.4g", limit) +
                " s (it resolves the contact in " + format("%.3g", at.duration / config.timeStep) +
                " steps); declare impact_speed = " + format("%.4g", speed) +
                " or more, or use time_step = \"auto\" (its floor follows the measured speeds)";
            reporter.finish();
            if (root) std::cerr << "warning: " << warning << "\n";
            warnings.push_back(warning);
          }
        }
        for (const std::string& warning : checks.atSample(s, stage.name)) {
          reporter.finish();
          if (root) std::cerr << "warning: " << warning << "\n";
          warnings.push_back(warning);
        }
      };
      observer.onSnapshot = [&](const Simulation& s, double) {
        withWhole(s, [&](const Simulation& whole) {
          writeParticleSnapshot(snapshotPath(outDir, "snapshot", stage.name, s.stepCount()), whole);
          writeContactCsv(snapshotPath(outDir, "contacts", stage.name, s.stepCount()), whole);
          writeParaviewSnapshot(outDir, scene, progress, k, whole);
        });
      };
      observer.onProgress = [&](const Simulation& s, const StageSpec& st) {
        reporter.update(s, st);
      };
      observer.progressSteps = 200;  // a clock read every 200 steps costs nothing measurable
      // Checkpoints are offered every 100 steps; an injected fault needs every step.
      observer.checkpointSteps = fault ? 1 : 100;
      observer.onCheckpoint = [&](const Simulation& s, const StageProgress& p) {
        // An automatic step's stage offers a checkpoint only every 100 steps or more.
        const bool offered = s.config().step.automatic || p.steps % 100 == 0;
        // Rank 0's clock says when a checkpoint is due.
        const bool due = offered && options.checkpointEvery > 0 &&
                         secondsSince(lastWritten) >= options.checkpointEvery;
        if (offered && (ranks ? ranks->anyOverRanks(root && due) : due)) {
          progress.inStage = p;
          save(s);
        }
        if (offered && stopped()) {
          progress.inStage = p;
          save(s);
          stopAndSayHowToResume(options, outDir, s);
        }
        if (fault && s.stepCount() == fault->first) {
          // The particle by its id in the scene: in a split run, on the rank that owns it.
          for (std::size_t i = 0; i < s.particles().size(); ++i) {
            if (s.globalId(i) != fault->second || !s.owns(i)) continue;
            auto& v = const_cast<Particles&>(s.particles()).velocity[i];
            v.x() = std::numeric_limits<double>::quiet_NaN();
          }
        }
      };
      // A stage that had begun continues where its checkpoint left it; one that had not
      // (steps = 0: checkpoints inside a stage follow at least one step) starts with its set-up.
      StageProgress resumeAt = progress.inStage;
      // The stage's origin is the run's record of it (an automatic step aims at its times).
      if (resumeAt.time) resumeAt.origin = progress.stageOrigin;
      const bool continuing = resumeAt.steps > 0;
      // The stage's t = 0 on the simulation's clock (runStage resets the clock where asked).
      if (!continuing) progress.stageOrigin = stage.resetClock ? 0.0 : sim.time();
      const auto stageStart = std::chrono::steady_clock::now();
      const StageResult result =
          runStage(sim, stage, scene.output, observer, continuing ? &resumeAt : nullptr);
      reporter.finish();
      progress.finished.push_back({result, secondsSince(stageStart)});
      progress.stage = k + 1;
      progress.inStage = StageProgress{};
      const bool stop = stopped();
      if (options.checkpointEvery > 0 || stop) save(sim);
      if (stop && k + 1 < scene.stages.size()) stopAndSayHowToResume(options, outDir, sim);
      const double kinetic = sim.kineticEnergy();
      out << "stage " << stage.name << ": " << reasonText(result.reason) << " after "
          << format("%.6g", result.duration) << " s (" << result.steps << " steps, "
          << format("%.1f", progress.finished.back().wallSeconds) << " s wall-clock), KE "
          << format("%.3e", kinetic) << " J\n"
          << std::flush;
    }
  } catch (const NumericalError& e) {
    reporter.finish();
    if (ranks && ranks->size() > 1 && dynamic_cast<const BrokenStateError*>(&e)) {
      // A broken particle of this rank's own, which the others cannot know of: its share of
      // the state, the message, and every rank ends.
      const std::filesystem::path broken =
          outDir / ("failed_state_rank" + std::to_string(ranks->rank()) + ".csv");
      std::vector<std::uint64_t> ids(sim.particles().size());
      for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = sim.globalId(i);
      createOutputFolder(outDir);
      writeParticleState(broken, sim.particles(), &ids);
      std::cerr << "error: " << e.what() << "; this rank's particles (owned and ghosts) are in "
                << broken.string()
                << (lastGood ? "; the last good state is " + checkpoint.string() +
                                   ": remove the cause and continue it with --resume"
                             : std::string("; no checkpoint was written in this run"))
                << "\n"
                << std::flush;
      MpiSession::abortAll(kExitNumericalFailure);
    }
    const std::filesystem::path broken = outDir / "failed_state.csv";
    withWhole(sim, [&](const Simulation& whole) { writeParticleState(broken, whole.particles()); });
    if (!root) return kExitNumericalFailure;
    std::cerr << "error: " << e.what() << "\n";
    if (lastGood) {
      std::cerr << "the last good state is " << checkpoint.string()
                << " (t = " << format("%.9g", lastGood->first) << " s, step " << lastGood->second
                << "): remove the cause and continue it with --resume; the broken state is in "
                << broken.string() << "\n";
    } else {
      std::cerr
          << "no checkpoint was written in this run (--checkpoint-every); the broken state is in "
          << broken.string() << "\n";
    }
    return kExitNumericalFailure;
  }
  std::optional<Simulation> gathered;
  if (ranks) gathered.emplace(sim.wholeState());
  const double finalKinetic = sim.kineticEnergy();
  if (!root) return 0;
  const Simulation& whole = gathered ? *gathered : sim;
  writeParticleState(outDir / "final_state.csv", whole.particles());

  // 3. Summary
  // -------------------------------------------------------------------------------------
  std::ostringstream summary;
  summary << "scene: " << scene.sourceFile.string() << "\n"
          << "particles: " << whole.particles().size() << "\n"
          << "total mass: " << format("%.6g", totalMass(whole.particles())) << " kg\n"
          << "stages:\n";
  for (std::size_t k = 0; k < progress.finished.size(); ++k) {
    const FinishedStage& r = progress.finished[k];
    summary << "  " << scene.stages[k].name << ": ended by " << reasonText(r.result.reason) << "; "
            << format("%.6g", r.result.duration) << " s simulated, " << r.result.steps << " steps, "
            << format("%.2f", r.wallSeconds) << " s wall-clock\n";
  }
  for (const std::string& warning : warnings) summary << "warning: " << warning << "\n";
  const StepCounters& counted = sim.counters();
  summary << "time step: " << csvNumber(counted.smallestStep) << " to "
          << csvNumber(counted.largestStep) << " s"
          << (sim.config().step.automatic ? " (auto)" : "") << "; " << counted.stepChecks
          << " checks against the contact network";
  // What the reviews inside the steps cost (a setter's check between calls is not counted):
  // the step control's share of the run, which a user weighs against a fixed step's.
  const studies::StepControlCost cost = studies::stepControlCost(sim);
  if (cost.calibrations > 0) {
    summary << " (" << cost.calibrations << " making the spectrum's estimate)";
  }
  if (cost.scans > 0) summary << " and " << cost.scans << " scans of the contacts' motion";
  summary << ", " << format("%.3g", cost.seconds) << " s of the wall-clock";
  if (counted.unstableChecks > 0) {
    summary << ", " << counted.unstableChecks << " found the step above it (up to "
            << format("%.3g", counted.worstStepRatio) << " x)";
  }
  if (counted.rollbacks > 0) {
    summary << ", " << counted.rollbacks
            << " found a growing mode and took the steps since the last again at a shorter step";
  }
  if (counted.keptGrowths > 0) {
    summary << ", " << counted.keptGrowths
            << " found a growing mode too late to undo (its energy stays in the ledger)";
  }
  summary << "\n";
  summary << "final kinetic energy: " << format("%.6e", finalKinetic) << " J\n"
          << "state hash: " << hexHash(whole.stateHash()) << "\n"
          << "wall-clock: " << format("%.2f", secondsSince(started)) << " s"
          << (start.resumed ? " (since the resume)" : "") << "\n";
  writeTextFile(outDir / "summary.txt", summary.str());
  std::cout << "wrote " << (outDir / "timeseries.csv").string() << ", final_state.csv, summary.txt"
            << (std::filesystem::exists(outDir / "particles.pvd")
                    ? "; snapshots for ParaView: particles.pvd, contacts.pvd, walls.pvd"
                    : "")
            << "\n";
  if (options.figures) {
    try {
      printRunFigures(std::cout, drawRunFigures(outDir));
    } catch (const Interrupted&) {
      throw;
    } catch (const std::exception& e) {
      throw IoError(std::string(e.what()) + " (the run's own files in " + outDir.string() +
                    " are complete)");
    }
  }
  return 0;
}

}  // namespace

int runCommand(const RunOptions& options) {
  if (options.ranks) {
    return withRanksErrorMapping(*options.ranks, [&] { return runScene(options); });
  }
  return withErrorMapping([&] { return runScene(options); });
}

}  // namespace granular::app
