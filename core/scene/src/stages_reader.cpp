/// readStages: the [[stages]] array, with each stage's wall velocities (stages_reader.hpp), and
/// fileSafeName, the stage's name as output file names carry it.
#include "stages_reader.hpp"

#include <algorithm>
#include <string_view>

#include "exchange_reader.hpp"
#include "scene_schema.hpp"

namespace granular {

namespace {

/// A stage longer than this many steps is a unit slip or a "forever"; it would never end.
constexpr double kMaxStageSteps = 1e12;

std::vector<WallMotion> readWallMotions(const TomlTableReader& stage, const std::string& file,
                                        const BoxSpec& box, const std::vector<Wall>& others,
                                        bool topAvailable) {
  const toml::table* table = stage.subTable("wall_velocity");
  if (!table) return {};
  const TomlTableReader r(*table, stage.keyPath("wall_velocity"), file);
  if (r.has("top") && !topAvailable) {
    r.fail("top",
           "the box has no top wall: add \"top\" to box.walls, or set "
           "place_top_wall_on_surface = true in this or an earlier stage");
  }
  std::vector<std::string_view> walls;
  for (std::size_t f = 0; f < kBoxWallNames.size(); ++f) {
    if (box.walls[f] || (f == 5 && topAvailable)) walls.push_back(kBoxWallNames[f]);
  }
  // A face the box has no wall on is not a typo of another face: say which walls exist.
  for (std::size_t f = 0; f < kBoxWallNames.size(); ++f) {
    if (r.has(kBoxWallNames[f]) &&
        std::find(walls.begin(), walls.end(), kBoxWallNames[f]) == walls.end()) {
      std::string present;
      for (std::string_view w : walls) present += (present.empty() ? "" : ", ") + std::string(w);
      r.fail(kBoxWallNames[f], "the box has no " + std::string(kBoxWallNames[f]) +
                                   " wall (box.walls lists " + present +
                                   "): add it to box.walls to move it");
    }
  }
  for (const Wall& w : others) walls.push_back(w.name);
  r.expectOnly(walls);
  std::vector<WallMotion> motions;
  for (auto&& [key, node] : *table) {
    motions.push_back({std::string(key.str()), r.vec3(key.str(), Range::any())});
  }
  return motions;
}

}  // namespace

std::string fileSafeName(const std::string& name) {
  std::string safe;
  for (char c : name) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '-' || c == '_';
    safe += plain ? c : '_';
  }
  return safe;
}

std::vector<StageSpec> readStages(const TomlTableReader& root, const std::string& file,
                                  const BoxSpec& box, const std::vector<Wall>& walls,
                                  double timeStep) {
  const toml::array* array = root.tableArray("stages");
  if (!array) root.failMissing("stages");
  std::vector<StageSpec> stages;
  std::string topPlacedBy;           // name of the stage that placed the top wall, if any
  std::size_t sources = 0;           // inserts of the stages so far
  std::vector<std::string> removed;  // walls the stages so far took away
  for (std::size_t i = 0; i < array->size(); ++i) {
    const TomlTableReader r(*array->get(i)->as_table(), "stages[" + std::to_string(i) + "]", file);
    r.expectOnly(scene_schema::list(scene_schema::kStage));
    StageSpec s;
    s.name = r.string("name", "stage" + std::to_string(i + 1));
    if (s.name.empty()) r.fail("name", "must not be empty");
    for (const StageSpec& earlier : stages) {
      if (earlier.name == s.name) r.fail("name", "another stage has this name");
      // Output files carry the stage's name with characters outside [A-Za-z0-9_-] as '_'.
      if (fileSafeName(earlier.name) == fileSafeName(s.name)) {
        r.fail("name", "names the same output files as stage '" + earlier.name +
                           "' (both become '" + fileSafeName(s.name) +
                           "' in file names); use letters, digits, '-' and '_' to tell them apart");
      }
    }
    s.end.maxTime = r.number("max_time", Range::above(0));
    if (s.end.maxTime > kMaxStageSteps * timeStep) {
      r.fail("max_time",
             "must be at most 1e12 time steps: " + formatNumber(kMaxStageSteps * timeStep) +
                 " s at simulation.time_step = " + formatNumber(timeStep));
    }
    s.end.kineticEnergyBelow = r.optionalNumber("kinetic_energy_below", Range::above(0));
    s.end.sustainTime = r.number("sustain_time", 0.0, Range::closed(0, s.end.maxTime));
    if (r.has("sustain_time") && !s.end.kineticEnergyBelow) {
      r.fail("sustain_time", "has no effect without kinetic_energy_below");
    }
    s.placeTopWallOnSurface = r.boolean("place_top_wall_on_surface", false);
    if (s.placeTopWallOnSurface && box.walls[5]) {
      r.fail("place_top_wall_on_surface", "the box already has a top wall (box.walls)");
    }
    if (s.placeTopWallOnSurface && !topPlacedBy.empty()) {
      r.fail("place_top_wall_on_surface",
             "the top wall was already placed by stage '" + topPlacedBy + "'");
    }
    if (s.placeTopWallOnSurface) topPlacedBy = s.name;
    s.resetClock = r.boolean("reset_clock", false);
    if (r.has("snapshots")) {
      s.snapshotTimes = r.numbers("snapshots", Range::atLeast(0));
      std::sort(s.snapshotTimes->begin(), s.snapshotTimes->end());
    }
    s.wallMotions = readWallMotions(r, file, box, walls, box.walls[5] || !topPlacedBy.empty());
    readStageExchange(r, file, box, walls, sources, removed, s);
    stages.push_back(std::move(s));
  }
  return stages;
}

}  // namespace granular
