#pragma once
/// The GUI's "export figures": the paper's kinds of figures drawn from the run on screen, with
/// the headless renderer (as `granular paper` draws them).
#include <filesystem>
#include <vector>

#include "sim_runner.hpp"

namespace granular::gui {

/// Writes into `folder` (created if missing): the particles coloured by Σ|F_ij| (as the paper's
/// Figs. 3 and 6) and by their own σ33, with the scene's walls other than infinite planes drawn
/// translucent where the run has them (wall_drawing.hpp), and time plots of the live series:
/// σ33 and σ11, σ22 by Eq. (1) and Eq. (2), the bottom and top wall reactions (these three where
/// the scene has the box's walls), the kinetic energy. Returns the files written. It opens its
/// own headless GL context, which is current per thread: call it from a thread that has no
/// window context current (the GUI runs it on a worker thread). Throws render::RenderError or
/// render::ImageError on failure.
std::vector<std::filesystem::path> exportFigures(const Snapshot& snap,
                                                 const std::filesystem::path& folder);

}  // namespace granular::gui
