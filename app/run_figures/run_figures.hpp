#pragma once
/// The figures of a `granular run` folder, drawn from its files alone into RUN_DIR/figures/:
/// the time plots of timeseries.csv (series_figures.hpp), each snapshot's particles coloured by
/// Σ|F_ij| with the walls drawn translucent, and the last snapshot's wall pressures against height
/// (snapshot_figure.hpp).
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace granular::app {

/// Whether `dir` holds a `granular run`: its summary.txt, whose first line starts "scene:", and
/// its timeseries.csv.
bool isRunFolder(const std::filesystem::path& dir);

/// What drawRunFigures drew, what it drew short of something, and what it could not draw.
struct RunFigureSet {
  std::vector<std::filesystem::path> written;  ///< full paths, in the order drawn
  /// "particles_fill_100.png: particles in one colour: contacts_fill_100.csv is missing"
  std::vector<std::string> notes;
  /// "particle figures (no snapshots in this run: the scene's [output] snapshots is empty)"
  std::vector<std::string> missing;
};

/// Draws every figure the folder's files allow, replacing the ones an earlier call drew (their
/// names only: other files in figures/ stay). Throws IoError naming the file (and line) that
/// cannot be read or written, render::RenderError without OpenGL.
RunFigureSet drawRunFigures(const std::filesystem::path& runDir);

/// Says what was drawn ("wrote ..."), what each drawn figure lacks and what was not drawn, one a
/// line.
void printRunFigures(std::ostream& out, const RunFigureSet& set);

/// `granular figures RUN_DIR` for a run folder: draws, prints, and returns 0 when it drew
/// something; 1, with the reason, when it drew nothing or a file could not be read.
int runFiguresCommand(const std::filesystem::path& runDir);

}  // namespace granular::app
