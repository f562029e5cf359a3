/// `granular paper` (paper_command.hpp). Sections: 1. files of a case; 2. one case, and the
/// sensitivity runs; 3. both and the report.
#include "paper_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <variant>

#include "csv_input.hpp"
#include "csv_output.hpp"
#include "granular/checkpoint.hpp"
#include "granular/compaction.hpp"
#include "granular/run_checks.hpp"
#include "granular/scene_fingerprint.hpp"
#include "granular/stress.hpp"
#include "paper_fields.hpp"
#include "paper_figures.hpp"
#include "paper_report.hpp"
#include "paper_run_folder.hpp"
#include "progress.hpp"
#include "run_header.hpp"
#include "stop_signals.hpp"
#include "vtk_snapshot.hpp"

namespace granular::app {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// 1. Files of a case ------------------------------------------------------------------------------

/// compaction_stress.csv: one row per output interval of stage 2 (averaged over the interval).
void writeStressSeries(const std::filesystem::path& path, const CompactionResult& r) {
  std::ostringstream out;
  out << "time_s,top_wall_height_m,R33_top_N,R33_bottom_N,side_mean_R_N,side_vertical_N,weight_N,"
         "balance_error";
  for (const char* eq : {"eq1"}) {
    for (int i = 1; i <= 3; ++i) {
      for (int j = 1; j <= 3; ++j) out << ",s" << i << j << '_' << eq << "_Pa";
    }
  }
  out << ",s11_eq2_Pa,s22_eq2_Pa,s33_eq2_Pa,z_cm_m,s33_cm_term_Pa\n";
  for (const CompactionSample& s : r.samples) {
    const BoxStress& b = s.box;
    out << csvNumber(s.time) << ',' << csvNumber(b.upper.z() - b.lower.z()) << ','
        << csvNumber(b.topForce) << ',' << csvNumber(b.bottomForce) << ','
        << csvNumber(b.sideMeanForce) << ',' << csvNumber(b.sideVerticalForce) << ','
        << csvNumber(b.weight) << ',' << csvNumber(b.balanceError);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) out << ',' << csvNumber(b.eq1(i, j));
    }
    out << ',' << csvNumber(b.eq2.x()) << ',' << csvNumber(b.eq2.y()) << ',' << csvNumber(b.eq2.z())
        << ',' << csvNumber(b.centreOfMassHeight) << ',' << csvNumber(b.sigma33CentreOfMassTerm)
        << '\n';
  }
  writeTextFile(path, out.str());
}

void writeSettleHistory(const std::filesystem::path& path, const CompactionResult& r) {
  std::ostringstream out;
  out << "time_s,kinetic_J\n";
  for (const SettleSample& s : r.settleHistory) {
    out << csvNumber(s.time) << ',' << csvNumber(s.kinetic) << '\n';
  }
  writeTextFile(path, out.str());
}

/// settle_summary.txt: "key = value" lines, read back when stage 1 is restored.
void writeSettleSummary(const std::filesystem::path& path, const SettleSummary& s) {
  std::ostringstream out;
  out << "ended_by = " << s.endedBy << "\nduration_s = " << csvNumber(s.duration)
      << "\nsteps = " << csvNumber(s.steps) << "\nwall_seconds = " << csvNumber(s.wallSeconds)
      << "\nfinal_kinetic_J = " << csvNumber(s.finalKinetic)
      << "\nthreshold_J = " << csvNumber(s.threshold) << "\nsustain_s = " << csvNumber(s.sustain)
      << "\ncap_s = " << csvNumber(s.cap) << '\n';
  writeTextFile(path, out.str());
}

std::optional<SettleSummary> readSettleSummary(const std::filesystem::path& path) {
  try {
    const auto kv = readKeyValues(path);
    SettleSummary s;
    s.endedBy = kv.at("ended_by");
    s.duration = numberAt(kv, "duration_s", path);
    s.steps = numberAt(kv, "steps", path);
    s.wallSeconds = numberAt(kv, "wall_seconds", path);
    s.finalKinetic = numberAt(kv, "final_kinetic_J", path);
    s.threshold = numberAt(kv, "threshold_J", path);
    s.sustain = numberAt(kv, "sustain_s", path);
    s.cap = numberAt(kv, "cap_s", path);
    return s;
  } catch (const std::exception&) {
    return std::nullopt;  // missing or damaged: the report says the settle details are unknown
  }
}

/// Particles for the 3-D figures: id, centre, radius and one scalar per particle (Σ|F_ij| for
/// the settled bed, speed for the falling one).
void writeParticleFigureData(const std::filesystem::path& path, const Simulation& sim,
                             const std::string& scalarName, const std::vector<double>& scalar) {
  const Particles& p = sim.particles();
  std::ostringstream out;
  out << "id,x_m,y_m,z_m,radius_m," << scalarName << '\n';
  for (std::size_t i = 0; i < p.size(); ++i) {
    out << i << ',' << csvNumber(p.position[i].x()) << ',' << csvNumber(p.position[i].y()) << ','
        << csvNumber(p.position[i].z()) << ',' << csvNumber(p.radius[i]) << ','
        << csvNumber(scalar[i]) << '\n';
  }
  writeTextFile(path, out.str());
}

/// box.txt: the box the figures draw ("key = value", metres).
void writeBox(const std::filesystem::path& path, const Simulation& sim) {
  auto wall = [&](const char* name) { return sim.walls()[sim.findWall(name)].point; };
  std::ostringstream out;
  out << "x_min = " << csvNumber(wall("x-").x()) << "\nx_max = " << csvNumber(wall("x+").x())
      << "\ny_min = " << csvNumber(wall("y-").y()) << "\ny_max = " << csvNumber(wall("y+").y())
      << "\nz_min = " << csvNumber(wall("bottom").z()) << '\n';
  writeTextFile(path, out.str());
}

/// stress_t1.csv: σ_ij of Eq. (1) and the diagonal of Eq. (2) at the end of stage 2.
void writeFinalStress(const std::filesystem::path& path, const BoxStress& b) {
  std::ostringstream out;
  out << "row,eq1_col1_Pa,eq1_col2_Pa,eq1_col3_Pa,eq2_diagonal_Pa\n";
  for (int i = 0; i < 3; ++i) {
    out << i + 1 << ',' << csvNumber(b.eq1(i, 0)) << ',' << csvNumber(b.eq1(i, 1)) << ','
        << csvNumber(b.eq1(i, 2)) << ',' << csvNumber(b.eq2[i]) << '\n';
  }
  writeTextFile(path, out.str());
}

/// ParaView files of stage 2 every `kParaviewInterval` of its clock, from the settled bed (t = 0)
/// to the end: paraview/compaction_<t>_{particles,contacts,walls}.vtp and one .pvd per kind,
/// rewritten with each snapshot so an interrupted run still opens.
constexpr double kParaviewInterval = 0.1;  // [s]

class CompactionParaview {
 public:
  CompactionParaview(std::filesystem::path dir, const Scene& scene) : dir_(std::move(dir)) {
    boxMin_ = scene.box.min;
    boxMax_ = scene.box.max;
    every_ = std::max(1L, std::lround(kParaviewInterval / scene.output.interval));
    interval_ = scene.output.interval;
    createOutputFolder(dir_ / "paraview");
  }

  /// Called with every stage-2 sample, the first at t = 0.
  void sample(const Simulation& sim) {
    const long index = samples_++;
    if (index % every_ != 0) return;
    // Rounded to a nanosecond so 7 × 0.1 names its file 0.7, not 0.7000000000000001.
    const double t = std::round(static_cast<double>(index) * interval_ * 1e9) / 1e9;
    for (const char* kind : {"particles", "contacts", "walls"}) {
      const std::filesystem::path file =
          std::filesystem::path("paraview") / ("compaction_" + csvNumber(t) + "_" + kind + ".vtp");
      const std::string k = kind;
      if (k == "particles") writeParticlesVtp(dir_ / file, sim);
      if (k == "contacts") writeContactsVtp(dir_ / file, sim);
      if (k == "walls") writeWallsVtp(dir_ / file, sim, boxMin_, boxMax_);
      entries_[k].push_back({t, file});
      writePvd(dir_ / ("compaction_" + k + ".pvd"), entries_[k]);
    }
  }

 private:
  std::filesystem::path dir_;
  Vec3 boxMin_, boxMax_;
  long every_ = 1, samples_ = 0;
  double interval_ = 0;
  std::map<std::string, std::vector<PvdEntry>> entries_;
};

// 2. One case -------------------------------------------------------------------------------------

/// Mean reduced radius and overlap of the bed's contacts: each particle pair once (from its lower
/// index), each particle-wall contact once with R_ij = R_i (a wall is a body of infinite radius).
BedContacts bedContacts(const Simulation& sim) {
  const Particles& p = sim.particles();
  const double coefficient = sim.config().material.tangentialCoefficient();
  BedContacts bed;
  double radius = 0, overlap = 0, sideStiffness = 0;
  std::size_t side = 0;
  sim.forEachContact([&](const ContactView& v) {
    if (!v.isWall() && v.otherParticle() < v.particle) return;
    if (!v.touching()) return;
    const double ri = p.radius[v.particle];
    const double rj = v.isWall() ? 0.0 : p.radius[v.otherParticle()];
    radius += v.isWall() ? ri : ri * rj / (ri + rj);
    overlap += v.overlap;
    ++bed.count;
    const std::string& wall = v.isWall() ? sim.walls()[v.wall()].name : std::string();
    if (wall == "x-" || wall == "x+" || wall == "y-" || wall == "y+") {
      sideStiffness += coefficient * std::sqrt(ri * v.overlap);
      ++side;
    }
  });
  if (bed.count > 0) {
    bed.meanRadius = radius / double(bed.count);
    bed.meanOverlap = overlap / double(bed.count);
  }
  if (side > 0) bed.sideWallMindlin = sideStiffness / double(side);
  return bed;
}

/// Both stages of the case in `folder`. A failed run check (energy balance, a particle outside
/// the box) is a warning on stderr naming the case, kept in the result for the report; under
/// on_failed_check = "stop" it ends the command (exit 3), naming the case.
CompactionResult checkedCompaction(const Scene& scene, const CompactionOptions& run,
                                   const std::string& folder, ProgressReporter& progress) {
  CompactionResult result;
  try {
    result = runCompaction(scene, run);
  } catch (const RunCheckError& e) {
    progress.finish();
    throw RunCheckError("case " + folder + ": " + e.what());
  }
  progress.finish();
  for (const std::string& failed : result.failedChecks) {
    std::cerr << "warning: case " << folder << ": " << failed << "\n";
  }
  return result;
}

/// The scene of a case: the paper's, with the constant tangential law at `constantStiffness`
/// when positive and the grid's seed replaced when `seed` is given.
Scene caseScene(const std::filesystem::path& sceneFile, double constantStiffness,
                std::optional<std::uint64_t> seed) {
  Scene scene = loadScene(sceneFile);
  if (constantStiffness > 0) {
    scene.simulation.material.tangentialLaw = TangentialLaw::Constant;
    scene.simulation.material.tangentialStiffness = constantStiffness;
  }
  if (seed) {
    auto* grid =
        scene.generators.size() == 1 ? std::get_if<GridGenerator>(&scene.generators[0]) : nullptr;
    if (!grid) {
      throw ConfigError(sceneFile.string() +
                        ": --sensitivity varies the seed of the particles' grid, and this scene "
                        "has no single [[particles]] grid");
    }
    grid->seed = *seed;
  }
  return scene;
}

std::uint64_t gridSeed(const Scene& scene) {
  const auto* grid =
      scene.generators.size() == 1 ? std::get_if<GridGenerator>(&scene.generators[0]) : nullptr;
  return grid ? grid->seed : 0;
}

/// One case into options.outDir/folder: the paper's scene, or with `constantStiffness` > 0 the
/// same scene with the constant tangential law.
CaseOutcome runCase(const PaperReference& ref, const std::string& folder, double constantStiffness,
                    const PaperOptions& options, ProgressReporter& progress) {
  const auto start = std::chrono::steady_clock::now();
  const std::filesystem::path sceneFile = options.scenesDir / ref.scene;
  const Scene scene = caseScene(sceneFile, constantStiffness, std::nullopt);
  const std::filesystem::path dir = options.outDir / folder;
  createOutputFolder(dir);
  const std::filesystem::path checkpoint = dir / "settled.ckpt";
  if (options.fresh) std::filesystem::remove(checkpoint);
  std::string caseText = "scene = " + sceneFile.string() +
                         "\nfriction = " + csvNumber(scene.simulation.material.friction) + "\n";
  if (constantStiffness > 0) {
    caseText += "tangential_law = constant\ntangential_stiffness_N_per_m = " +
                csvNumber(constantStiffness) + "\n";
  }
  writeTextFile(dir / "case.txt", caseText);

  CaseOutcome outcome;
  outcome.reference = &ref;
  outcome.folder = folder;
  outcome.constantStiffness = constantStiffness;
  outcome.seed = gridSeed(scene);
  std::unique_ptr<TimeSeriesWriter> settleSeries;  // opened only if stage 1 really runs
  TimeSeriesWriter compactSeries(dir / "compaction_timeseries.csv", reactionWallNames(scene),
                                 scene.simulation.material);
  CompactionParaview paraview(dir, scene);
  const StageSpec& settleStage = scene.stages.at(0);

  CompactionOptions run;
  run.checkpoint = checkpoint;
  run.fingerprint = fingerprintScene(scene);
  run.onStart = [&](const Simulation& sim) {
    printHeader(std::cout, scene, sim, dir);
    outcome.density = sim.config().material.density;
    outcome.friction = sim.config().material.friction;
    outcome.timeStep = sim.config().timeStep;
    outcome.contactDuration = sim.contactScale().duration;
    outcome.integrator =
        sim.config().integrator == Integrator::Gear5 ? "Gear 5th order" : "velocity Verlet";
    outcome.boxSide =
        sim.walls()[sim.findWall("x+")].point.x() - sim.walls()[sim.findWall("x-")].point.x();
  };
  // Fig. 2 shows the falling particles at t = 1 s of stage 1; Figs. 3 and 6 the settled bed.
  run.settleSnapshots = {1.0};
  run.onSettleSnapshot = [&](const Simulation& sim, double) {
    std::vector<double> speed;
    for (const Vec3& v : sim.particles().velocity) speed.push_back(v.norm());
    writeParticleFigureData(dir / "falling_t1.csv", sim, "speed_m_per_s", speed);
  };
  run.onSettled = [&](const Simulation& sim) {
    writeParticleFigureData(dir / "settled_particles.csv", sim, "force_sum_N",
                            particleForceSums(sim));
    writeBox(dir / "box.txt", sim);
    outcome.fields = writeStressFields(sim, dir);
    outcome.bed = bedContacts(sim);
  };
  run.onSample = [&](const Simulation& sim, const std::string& stage) {
    if (stage == settleStage.name) {
      if (!settleSeries) {
        settleSeries = std::make_unique<TimeSeriesWriter>(
            dir / "settle_timeseries.csv", reactionWallNames(scene), scene.simulation.material);
      }
      settleSeries->write(stage, sim);
    } else {
      compactSeries.write(stage, sim);
      paraview.sample(sim);
    }
  };
  run.onProgress = [&](const Simulation& sim, const StageSpec& stage) {
    progress.update(sim, stage);
    stopIfSignalled("case " + folder + " is incomplete; run the same command again" +
                    (stage.name == settleStage.name
                         ? std::string(" (stage 1 starts again)")
                         : " (stage 1 is restored from " + checkpoint.string() + ")"));
  };
  outcome.result = checkedCompaction(scene, run, folder, progress);
  if (!outcome.result.checkpointRefused.empty()) {
    std::cout << "settled again: the settled checkpoint was not used: "
              << outcome.result.checkpointRefused << "\n";
  }

  const CompactionResult& r = outcome.result;
  if (!r.checkpointRefused.empty()) {
    std::cout << "not restored, settled again: " << r.checkpointRefused << "\n";
  }
  if (!r.settleRestored) {
    SettleSummary& s = outcome.settle;
    s.endedBy = r.settle.reason == StageEndReason::KineticEnergy ? "kinetic energy below threshold"
                                                                 : "max time";
    s.duration = r.settle.duration;
    s.steps = static_cast<double>(r.settle.steps);
    s.wallSeconds = r.settleWallSeconds;
    s.finalKinetic = r.settleHistory.empty() ? 0.0 : r.settleHistory.back().kinetic;
    s.threshold = settleStage.end.kineticEnergyBelow.value_or(0.0);
    s.sustain = settleStage.end.sustainTime;
    s.cap = settleStage.end.maxTime;
    writeSettleSummary(dir / "settle_summary.txt", s);
    writeSettleHistory(dir / "settle_kinetic.csv", r);
  } else if (auto saved = readSettleSummary(dir / "settle_summary.txt")) {
    outcome.settle = *saved;
  } else {
    outcome.settle.endedBy = "unknown (restored from a checkpoint without settle_summary.txt)";
  }
  std::cout << "stage 1 (" << settleStage.name << "): "
            << (r.settleRestored
                    ? "restored from " + checkpoint.string()
                    : outcome.settle.endedBy + " after " + format("%.4g", r.settle.duration) +
                          " s simulated (" + format("%.1f", r.settleWallSeconds) + " s wall-clock)")
            << "; settled height " << format("%.4f", r.settledHeight) << " m\n";
  std::cout << "stage 2 (" << scene.stages[1].name << "): " << format("%.4g", r.compact.duration)
            << " s simulated (" << format("%.1f", r.compactWallSeconds) << " s wall-clock); strain "
            << format("%.2f", 1000 * r.strain) << " per mille\n";
  writeStressSeries(dir / "compaction_stress.csv", r);
  writeFinalStress(dir / "stress_t1.csv", r.samples.back().box);
  outcome.wallSeconds = secondsSince(start);
  return outcome;
}

/// One bed of --sensitivity into `dir`: both stages with the settled checkpoint and the stress
/// fields, none of a case's other files (time series, ParaView, figure data).
CaseOutcome runSeed(const PaperReference& ref, const Scene& scene, const std::filesystem::path& dir,
                    double constantStiffness, const PaperOptions& options,
                    ProgressReporter& progress) {
  const auto start = std::chrono::steady_clock::now();
  createOutputFolder(dir);
  CaseOutcome outcome;
  outcome.reference = &ref;
  outcome.folder = dir.filename().string();
  outcome.constantStiffness = constantStiffness;
  outcome.seed = gridSeed(scene);
  CompactionOptions run;
  run.checkpoint = dir / "settled.ckpt";
  if (options.fresh) std::filesystem::remove(run.checkpoint);
  run.fingerprint = fingerprintScene(scene);
  run.onStart = [&](const Simulation& sim) {
    outcome.density = sim.config().material.density;
    outcome.friction = sim.config().material.friction;
    outcome.timeStep = sim.config().timeStep;
    outcome.boxSide =
        sim.walls()[sim.findWall("x+")].point.x() - sim.walls()[sim.findWall("x-")].point.x();
  };
  run.onSettled = [&](const Simulation& sim) {
    outcome.fields = writeStressFields(sim, dir);
    outcome.bed = bedContacts(sim);
  };
  run.onProgress = [&](const Simulation& sim, const StageSpec& stage) {
    progress.update(sim, stage);
    stopIfSignalled(
        "the sensitivity runs are incomplete; run the same command again (the beds "
        "settled so far are restored)");
  };
  outcome.result = checkedCompaction(scene, run, outcome.folder, progress);
  outcome.wallSeconds = secondsSince(start);
  return outcome;
}

/// The report's sensitivity study: the μ = 0.3 case with the constant law at the Mindlin k_t of
/// its settled bed's R̄ and h̄, and with --sensitivity both laws from more seeds.
SensitivityOutcome runSensitivity(const CaseOutcome& mindlin, const PaperOptions& options,
                                  ProgressReporter& progress) {
  SensitivityOutcome s;
  s.defaultSeeds = kSensitivitySeeds;
  if (mindlin.friction == 0) {
    s.skipped = "the " + mindlin.folder +
                " scene has no friction, so the tangential spring carries no force under either "
                "law";
    return s;
  }
  const PaperReference& ref = *mindlin.reference;
  const Scene scene = loadScene(options.scenesDir / ref.scene);
  s.coefficient = scene.simulation.material.tangentialCoefficient();
  s.bed = mindlin.bed;
  s.stiffness = s.coefficient * std::sqrt(s.bed.meanRadius * s.bed.meanOverlap);
  std::cout << "\n== case " << ref.name
            << "_constant_kt: constant k_t = " << format("%.6g", s.stiffness) << " N/m ==\n";
  s.constant = runCase(ref, std::string(ref.name) + "_constant_kt", s.stiffness, options, progress);
  if (!options.sensitivity) return s;

  const auto start = std::chrono::steady_clock::now();
  s.mindlinSeeds.push_back(mindlin);
  s.constantSeeds.push_back(*s.constant);
  const std::filesystem::path root = options.outDir / "sensitivity";
  for (int k = 1; k < options.seeds; ++k) {
    const std::uint64_t seed = mindlin.seed + std::uint64_t(k);
    for (const double stiffness : {0.0, s.stiffness}) {
      const std::string name =
          "seed" + std::to_string(seed) + (stiffness > 0 ? "_constant_kt" : "_mindlin");
      std::cout << "== sensitivity: " << name << " ==\n";
      const Scene seeded = caseScene(options.scenesDir / ref.scene, stiffness, seed);
      CaseOutcome run = runSeed(ref, seeded, root / name, stiffness, options, progress);
      (stiffness > 0 ? s.constantSeeds : s.mindlinSeeds).push_back(std::move(run));
    }
  }
  writeTextFile(root / "seeds.csv", sensitivityCsv(s));
  s.seedSeconds = secondsSince(start);
  return s;
}

// 3. Both cases and the report --------------------------------------------------------------------

int runPaper(const PaperOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  catchStopSignals();
  checkPaperOutputFolder(options.outDir, options.force);
  createOutputFolder(options.outDir);
  ProgressReporter progress(!options.quiet);
  if (options.sensitivity && options.seeds < 2) {
    throw ConfigError("--seeds " + std::to_string(options.seeds) +
                      ": must be at least 2 (the paper's seed and one more) for a spread");
  }
  std::vector<CaseOutcome> cases;
  for (const PaperReference& ref : kPaperCases) {
    std::cout << "\n== case " << ref.name << " ==\n";
    cases.push_back(runCase(ref, ref.name, 0.0, options, progress));
  }
  const SensitivityOutcome sensitivity = runSensitivity(cases.back(), options, progress);
  std::vector<FigureFile> figures;
  try {
    FigureSet set = drawPaperFigures(options.outDir);
    for (const std::string& missing : set.missing) {
      std::cerr << "warning: figure not drawn: " << missing << "\n";
    }
    for (const std::string& gap : set.gaps) std::cerr << "warning: " << gap << "\n";
    figures = std::move(set.written);
  } catch (const Interrupted&) {
    throw;
  } catch (const IoError&) {
    throw;  // a full disk or a folder in the way: the report would fail the same way
  } catch (const std::exception& e) {
    // The numbers stand without the pictures: say so and go on to the report.
    std::cerr << "warning: figures not drawn: " << e.what() << "\n";
  }
  const double total = secondsSince(start);
  writeTextFile(options.outDir / "report.md", paperReport(cases, sensitivity, figures, total));
  std::cout << "\nwrote " << (options.outDir / "report.md").string() << " ("
            << format("%.1f", total) << " s wall-clock)\n";
  return 0;
}

}  // namespace

int paperCommand(const PaperOptions& options) {
  return withErrorMapping([&] { return runPaper(options); });
}

}  // namespace granular::app
