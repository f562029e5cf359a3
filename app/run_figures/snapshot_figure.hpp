#pragma once
/// The figures of one snapshot of a `granular run` folder: its particles coloured by Σ|F_ij|
/// with the walls drawn translucent, and the mean pressure on each wall against height.
#include <optional>
#include <string>
#include <vector>

#include "csv_input.hpp"
#include "granular/render/image.hpp"
#include "granular/render/particle_figure.hpp"
#include "snapshot_files.hpp"
#include "wall_cells.hpp"

namespace granular::app {

/// A snapshot's files, read: the particles, and the contacts and walls where the run wrote them.
struct SnapshotData {
  SnapshotFiles files;
  CsvTable particles;
  std::optional<CsvTable> contacts;  ///< with the wall column as text
  std::optional<SnapshotWalls> walls;
  std::string when;  ///< "stage fill, t = 0.5 s (step 1234)"
};

/// Reads the files that exist; IoError naming a file that cannot be read.
SnapshotData readSnapshot(const SnapshotFiles& files);

/// A drawn figure and what it lacks ("in one colour: contacts_fill_100.csv is missing").
struct DrawnFigure {
  render::Image image;
  std::vector<std::string> notes;
};

/// The particles coloured by Σ|F_ij| [N] (force_sums.hpp) inside the scene's box, its walls but
/// the infinite planes drawn translucent. Without the contacts file the particles are one grey
/// and the figure has no colour bar; without the walls file no wall is drawn and the frame is
/// the particles' bounding box.
DrawnFigure particleFigure(render::FigureRenderer& renderer, const SnapshotData& snapshot);

/// The walls that have a pressure profile: all but the infinite planes (whose load is their
/// reaction over an unbounded area).
bool hasShellWalls(const SnapshotData& snapshot);

/// Per wall other than an infinite plane: the mean normal pressure against height
/// (wall_pressure.hpp) in bands two mean particle diameters high. Needs the contacts and the
/// walls.
render::Image pressureFigure(const SnapshotData& snapshot);

}  // namespace granular::app
