#pragma once
/// The snapshots of a `granular run` folder and the files each has: snapshot_<stage>_<step>.csv,
/// contacts_<stage>_<step>.csv and paraview/<stage>_<step>_walls.vtp (run_command.cpp names
/// them), any of the last two possibly missing.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace granular::app {

struct SnapshotFiles {
  std::string name;    ///< "<stage>_<step>", the stage as its file names write it
  std::uint64_t step;  ///< the run's step count at the snapshot
  std::filesystem::path particles, contacts, walls;  ///< full paths; the last two may not exist
};

/// Every snapshot_*.csv of the folder whose name ends in _<step>.csv, by step.
std::vector<SnapshotFiles> listSnapshots(const std::filesystem::path& runDir);

}  // namespace granular::app
