/// run_figures.hpp.
#include "run_figures.hpp"

#include <fstream>
#include <iostream>
#include <optional>
#include <system_error>

#include "granular/error.hpp"
#include "granular/render/particle_figure.hpp"
#include "run_header.hpp"
#include "series_figures.hpp"
#include "snapshot_figure.hpp"
#include "snapshot_files.hpp"
#include "stop_signals.hpp"

namespace granular::app {

namespace {

constexpr double kDpi = 150.0;  // as the paper's figures

/// The names drawRunFigures writes, so that it replaces its own earlier figures and no others.
bool isRunFigure(const std::string& name) {
  if (!name.ends_with(".png")) return false;
  for (const char* fixed :
       {"energies.png", "kinetic_energy.png", "wall_reactions.png", "contacts.png", "mass.png"}) {
    if (name == fixed) return true;
  }
  return name.starts_with("particles_") || name.starts_with("wall_pressure_");
}

void removeEarlierFigures(const std::filesystem::path& folder) {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    if (!entry.is_regular_file(error) || !isRunFigure(entry.path().filename().string())) continue;
    std::filesystem::remove(entry.path(), error);
    if (error) {
      throw IoError(entry.path().string() +
                    ": cannot remove the earlier figure: " + error.message());
    }
  }
}

}  // namespace

bool isRunFolder(const std::filesystem::path& dir) {
  std::ifstream summary(dir / "summary.txt");
  std::string first;
  return summary && std::getline(summary, first) && first.starts_with("scene:") &&
         std::filesystem::is_regular_file(dir / "timeseries.csv");
}

RunFigureSet drawRunFigures(const std::filesystem::path& runDir) {
  RunFigureSet set;
  const std::filesystem::path out = runDir / "figures";
  createOutputFolder(out);
  removeEarlierFigures(out);
  auto save = [&](const render::Image& image, const std::string& name) {
    render::writePng(image, out / name, kDpi);
    set.written.push_back(out / name);
  };

  const RunSeries series = readRunSeries(runDir / "timeseries.csv");
  if (series.table.rows() == 0) {
    set.missing.push_back("time plots (timeseries.csv has no rows)");
  } else {
    stopIfSignalled("the run's figures not drawn");
    save(energyFigure(series), "energies.png");
    if (auto image = kineticFigure(series)) {
      save(*image, "kinetic_energy.png");
    } else {
      set.missing.push_back("kinetic_energy.png (the kinetic energy is 0 throughout)");
    }
    if (auto image = reactionFigure(series)) {
      save(*image, "wall_reactions.png");
    } else {
      set.missing.push_back("wall_reactions.png (the scene has no walls)");
    }
    save(contactFigure(series), "contacts.png");
    if (auto image = massFigure(series)) save(*image, "mass.png");
  }

  const std::vector<SnapshotFiles> snapshots = listSnapshots(runDir);
  if (snapshots.empty()) {
    set.missing.push_back(
        "particle figures and wall pressures (no snapshots in this run: the scene's [output] "
        "snapshots lists none)");
    return set;
  }
  std::optional<render::FigureRenderer> renderer;
  std::optional<SnapshotData> last;  // the last snapshot that has walls and contacts
  for (const SnapshotFiles& files : snapshots) {
    stopIfSignalled("the run's figures from particles_" + files.name + ".png on not drawn");
    SnapshotData data = readSnapshot(files);
    if (!renderer) renderer.emplace();
    const std::string name = "particles_" + files.name + ".png";
    const DrawnFigure figure = particleFigure(*renderer, data);
    save(figure.image, name);
    for (const std::string& note : figure.notes) set.notes.push_back(name + ": " + note);
    if (data.walls && data.contacts) last = std::move(data);
  }
  if (!last) {
    set.missing.push_back(
        "wall pressures (no snapshot has both its contacts_*.csv and paraview/*_walls.vtp)");
  } else if (!hasShellWalls(*last)) {
    set.missing.push_back(
        "wall pressures (the scene has no walls but infinite planes, whose reactions "
        "wall_reactions.png shows)");
  } else {
    save(pressureFigure(*last), "wall_pressure_" + last->files.name + ".png");
  }
  return set;
}

void printRunFigures(std::ostream& out, const RunFigureSet& set) {
  for (const std::filesystem::path& file : set.written) out << "wrote " << file.string() << "\n";
  for (const std::string& note : set.notes) out << "note: " << note << "\n";
  for (const std::string& missing : set.missing) out << "not drawn: " << missing << "\n";
}

int runFiguresCommand(const std::filesystem::path& runDir) {
  return withErrorMapping([&] {
    catchStopSignals();
    const RunFigureSet set = drawRunFigures(runDir);
    printRunFigures(std::cout, set);
    if (set.written.empty()) {
      std::string why;
      for (const std::string& m : set.missing) why += (why.empty() ? "" : "; ") + m;
      throw IoError(runDir.string() + ": nothing to draw: " + why);
    }
    return 0;
  });
}

}  // namespace granular::app
