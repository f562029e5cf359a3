#pragma once
/// The paper's figures, drawn from the files a `granular paper` run folder holds (no simulation):
/// Fig. 2 falling particles, Figs. 3 and 6 settled beds coloured by Σ|F_ij|, Figs. 4 and 7 wall
/// reactions, Figs. 5 and 8 stresses of Eq. (1) and Eq. (2), and the settling kinetic energy.
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace granular::app {

struct FigureFile {
  std::string caption;         ///< for report.md
  std::filesystem::path path;  ///< relative to the run folder
};

/// Draws into RUN_DIR/figures/ every figure whose data exist; returns what it wrote, in the
/// paper's order. Throws IoError on unreadable data, render::RenderError without OpenGL.
std::vector<FigureFile> drawPaperFigures(const std::filesystem::path& runDir);

/// `granular figures RUN_DIR`: re-draws the figures of a run. Exit status as `granular run`.
int figuresCommand(const std::filesystem::path& runDir);

}  // namespace granular::app
