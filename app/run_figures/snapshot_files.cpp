/// snapshot_files.hpp.
#include "snapshot_files.hpp"

#include <algorithm>
#include <cctype>
#include <system_error>

namespace granular::app {

std::vector<SnapshotFiles> listSnapshots(const std::filesystem::path& runDir) {
  std::vector<SnapshotFiles> found;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(runDir, error)) {
    const std::string file = entry.path().filename().string();
    if (!file.starts_with("snapshot_") || !file.ends_with(".csv")) continue;
    const std::string name = file.substr(9, file.size() - 9 - 4);
    // The stage's name may hold underscores; the step is what follows the last one.
    const std::size_t cut = name.rfind('_');
    if (cut == std::string::npos || cut + 1 == name.size() || cut == 0) continue;
    const std::string digits = name.substr(cut + 1);
    if (digits.size() > 19 ||
        !std::all_of(digits.begin(), digits.end(), [](char c) { return std::isdigit(c); })) {
      continue;
    }
    SnapshotFiles s;
    s.name = name;
    s.step = std::stoull(digits);
    s.particles = entry.path();
    s.contacts = runDir / ("contacts_" + name + ".csv");
    s.walls = runDir / "paraview" / (name + "_walls.vtp");
    found.push_back(std::move(s));
  }
  std::sort(found.begin(), found.end(), [](const SnapshotFiles& a, const SnapshotFiles& b) {
    return a.step != b.step ? a.step < b.step : a.name < b.name;
  });
  return found;
}

}  // namespace granular::app
