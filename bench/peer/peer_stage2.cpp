/// granular_peer_stage2: the paper's stage 2 (compaction by the moving top wall) from the settled
/// checkpoint, timed, for the side-by-side benchmark against LAMMPS and LIGGGHTS (bench/peer/).
///
///   granular_peer_stage2 [--checkpoint F] [--scene F] [--dt S] [--skin M] [--threads N]
///                        [--duration S] [--exact-sums] [--unchecked]
///                        [--fresh [--integrator gear5|verlet]] [--series FILE]
///                        [--auto [--contact-resolution N] [--step-safety S]
///                                [--estimate-scale F]]
///   granular_peer_stage2 [--checkpoint F] [--scene F] [--export-lammps DIR]
///                        [--export-liggghts DIR] [--radius-types K] [--mean-wall-stiffness]
///
/// Prints `key = value` lines (bench/peer/compare.py reads them): wall time, particle-steps/s,
/// σ of Eq. (1) and Eq. (2) at the end. --series writes σ of Eq. (2) from the instantaneous
/// wall reactions after every step, the one measure the peers produce the same way.
/// With an --export option it writes the peer inputs for the settled state and runs nothing.
/// Exit status: 0 done, 1 I/O or checkpoint error, 2 bad arguments or configuration.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "granular/bricks.hpp"
#include "granular/checkpoint.hpp"
#include "granular/engine_studies.hpp"
#include "granular/error.hpp"
#include "granular/mpi_session.hpp"
#include "granular/scene.hpp"
#include "granular/scene_fingerprint.hpp"
#include "granular/stage.hpp"
#include "granular/stress.hpp"
#include "peer_export.hpp"

namespace granular::peer {
namespace {

struct Options {
  std::filesystem::path checkpoint = "runs/paper/mu03/settled.ckpt";
  std::filesystem::path scene = "assets/scenes/paper-mu03.toml";
  std::optional<double> dt;
  std::optional<double> skin;
  int threads = 1;
  bool exactSums = false;
  std::optional<double> duration;
  bool fresh = false;
  std::string integrator;  // empty: the checkpoint's
  std::filesystem::path series;
  std::filesystem::path exportLammps;
  std::filesystem::path exportLiggghts;
  int radiusTypes = 10;
  bool meanWallStiffness = false;
  bool rebuildEveryStep = false;
  bool unchecked = false;         // a fixed step run without its check against the network
  bool automatic = false;         // time_step = "auto" (with --fresh)
  double contactResolution = 10;  // its accuracy floor t_c / N
  double stepSafety = StepControl{}.safety;  // with --auto
  double estimateScale = 1.0;                // studies::scaleSpectrumEstimate (with --auto)
};

constexpr const char* kMakeCheckpoint =
    "./build/release/app/granular paper --out runs/paper   (settles both paper cases; the "
    "mu = 0.3 one is written to runs/paper/mu03/settled.ckpt)";

/// The settled state, refused with the command that makes it when missing or stale.
Simulation restoreSettled(const Options& o) {
  if (!std::filesystem::exists(o.checkpoint)) {
    throw CheckpointError("settled checkpoint " + o.checkpoint.string() +
                          " not found. Make it with:\n  " + kMakeCheckpoint);
  }
  try {
    return readCheckpoint(o.checkpoint, fingerprintScene(loadScene(o.scene)));
  } catch (const CheckpointError& e) {
    // `granular paper` settles again over a stale checkpoint by itself.
    throw CheckpointError(std::string(e.what()) + "\nRe-make it with:\n  " + kMakeCheckpoint);
  }
}

/// The same positions, velocities, spins and walls, without contact history or Gear's higher
/// derivatives: what a peer gets from a data file, so the codes start from the same state.
/// A fresh start may also change the integrator (the peers use velocity Verlet).
Simulation withoutHistory(const Simulation& settled, const std::string& integrator) {
  std::vector<Wall> walls = settled.walls();
  for (Wall& w : walls) w.reaction = w.impulse = Vec3::Zero();
  SimulationConfig config = settled.config();
  if (integrator == "gear5") config.integrator = Integrator::Gear5;
  if (integrator == "verlet") config.integrator = Integrator::VelocityVerlet;
  return Simulation(settled.particles(), walls, config);
}

double topSurface(const Particles& p) {
  double top = p.position[0].z() + p.radius[0];
  for (std::size_t i = 1; i < p.size(); ++i) top = std::max(top, p.position[i].z() + p.radius[i]);
  return top;
}

Stage2Setup stage2Setup(const Simulation& sim, const StageSpec& stage) {
  Stage2Setup s;
  s.topWallHeight = topSurface(sim.particles());
  for (const WallMotion& m : stage.wallMotions) {
    if (m.wall == "top") s.topWallVelocity = m.velocity;
  }
  return s;
}

/// σ11, σ22, σ33 of Eq. (2) from the instantaneous reactions (measureBox's definition). Empty
/// contact sums skip Eq. (1), which would cost a contact pass every step.
Vec3 eq2Now(const Simulation& sim) {
  const BoxContactSums skipped;
  return measureBox(sim, {}, &skipped).eq2;
}

void printTensor(const char* key, const Mat3& m) {
  std::printf("%s =", key);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) std::printf(" %.6f", m(r, c));
  }
  std::printf("\n");
}

/// `ranks`: the processes of an mpirun job, among which the run is split by space (null: one
/// process). Rank 0 prints.
int run(const Options& o, const std::shared_ptr<const Communicator>& ranks) {
  const Scene scene = loadScene(o.scene);
  if (scene.stages.size() != 2 || !scene.stages[1].placeTopWallOnSurface) {
    throw ConfigError(o.scene.string() +
                      ": expected the paper's two stages, the second placing "
                      "the top wall on the surface");
  }
  StageSpec stage = scene.stages[1];
  if (o.duration) stage.end.maxTime = *o.duration;
  Simulation settled = restoreSettled(o);

  if (!o.exportLammps.empty() || !o.exportLiggghts.empty()) {
    const Stage2Setup setup = stage2Setup(settled, stage);
    if (!o.exportLammps.empty())
      writeLammps(settled, setup, o.radiusTypes, !o.meanWallStiffness, o.exportLammps);
    if (!o.exportLiggghts.empty()) writeLiggghts(settled, setup, o.radiusTypes, o.exportLiggghts);
    const RadiusClasses c = classifyRadii(settled.particles(), o.radiusTypes);
    std::printf("exported = %zu particles, %d radius classes (largest |R - R_class|/R = %.4g)\n",
                settled.particles().size(), o.radiusTypes, c.maxRelativeError);
    return 0;
  }

  if (!o.integrator.empty() && !o.fresh) {
    throw ConfigError("--integrator needs --fresh: the checkpoint's derivatives belong to its own");
  }
  Simulation sim = o.fresh ? withoutHistory(settled, o.integrator) : std::move(settled);
  // Unchecked, a step above the network's is taken (where the run really breaks is measured).
  if (o.unchecked) {
    if (o.automatic) throw ConfigError("--unchecked is for a fixed step, not --auto");
    studies::disableStepLimit(sim, true);
  }
  if (o.dt) sim.setTimeStep(*o.dt);
  if (o.skin) sim.setSkin(*o.skin);
  if (o.automatic) {
    if (!o.fresh) throw ConfigError("--auto needs --fresh");
    StepControl control;
    control.automatic = true;
    control.contactResolution = o.contactResolution;
    control.safety = o.stepSafety;
    sim.setStepControl(control);
    studies::scaleSpectrumEstimate(sim, o.estimateScale);
  }
  sim.setThreads(o.threads);
  sim.setExactSums(o.exactSums);
  if (ranks) {
    if (!o.series.empty()) throw ConfigError("--series runs on one process (not under mpirun)");
    auto bricks = std::make_shared<Bricks>(ranks->size(), scene.box.min, scene.box.max);
    bricks->balance(sim.particles().position, 0.07);
    sim.splitAmong(bricks, ranks);
  }
  studies::setRebuildEveryStep(sim, o.rebuildEveryStep);

  std::ofstream series;
  StageObserver observer;
  if (!o.series.empty()) {
    series.open(o.series);
    if (!series) throw std::runtime_error("cannot write " + o.series.string());
    series.precision(10);
    series << "step,time_s,top_z_m,s11_eq2_Pa,s22_eq2_Pa,s33_eq2_Pa\n";
    // After every step: the stage clock (n·Δt at a fixed step, stage.cpp; the sum of the
    // steps at "auto"), the reactions are this step's.
    observer.progressSteps = 1;
    std::uint64_t n = 0;
    observer.onProgress = [&, n](const Simulation& s, const StageSpec&) mutable {
      ++n;
      const Vec3 eq2 = eq2Now(s);
      series << n << ',' << s.time() << ',' << s.walls()[s.findWall("top")].point.z() << ','
             << eq2.x() << ',' << eq2.y() << ',' << eq2.z() << '\n';
    };
  }

  // No samples or snapshots inside the stage: nothing here writes them, and the peers' runs
  // take none at fixed times (their series is per step, as --series is here). A scene's
  // output interval would have an automatic step land on every sample time exactly, steps
  // the peers do not take (bench/RESULTS.md, "The step from the estimate").
  OutputSpec output = scene.output;
  output.interval = stage.end.maxTime;
  output.snapshotTimes.clear();
  stage.snapshotTimes.reset();
  const EnergyBalance before = sim.energy();  // collective under mpirun
  const auto start = std::chrono::steady_clock::now();
  const StageResult result = runStage(sim, stage, output, observer);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const EnergyBalance after = sim.energy();
  const Simulation whole = sim.wholeState();  // a copy alone, the gathered run under mpirun
  if (ranks && ranks->rank() != 0) return 0;
  const BoxStress box = measureBox(whole);
  const double n = double(whole.particles().size());
  std::printf("code = granular\n");
  std::printf("integrator = %s\n",
              sim.config().integrator == Integrator::Gear5 ? "gear5" : "velocity-verlet");
  std::printf("history = %s\n", o.fresh ? "dropped (--fresh)" : "from the checkpoint");
  std::printf("particles = %.0f\n", n);
  std::printf("dt_s = %.9g\n", sim.config().timeStep);
  std::printf("step_control = %s\n", o.automatic ? "auto" : "fixed");
  std::printf("dt_range_s = %.9g %.9g\n", sim.counters().smallestStep, sim.counters().largestStep);
  std::printf("threads = %d\n", o.threads);
  std::printf("ranks = %d\n", ranks ? ranks->size() : 1);
  std::printf("exact_sums = %s\n", o.exactSums ? "on" : "off");
  std::printf("skin_m = %.6g\n", sim.skin());
  std::printf("steps = %llu\n", static_cast<unsigned long long>(result.steps));
  std::printf("simulated_s = %.9g\n", result.duration);
  std::printf("wall_s = %.6f\n", wall);
  std::printf("particle_steps_per_s = %.6g\n", n * double(result.steps) / wall);
  std::printf("list_rebuilds = %llu\n", static_cast<unsigned long long>(sim.counters().rebuilds));
  const studies::StepControlCost cost = studies::stepControlCost(sim);
  std::printf("step_reviews = %llu checks, %llu scans, %llu calibrations\n",
              static_cast<unsigned long long>(cost.checks),
              static_cast<unsigned long long>(cost.scans),
              static_cast<unsigned long long>(cost.calibrations));
  std::printf("step_control_s = %.6f\n", cost.seconds);
  std::printf("growing_modes = %llu undone, %llu kept\n",
              static_cast<unsigned long long>(sim.counters().rollbacks),
              static_cast<unsigned long long>(sim.counters().keptGrowths));
  // What the stage's steps created or lost, against the work gravity and the walls did.
  std::printf("ledger_residual_J = %.6g of %.6g J work\n", after.total() - before.total(),
              std::abs(after.gravityWork - before.gravityWork) +
                  std::abs(after.wallWork - before.wallWork));
  std::printf("top_z_m = %.9f\n", box.upper.z());
  std::printf("state_hash = %016llx\n", static_cast<unsigned long long>(whole.stateHash()));
  printTensor("sigma_eq1_Pa", box.eq1);
  std::printf("sigma_eq2_Pa = %.6f %.6f %.6f\n", box.eq2.x(), box.eq2.y(), box.eq2.z());
  return 0;
}

}  // namespace
}  // namespace granular::peer

int main(int argc, char** argv) {
  granular::peer::Options o;
  CLI::App app{"The paper's stage 2 from the settled checkpoint, timed (bench/peer/README.md)"};
  app.add_option("--checkpoint", o.checkpoint,
                 "Settled state (default runs/paper/mu03/settled.ckpt)");
  app.add_option("--scene", o.scene,
                 "Scene of the checkpoint (default assets/scenes/paper-mu03.toml)");
  app.add_option("--dt", o.dt, "Time step [s] (default: the scene's)");
  app.add_option("--skin", o.skin,
                 "Neighbour-list skin [m] (default: the checkpoint's; 0 = 0.3 x smallest radius)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--threads", o.threads, "OpenMP threads (default 1)");
  app.add_option("--duration", o.duration, "Stage-2 duration [s] (default: the scene's, 1 s)");
  app.add_flag("--exact-sums", o.exactSums,
               "Energies and wall reactions summed exactly, as a run on several processes does");
  app.add_flag("--fresh", o.fresh,
               "Drop the contact history and Gear derivatives, as a peer's data file does");
  app.add_option("--integrator", o.integrator,
                 "gear5 or verlet (with --fresh; default: the checkpoint's)")
      ->check(CLI::IsMember({"gear5", "verlet"}));
  app.add_option("--series", o.series, "Write sigma of Eq. (2) after every step to this CSV");
  app.add_flag("--auto", o.automatic,
               "time_step = \"auto\": the step chosen from the contact network (with --fresh)");
  app.add_option("--contact-resolution", o.contactResolution,
                 "With --auto: the accuracy floor, at most t_c / N (default 10)")
      ->check(CLI::Range(1.0, 1e6));
  app.add_option("--step-safety", o.stepSafety,
                 "With --auto: the step's share of the network's (default 0.9)")
      ->check(CLI::Range(0.01, 1.0));
  app.add_option("--estimate-scale", o.estimateScale,
                 "With --auto: the spectrum's estimate taken x F, F < 1 an estimate too low "
                 "whose growing modes the run must catch (a study; default 1)")
      ->check(CLI::PositiveNumber);
  app.add_option("--export-lammps", o.exportLammps,
                 "Write LAMMPS inputs to this folder, run nothing");
  app.add_option("--export-liggghts", o.exportLiggghts,
                 "Write LIGGGHTS inputs to this folder, run nothing");
  app.add_option("--radius-types", o.radiusTypes,
                 "Radius classes (atom types) for the peers' per-type stiffness (default 10)");
  app.add_flag("--mean-wall-stiffness", o.meanWallStiffness,
               "LAMMPS: one set of walls, stiffness of the mean radius (default: per class)");
  app.add_flag("--unchecked", o.unchecked,
               "A fixed step taken without its check against the contact network: a step above "
               "the network's runs (to find where it really breaks)");
  app.add_flag("--rebuild-every-step", o.rebuildEveryStep,
               "Rebuild the neighbour list every step (times the rebuild; same physics)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  // Under mpirun the stage is split by space among the ranks (exact sums, as granular run).
  std::optional<granular::MpiSession> mpi;
  if (granular::MpiSession::launched()) mpi.emplace(argc, argv);
  try {
    return granular::peer::run(
        o, mpi ? std::shared_ptr<const granular::Communicator>(mpi->world()) : nullptr);
  } catch (const granular::CheckpointError& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 1;
  } catch (const granular::ConfigError& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 2;
  } catch (const granular::SceneError& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 1;
  }
}
