#pragma once
/// `granular paper`: the paper's numerical experiment for μ = 0 and μ = 0.3, from scratch or from
/// the settled checkpoints, with time series, the t = 1 s stress tensors and report.md; and the
/// μ = 0.3 case with a constant tangential stiffness, the report's sensitivity section.
#include <filesystem>

namespace granular::app {

/// Seeds of --sensitivity by default: the paper's and seven more.
inline constexpr int kSensitivitySeeds = 8;

struct PaperOptions {
  std::filesystem::path outDir = "runs/paper";  ///< output folder
  std::filesystem::path scenesDir;              ///< folder of paper-mu0.toml, paper-mu03.toml
  bool fresh = false;                           ///< ignore settled checkpoints
  bool quiet = false;                           ///< no progress lines
  /// Write into an existing folder that holds other files and no case of a paper run.
  bool force = false;
  /// Also run the μ = 0.3 case from `seeds` initial states (the grid's seed) with both tangential
  /// laws, for the report's sensitivity section.
  bool sensitivity = false;
  int seeds = kSensitivitySeeds;
};

/// Exit status as for `granular run`.
int paperCommand(const PaperOptions& options);

}  // namespace granular::app
