/// siloCommand (silo_command.hpp).
#include "silo_command.hpp"

#include <chrono>
#include <iostream>

#include "csv_output.hpp"
#include "granular/error.hpp"
#include "granular/scene.hpp"
#include "granular/silo_study.hpp"
#include "progress.hpp"
#include "run_header.hpp"
#include "silo_figures.hpp"
#include "silo_report.hpp"

namespace granular::app {

namespace {

int runSilo(const SiloOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  Scene scene = loadScene(options.scene);
  for (const std::string& warning : scene.warnings) std::cerr << "warning: " << warning << "\n";
  if (scene.stages.empty() || scene.stages[0].inserts.empty()) {
    throw ConfigError(options.scene.string() +
                      ": the silo study fills the silo with the first stage's insert; it has none");
  }
  if (options.particles > 0) scene.stages[0].inserts[0].count = options.particles;
  if (!(options.dischargeTime > 0)) {
    throw ConfigError("--discharge-time = " + std::to_string(options.dischargeTime) +
                      " s: must be > 0");
  }
  createOutputFolder(options.outDir);

  ProgressReporter reporter(!options.quiet);
  StageSpec shown;
  SiloStudyOptions study;
  study.dischargeTime = options.dischargeTime;
  study.onProgress = [&](const Simulation& sim, const std::string& phase) {
    if (shown.name != phase) {
      reporter.finish();
      shown.name = phase;
    }
    reporter.update(sim, shown);
  };
  std::cout << "silo study: " << options.scene.string() << ", " << scene.stages[0].inserts[0].count
            << " particles poured in, then " << options.dischargeTime
            << " s through each orifice\n";
  const SiloStudyResult result = runSiloStudy(scene, study);
  reporter.finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  writeSiloTables(result, options.outDir);
  const std::vector<std::filesystem::path> figures = drawSiloFigures(result, options.outDir);
  writeTextFile(options.outDir / "report.md",
                siloReport(result, options.scene.filename().string(), seconds));
  std::cout << "Janssen: λ = μ_w K = " << result.janssen.lambda << " fitted (RMS "
            << 100 * result.janssen.rmsRelativeResidual << " %), " << result.lambdaMeasured
            << " measured\n";
  if (result.beverlooFitted) {
    std::cout << "Beverloo: C = " << result.beverloo.c << ", k = " << result.beverloo.k << "\n";
  }
  std::cout << "wrote " << (options.outDir / "report.md").string() << ", levels.csv, "
            << "discharge.csv" << (result.hasHopper ? ", hopper.csv" : "");
  for (const std::filesystem::path& f : figures) std::cout << ", " << f.filename().string();
  std::cout << " (" << seconds << " s)\n";
  return 0;
}

}  // namespace

int siloCommand(const SiloOptions& options) {
  return withErrorMapping([&] { return runSilo(options); });
}

}  // namespace granular::app
