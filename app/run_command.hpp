#pragma once
/// `granular run`: load a scene, run its stages, write the time series, snapshots, final state
/// and a summary.
#include <filesystem>
#include <memory>

#include "granular/communicator.hpp"

namespace granular::app {

struct RunOptions {
  std::filesystem::path scene;   ///< the scene file
  std::filesystem::path outDir;  ///< output folder; empty means runs/<scene stem>
  bool quiet = false;            ///< no progress lines
  /// Wall-clock seconds between checkpoints (<outDir>/checkpoint.bin); 0: none [s].
  double checkpointEvery = 300.0;
  /// Continue from <outDir>/checkpoint.bin when it exists (else start from the beginning).
  bool resume = false;
  /// Start again in an output folder that holds an earlier run: its files are removed first
  /// (without it such a folder is refused, run_folder.hpp).
  bool force = false;
  /// Once the run's files are complete, draw its figures into <outDir>/figures/ (run_figures.hpp).
  bool figures = false;
  /// The processes of a run under mpirun (null: one process alone). The run is then split by
  /// space among them: rank 0 writes every file and prints, each rank steps its share.
  std::shared_ptr<const Communicator> ranks;
};

/// Exit status of a run whose state stopped being finite (NaN or infinity).
inline constexpr int kExitNumericalFailure = 3;

/// Runs the scene. Returns the exit status: 0 done, 1 I/O error, 2 invalid scene or
/// configuration, 3 the state broke (NaN/inf; the last checkpoint is the last good state).
/// Messages go to stderr; the header and stage results to stdout.
///
/// Fault injection for tests: GRANULAR_INJECT_NAN=STEP:PARTICLE sets that particle's velocity to
/// NaN after that step (total step count), as a bug or a cosmic ray would.
int runCommand(const RunOptions& options);

}  // namespace granular::app
