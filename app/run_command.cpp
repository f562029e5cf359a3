/// `granular run` (see run_command.hpp).
/// Sections: 1. header; 2. output names; 3. running the stages; 4. summary; 5. error mapping.
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

namespace granular::app {

namespace {

std::string format(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

double totalMass(const Particles& particles) {
  double sum = 0.0;
  for (double m : particles.mass) sum += m;
  return sum;
}

// 1. Header ---------------------------------------------------------------------------------------

void printHeader(std::ostream& out, const Scene& scene, const Simulation& sim,
                 const std::filesystem::path& outDir) {
  const SimulationConfig& config = sim.config();
  const ContactScale& contact = sim.contactScale();
  const double dt = config.timeStep;
  out << "scene       " << scene.sourceFile.string() << "\n";
  out << "particles   " << sim.particles().size() << ", total mass "
      << format("%.6g", totalMass(sim.particles())) << " kg (density "
      << format("%.6g", config.material.density) << " kg/m³"
      << (scene.totalMass ? ", scaled to the scene's total_mass" : "") << ")\n";
  out << "integrator  " << (config.integrator == Integrator::Gear5 ? "gear5" : "verlet")
      << ", dt = " << format("%.3g", dt) << " s\n";
  out << "contact     stiffest " << (contact.againstWall ? "particle-wall" : "particle-particle")
      << " (R = " << format("%.4g", contact.radius) << " m), duration "
      << format("%.4g", contact.duration) << " s; dt = duration/"
      << format("%.1f", contact.duration / dt) << "\n";
  out << "friction    "
      << (sim.frictional() ? "on (mu = " + format("%g", config.material.friction) +
                                 "): tangential forces and rotations integrated"
                           : std::string("off (mu = 0): no tangential forces, no rotations"))
      << "\n";
  out << "walls      ";
  for (const Wall& wall : sim.walls()) out << " " << wall.name;
  out << "\nstages     ";
  for (const StageSpec& stage : scene.stages) {
    out << " " << stage.name << " (<= " << format("%g", stage.end.maxTime) << " s)";
  }
  out << "\noutput      " << outDir.string() << " (sample every "
      << format("%g", scene.output.interval) << " s)\n"
      << std::flush;
}

// 2. Output names ---------------------------------------------------------------------------------

/// The walls whose reactions the time series carries: the box's, plus the top wall if a stage
/// will place it. Fixed before the run because CSV columns cannot be added later.
std::vector<std::string> reactionWalls(const Scene& scene) {
  std::vector<std::string> walls;
  for (std::size_t f = 0; f < kBoxWallNames.size(); ++f) {
    if (scene.box.walls[f]) walls.push_back(kBoxWallNames[f]);
  }
  for (const StageSpec& stage : scene.stages) {
    if (stage.placeTopWallOnSurface && !scene.box.walls[5]) {
      walls.push_back("top");
      break;
    }
  }
  return walls;
}

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

// 3. Running the stages ---------------------------------------------------------------------------

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

  TimeSeriesWriter series(outDir / "timeseries.csv", reactionWalls(scene));
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

  // 4. Summary
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

// 5. Error mapping --------------------------------------------------------------------------------

int runCommand(const RunOptions& options) {
  try {
    return runScene(options);
  } catch (const SceneError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const ConfigError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const IoError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace granular::app
