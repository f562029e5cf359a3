#pragma once
/// The files `granular run` writes into its output folder, recognised by their names, so that a
/// new run never mixes its files with an earlier run's: a fresh run into a folder that holds
/// them is refused (or, with --force, starts clean), and a resumed run continues its own.
#include <filesystem>
#include <vector>

namespace granular::app {

/// The files and folders of an earlier run in `outDir` (timeseries.csv, final_state.csv,
/// summary.txt, checkpoint.bin, failed_state*.csv, snapshot_*.csv, contacts_*.csv, *.pvd, the
/// paraview folder), in name order; empty when there are none or `outDir` does not exist.
/// Other files are not a run's and are left alone.
std::vector<std::filesystem::path> earlierRunFiles(const std::filesystem::path& outDir);

/// Throws ConfigError when `outDir` holds an earlier run's files, naming the folder, a few of
/// the files and the ways on: --resume, --force, another --out. `resume` says whether the run
/// was asked to resume (and found no checkpoint to resume from).
void refuseEarlierRun(const std::filesystem::path& outDir, bool resume);

/// Removes the earlier run's files (earlierRunFiles) from `outDir`; IoError naming the file
/// that cannot be removed.
void removeEarlierRun(const std::filesystem::path& outDir);

}  // namespace granular::app
