/// `granular paper` (paper_command.hpp). Sections: 1. files of a case; 2. one case; 3. both and
/// the report.
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

#include "csv_input.hpp"
#include "csv_output.hpp"
#include "granular/checkpoint.hpp"
#include "granular/compaction.hpp"
#include "granular/scene_fingerprint.hpp"
#include "granular/stress.hpp"
#include "paper_fields.hpp"
#include "paper_figures.hpp"
#include "paper_report.hpp"
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

CaseOutcome runCase(const PaperReference& ref, const PaperOptions& options,
                    ProgressReporter& progress) {
  const auto start = std::chrono::steady_clock::now();
  const std::filesystem::path sceneFile = options.scenesDir / ref.scene;
  const Scene scene = loadScene(sceneFile);
  const std::filesystem::path dir = options.outDir / ref.name;
  createOutputFolder(dir);
  const std::filesystem::path checkpoint = dir / "settled.ckpt";
  if (options.fresh) std::filesystem::remove(checkpoint);
  writeTextFile(dir / "case.txt", "scene = " + sceneFile.string() + "\nfriction = " +
                                      csvNumber(scene.simulation.material.friction) + "\n");

  CaseOutcome outcome;
  outcome.reference = &ref;
  std::unique_ptr<TimeSeriesWriter> settleSeries;  // opened only if stage 1 really runs
  TimeSeriesWriter compactSeries(dir / "compaction_timeseries.csv", reactionWallNames(scene));
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
  };
  run.onSample = [&](const Simulation& sim, const std::string& stage) {
    if (stage == settleStage.name) {
      if (!settleSeries) {
        settleSeries = std::make_unique<TimeSeriesWriter>(dir / "settle_timeseries.csv",
                                                          reactionWallNames(scene));
      }
      settleSeries->write(stage, sim);
    } else {
      compactSeries.write(stage, sim);
      paraview.sample(sim);
    }
  };
  run.onProgress = [&](const Simulation& sim, const StageSpec& stage) {
    progress.update(sim, stage);
    stopIfSignalled("case " + std::string(ref.name) + " is incomplete; run the same command again" +
                    (stage.name == settleStage.name
                         ? std::string(" (stage 1 starts again)")
                         : " (stage 1 is restored from " + checkpoint.string() + ")"));
  };
  outcome.result = runCompaction(scene, run);
  progress.finish();
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

// 3. Both cases and the report --------------------------------------------------------------------

/// A folder `granular paper` may write into: new, empty, or one it wrote before (holding a
/// case folder). Anything else is somebody's other work, kept unless --force.
void checkOutputFolder(const PaperOptions& options) {
  std::error_code ec;
  if (options.force || !std::filesystem::exists(options.outDir, ec)) return;
  if (!std::filesystem::is_directory(options.outDir, ec)) {
    throw IoError(options.outDir.string() + ": --out must be a folder; this is a file");
  }
  if (std::filesystem::is_empty(options.outDir, ec)) return;
  for (const PaperReference& ref : kPaperCases) {
    if (std::filesystem::is_directory(options.outDir / ref.name, ec)) return;
  }
  throw ConfigError(options.outDir.string() +
                    ": not empty and not a `granular paper` run folder (no mu0/ or mu03/): "
                    "its report.md and figures/ would be overwritten; choose another --out or "
                    "add --force");
}

int runPaper(const PaperOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  catchStopSignals();
  checkOutputFolder(options);
  createOutputFolder(options.outDir);
  ProgressReporter progress(!options.quiet);
  std::vector<CaseOutcome> cases;
  for (const PaperReference& ref : kPaperCases) {
    std::cout << "\n== case " << ref.name << " ==\n";
    cases.push_back(runCase(ref, options, progress));
  }
  std::vector<FigureFile> figures;
  try {
    FigureSet set = drawPaperFigures(options.outDir);
    for (const std::string& missing : set.missing) {
      std::cerr << "warning: figure not drawn: " << missing << "\n";
    }
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
  writeTextFile(options.outDir / "report.md", paperReport(cases, figures, total));
  std::cout << "\nwrote " << (options.outDir / "report.md").string() << " ("
            << format("%.1f", total) << " s wall-clock)\n";
  return 0;
}

}  // namespace

int paperCommand(const PaperOptions& options) {
  return withErrorMapping([&] { return runPaper(options); });
}

}  // namespace granular::app
