#pragma once
/// `granular calibrate-box`: settles a scene's first stage in square boxes of several sides and
/// finds the side whose settled height is the target (docs/box-calibration.md: the paper gives the
/// frictionless settled height, 1.087 m, not the box).
#include <filesystem>
#include <vector>

namespace granular::app {

struct CalibrateOptions {
  std::filesystem::path scene;   ///< scene whose first stage settles the bed
  std::vector<double> sides;     ///< box sides to try [m]
  double targetHeight = 1.087;   ///< [m]
  std::filesystem::path report;  ///< markdown table to write (empty: stdout only)
  bool quiet = false;
};

int calibrateCommand(const CalibrateOptions& options);

}  // namespace granular::app
