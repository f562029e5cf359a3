/// siloCommand (silo_command.hpp).
#include "silo_command.hpp"

#include <chrono>
#include <cmath>
#include <iostream>

#include "csv_output.hpp"
#include "granular/error.hpp"
#include "granular/render/gl_context.hpp"
#include "granular/scene.hpp"
#include "granular/silo_study.hpp"
#include "progress.hpp"
#include "run_header.hpp"
#include "silo_figures.hpp"
#include "silo_report.hpp"
#include "silo_section_figures.hpp"

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
  // The settled bed's sections are drawn when the study reaches it: it goes on to discharge.
  std::vector<std::filesystem::path> sections;
  study.onSettled = [&](const Simulation& settled, const SiloStudyResult& atRest) {
    // The midsection ends a diameter above the bed's mean surface: above it the loose top
    // layer carries a few grains' weight and σ1's direction wanders (the cut-away frames every
    // particle whatever this top).
    double top = atRest.transition;
    const Particles& p = settled.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
      top = std::max(top, p.position[i].z() + p.radius[i]);
    }
    top = std::min(top, atRest.surface + atRest.particleDiameter);
    try {
      SiloSectionGeometry geometry{atRest.radius, atRest.floor, top};
      if (atRest.hasHopper) {
        geometry.transition = atRest.transition;
        geometry.outletRadius =
            atRest.radius - (atRest.transition - atRest.floor) * std::tan(atRest.hopperHalfAngle);
      }
      sections = writeSiloSectionFigures(settled, geometry, options.outDir);
    } catch (const render::RenderError& e) {
      std::cerr << "warning: the settled bed's section figures were not drawn: " << e.what()
                << "\n";
    }
  };
  std::cout << "silo study: " << options.scene.string() << ", " << scene.stages[0].inserts[0].count
            << " particles poured in, then " << options.dischargeTime
            << " s through each orifice\n";
  const SiloStudyResult result = runSiloStudy(scene, study);
  reporter.finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  writeSiloTables(result, options.outDir);
  std::vector<std::filesystem::path> figures = drawSiloFigures(result, options.outDir);
  figures.insert(figures.end(), sections.begin(), sections.end());
  std::vector<std::string> names;
  for (const std::filesystem::path& f : figures) names.push_back(f.filename().string());
  writeTextFile(options.outDir / "report.md",
                siloReport(result, options.scene.filename().string(), seconds, names));
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
