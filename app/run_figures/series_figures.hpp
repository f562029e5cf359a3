#pragma once
/// The time plots of a `granular run` folder, from its timeseries.csv (csv_output.hpp): the
/// energy ledger, the kinetic energy on a log scale, the walls' vertical reactions and the
/// contact counts, against time, with the starts of the later stages marked.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "csv_input.hpp"
#include "granular/render/image.hpp"

namespace granular::app {

/// timeseries.csv read for plotting.
struct RunSeries {
  CsvTable table;
  /// Each row's time since the run began [s]: time_s, with the clock of a stage that resets it
  /// (reset_clock) continued from the stage before.
  std::vector<double> time;
  bool clockJoined = false;  ///< some stage reset its clock: `time` is not time_s
  struct StageStart {
    std::string stage;
    double time = 0;  ///< [s], on `time`'s clock
  };
  std::vector<StageStart> stageStarts;  ///< every stage after the first
};

/// Reads it; IoError naming the file (and the line) when it is not a time series.
RunSeries readRunSeries(const std::filesystem::path& file);

/// Every *_J column: kinetic energies, the contact laws' stored and dissipated energies, the
/// work of gravity and of the walls, the total.
render::Image energyFigure(const RunSeries& series);
/// kinetic_translational_J + kinetic_rotational_J on a log scale; nullopt when no row is > 0.
std::optional<render::Image> kineticFigure(const RunSeries& series);
/// The z component of every reaction_<wall>_z_N column; nullopt when the run has no walls.
std::optional<render::Image> reactionFigure(const RunSeries& series);
/// Every contacts_* column.
render::Image contactFigure(const RunSeries& series);
/// The masses held, inserted and discharged (a scene whose stages insert or remove
/// particles); nullopt when the series has no such columns.
std::optional<render::Image> massFigure(const RunSeries& series);

}  // namespace granular::app
