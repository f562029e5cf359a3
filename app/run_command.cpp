/// `granular run` (see run_command.hpp).
/// Sections: 1. output names; 2. running the stages; 3. summary.
#include "run_command.hpp"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "csv_output.hpp"
#include "granular/error.hpp"
#include "granular/scene.hpp"
#include "granular/stage.hpp"
#include "progress.hpp"
#include "run_header.hpp"

namespace granular::app {

namespace {

// 1. Output names ---------------------------------------------------------------------------------

/// snapshot_<stage>_<time>.csv: the stage is part of the name because snapshot times are on
/// each stage's own clock, so two stages can pass the same time.
std::filesystem::path snapshotPath(const std::filesystem::path& outDir, const std::string& stage,
                                   double time) {
  std::string safe;
  for (char c : stage) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '-' || c == '_';
    safe += plain ? c : '_';
  }
  return outDir / ("snapshot_" + safe + "_" + csvNumber(time) + ".csv");
}

const char* reasonText(StageEndReason reason) {
  return reason == StageEndReason::KineticEnergy ? "kinetic energy below threshold" : "max time";
}

// 2. Running the stages ---------------------------------------------------------------------------

struct StageReport {
  std::string name;
  StageResult result;
  double wallSeconds = 0.0;
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int runScene(const RunOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  const Scene scene = loadScene(options.scene);
  Simulation sim = buildSimulation(scene);

  const std::filesystem::path outDir = options.outDir.empty()
                                           ? std::filesystem::path("runs") / options.scene.stem()
                                           : options.outDir;
  std::filesystem::create_directories(outDir);
  printHeader(std::cout, scene, sim, outDir);

  TimeSeriesWriter series(outDir / "timeseries.csv", reactionWallNames(scene));
  ProgressReporter progress(!options.quiet);
  std::vector<StageReport> reports;
  for (const StageSpec& stage : scene.stages) {
    StageObserver observer;
    observer.onSample = [&](const Simulation& s) { series.write(stage.name, s); };
    observer.onSnapshot = [&](const Simulation& s, double time) {
      writeParticleState(snapshotPath(outDir, stage.name, time), s.particles());
    };
    observer.onProgress = [&](const Simulation& s, const StageSpec& st) { progress.update(s, st); };
    observer.progressSteps = 200;  // a clock read every 200 steps costs nothing measurable

    const auto stageStart = std::chrono::steady_clock::now();
    const StageResult result = runStage(sim, stage, scene.output, observer);
    progress.finish();
    reports.push_back({stage.name, result, secondsSince(stageStart)});
    std::cout << "stage " << stage.name << ": " << reasonText(result.reason) << " after "
              << format("%.6g", result.duration) << " s (" << result.steps << " steps, "
              << format("%.1f", reports.back().wallSeconds) << " s wall-clock), KE "
              << format("%.3e", sim.kineticEnergy()) << " J\n"
              << std::flush;
  }
  writeParticleState(outDir / "final_state.csv", sim.particles());

  // 3. Summary
  // -------------------------------------------------------------------------------------
  std::ostringstream summary;
  summary << "scene: " << scene.sourceFile.string() << "\n"
          << "particles: " << sim.particles().size() << "\n"
          << "total mass: " << format("%.6g", totalMass(sim.particles())) << " kg\n"
          << "stages:\n";
  for (const StageReport& r : reports) {
    summary << "  " << r.name << ": ended by " << reasonText(r.result.reason) << "; "
            << format("%.6g", r.result.duration) << " s simulated, " << r.result.steps << " steps, "
            << format("%.2f", r.wallSeconds) << " s wall-clock\n";
  }
  summary << "final kinetic energy: " << format("%.6e", sim.kineticEnergy()) << " J\n"
          << "wall-clock: " << format("%.2f", secondsSince(started)) << " s\n";
  writeTextFile(outDir / "summary.txt", summary.str());
  std::cout << "wrote " << (outDir / "timeseries.csv").string()
            << ", final_state.csv, summary.txt\n";
  return 0;
}

}  // namespace

int runCommand(const RunOptions& options) {
  return withErrorMapping([&] { return runScene(options); });
}

}  // namespace granular::app
