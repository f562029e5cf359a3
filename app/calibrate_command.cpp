/// `granular calibrate-box` (calibrate_command.hpp).
#include "calibrate_command.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "csv_output.hpp"
#include "granular/error.hpp"
#include "granular/run_checks.hpp"
#include "granular/scene.hpp"
#include "granular/stage.hpp"
#include "progress.hpp"
#include "run_header.hpp"
#include "stop_signals.hpp"

namespace granular::app {
namespace {

/// The scene with a square footprint of side `side`, its grid generators re-laid to cover the
/// new footprint (centred, as many whole cells as fit) with the same particle count.
Scene withSide(Scene scene, double side) {
  scene.box.max.x() = scene.box.min.x() + side;
  scene.box.max.y() = scene.box.min.y() + side;
  for (Generator& g : scene.generators) {
    if (auto* grid = std::get_if<GridGenerator>(&g)) {
      const int across = static_cast<int>(std::floor(side / grid->cellSize + 1e-9));
      if (across < 1)
        throw ConfigError("box side " + format("%g", side) + " m is below one grid cell");
      grid->cells[0] = grid->cells[1] = across;
      grid->cells[2] = static_cast<int>((grid->count + across * across - 1) / (across * across));
      const double margin = 0.5 * (side - across * grid->cellSize);
      grid->origin.x() = scene.box.min.x() + margin;
      grid->origin.y() = scene.box.min.y() + margin;
    }
  }
  return scene;
}

int calibrate(const CalibrateOptions& options) {
  if (options.sides.empty()) throw ConfigError("calibrate-box: give at least one --sides value");
  catchStopSignals();
  // Refused now rather than after the settling runs.
  if (std::filesystem::is_directory(options.report)) {
    throw IoError(options.report.string() +
                  ": --report is a folder; give the markdown file to write, e.g. " +
                  (options.report / "calibration.md").string());
  }
  const Scene base = loadScene(options.scene);
  ProgressReporter progress(!options.quiet);
  std::ostringstream table;
  table << "| box side [m] | settled height [m] | ended by | simulated [s] | wall-clock [s] |\n"
        << "|---|---|---|---|---|\n";
  // Settled height scales as 1/side² at fixed packing fraction: fit H = a/side² by least squares.
  double sumXY = 0, sumXX = 0;
  std::vector<std::string> failedChecks;  // "box side 0.5 m: what failed"
  for (double side : options.sides) {
    const Scene scene = withSide(base, side);
    Simulation sim = buildSimulation(scene);
    const std::string box = "box side " + format("%g", side) + " m";
    // Each settling checks itself at its samples, as `granular run` does: a failed check is a
    // warning on stderr and in the report, or ends the command under on_failed_check = "stop".
    RunChecks checks(scene.output.checks, scene.box, sim.energy().total());
    StageObserver observer;
    observer.onSample = [&](const Simulation& s) {
      try {
        for (const std::string& failed : checks.atSample(s, scene.stages.at(0).name)) {
          progress.finish();
          std::cerr << "warning: " << box << ": " << failed << "\n";
          failedChecks.push_back(box + ": " + failed);
        }
      } catch (const RunCheckError& e) {
        progress.finish();
        throw RunCheckError(box + ": " + e.what() + "; nothing written");
      }
    };
    observer.onProgress = [&](const Simulation& s, const StageSpec& st) {
      progress.update(s, st);
      stopIfSignalled("the box of side " + format("%g", side) +
                      " m was not finished; nothing written");
    };
    observer.progressSteps = 200;
    const auto start = std::chrono::steady_clock::now();
    const StageResult r = runStage(sim, scene.stages.at(0), scene.output, observer);
    progress.finish();
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    double top = 0;
    const Particles& p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i) top = std::max(top, p.position[i].z() + p.radius[i]);
    const double height = top - scene.box.min.z();
    const double x = 1.0 / (side * side);
    sumXY += x * height;
    sumXX += x * x;
    std::ostringstream line;
    line << "| " << format("%.4f", side) << " | " << format("%.4f", height) << " | "
         << (r.reason == StageEndReason::KineticEnergy ? "kinetic energy" : "max time") << " | "
         << format("%.3f", r.duration) << " | " << format("%.1f", wall) << " |\n";
    std::cout << line.str() << std::flush;
    table << line.str();
  }
  const double a = sumXY / sumXX;
  const double best = std::sqrt(a / options.targetHeight);
  std::ostringstream result;
  result << "\nFit H = a / side² with a = " << format("%.5f", a) << " m³: side "
         << format("%.4f", best) << " m gives the target settled height "
         << format("%.4f", options.targetHeight) << " m.\n";
  std::cout << result.str();
  // The report says whether the settlings it rests on passed their run checks.
  std::string checked = "\nRun checks (energy balance, particles in the box): ";
  if (failedChecks.empty()) {
    checked += "every settling passed.\n";
  } else {
    checked += "**failed**, the heights above may not be trustworthy:\n\n";
    for (const std::string& failed : failedChecks) checked += "- " + failed + "\n";
  }
  if (!options.report.empty()) {
    std::string sides;
    for (double side : options.sides) {
      if (!sides.empty()) sides += ',';
      sides += format("%g", side);
    }
    writeTextFile(options.report, "Command: `granular calibrate-box " + options.scene.string() +
                                      " --target-height " + format("%g", options.targetHeight) +
                                      " --sides " + sides + "`\n\n" + table.str() + result.str() +
                                      checked);
  }
  return 0;
}

}  // namespace

int calibrateCommand(const CalibrateOptions& options) {
  return withErrorMapping([&] { return calibrate(options); });
}

}  // namespace granular::app
