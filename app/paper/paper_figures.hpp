#pragma once
/// The paper's figures, drawn from the files a `granular paper` run folder holds (no simulation):
/// Fig. 2 falling particles, Figs. 3 and 6 settled beds coloured by Σ|F_ij|, Figs. 4 and 7 wall
/// reactions, Figs. 5 and 8 stresses of Eq. (1) and Eq. (2), the settling kinetic energy, and
/// Figs. 9 and 10 of the sensitivity study's constant-k_t bed.
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace granular::app {

struct FigureFile {
  std::string caption;         ///< for report.md
  std::filesystem::path path;  ///< relative to the run folder
};

/// What drawPaperFigures drew, and what it could not draw with the reason.
struct FigureSet {
  std::vector<FigureFile> written;   ///< in the paper's order
  std::vector<std::string> missing;  ///< "fig02_falling_mu0.png (mu0/falling_t1.csv is missing)"
  /// Cells of a line plot's data that are not numbers, each a gap in the figure's line:
  /// "RUN/mu0/compaction_stress.csv line 5, column R33_top_N: nan; left out of
  /// fig04_forces_mu0.png (a gap in its line)"
  std::vector<std::string> gaps;
};

/// Draws into RUN_DIR/figures/ every figure whose data exist (18 for a whole run: 16 of the two
/// cases, Figs. 9 and 10 of the constant-k_t bed); labels each case with the friction its
/// case.txt records. Throws IoError on unreadable data or a failed
/// write, render::RenderError without OpenGL.
FigureSet drawPaperFigures(const std::filesystem::path& runDir);

/// `granular figures RUN_DIR`: re-draws the figures of a run. Exit status 1 when a figure cannot
/// be drawn (every missing input is named) or nothing is there to draw; a cell of a plot's data
/// that is not a number is a warning on stderr naming the file, line and column.
int figuresCommand(const std::filesystem::path& runDir);

}  // namespace granular::app
