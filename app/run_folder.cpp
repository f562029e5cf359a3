/// A run's output folder (run_folder.hpp).
#include "run_folder.hpp"

#include <algorithm>
#include <string>
#include <system_error>

#include "granular/error.hpp"

namespace granular::app {

namespace {

/// Whether a name in a run folder is one `granular run` writes (or its temporary, *.tmp).
bool isRunFile(const std::string& name) {
  std::string base = name;
  if (base.ends_with(".tmp")) base.resize(base.size() - 4);
  for (const char* fixed : {"timeseries.csv", "final_state.csv", "summary.txt", "checkpoint.bin",
                            "particles.pvd", "contacts.pvd", "walls.pvd"}) {
    if (base == fixed) return true;
  }
  for (const char* prefix : {"failed_state", "snapshot_", "contacts_"}) {
    if (base.starts_with(prefix) && base.ends_with(".csv")) return true;
  }
  return false;
}

/// Whether the paraview folder holds a snapshot's file (<stage>_<step>_<kind>.vtp).
bool holdsParaviewFiles(const std::filesystem::path& folder) {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file(error)) continue;
    for (const char* kind : {"_particles.vtp", "_contacts.vtp", "_walls.vtp"}) {
      if (name.ends_with(kind)) return true;
    }
  }
  return false;
}

}  // namespace

std::vector<std::filesystem::path> earlierRunFiles(const std::filesystem::path& outDir) {
  std::vector<std::filesystem::path> found;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(outDir, error)) {
    const std::string name = entry.path().filename().string();
    if (isRunFile(name) || (name == "paraview" && holdsParaviewFiles(entry.path()))) {
      found.push_back(entry.path());
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

void refuseEarlierRun(const std::filesystem::path& outDir, bool resume) {
  const std::vector<std::filesystem::path> files = earlierRunFiles(outDir);
  if (files.empty()) return;
  std::string names;
  for (std::size_t k = 0; k < files.size() && k < 3; ++k) {
    names += (k ? ", " : "") + files[k].filename().string();
  }
  if (files.size() > 3) names += " and " + std::to_string(files.size() - 3) + " more";
  throw ConfigError(outDir.string() + " holds an earlier run (" + names + ")" +
                    (resume ? " but no checkpoint.bin to resume from" : "") +
                    ": a new run would mix its files with those; " +
                    (resume ? std::string() : "add --resume to continue that run, ") +
                    "add --force to start again there (the earlier run's files are removed), or "
                    "choose another --out");
}

void removeEarlierRun(const std::filesystem::path& outDir) {
  for (const std::filesystem::path& file : earlierRunFiles(outDir)) {
    std::error_code error;
    std::filesystem::remove_all(file, error);
    if (error) {
      throw IoError(file.string() + ": cannot remove the earlier run's file: " + error.message());
    }
  }
}

}  // namespace granular::app
