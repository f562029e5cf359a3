#pragma once
/// `granular run`: load a scene, run its stages, write the time series, snapshots, final state
/// and a summary.
#include <filesystem>

namespace granular::app {

struct RunOptions {
  std::filesystem::path scene;   ///< the scene file
  std::filesystem::path outDir;  ///< output folder; empty means runs/<scene stem>
  bool quiet = false;            ///< no progress lines
};

/// Runs the scene. Returns the exit status: 0 done, 1 I/O error, 2 invalid scene or
/// configuration. Messages go to stderr; the header and stage results to stdout.
int runCommand(const RunOptions& options);

}  // namespace granular::app
