/// loadScene: reads and validates a scene file (TOML). Every key is checked for type, finiteness
/// and range; unknown keys are errors. Messages are "file:line:column: key = value: problem".
///
/// Schema (SI units; docs/scenes.md has the long form):
///
// clang-format off
/// key                                 | unit  | range / values               | default
/// ------------------------------------|-------|------------------------------|--------------
/// total_mass                          | kg    | > 0 (scales the density)     | none
/// material.youngs_modulus             | Pa    | (0, 1e12]                    | 0.3e6
/// material.poisson_ratio              | -     | [0, 0.5)                     | 0.30
/// material.shear_modulus              | Pa    | (0, 1e12]                    | 0.11e6
/// material.density                    | kg/m³ | > 0                          | 500
/// material.friction                   | -     | [0, 10]                      | 0
/// material.normal_damping             | 1/s   | >= 0                         | 60
/// material.tangential_damping         | 1/s   | >= 0                         | 10
/// material.normal_law                 | -     | "hooke" | "hertz"            | "hooke"
/// simulation.gravity                  | m/s²  | 3 finite numbers             | [0, 0, -9.81]
/// simulation.integrator               | -     | "gear5" | "verlet"           | "gear5"
/// simulation.time_step                | s     | > 0                          | required
/// simulation.skin                     | m     | >= 0 (0 = automatic)         | 0
/// simulation.impact_speed             | m/s   | > 0                          | computed
/// box.min, box.max                    | m     | 3 finite numbers, max > min  | required
/// box.walls                           | -     | x- x+ y- y+ bottom top       | all but top
/// particles[i].type                   | -     | "grid" | "csv"               | required
/// particles[i].origin        (grid)   | m     | 3 finite numbers             | required
/// particles[i].cell_size     (grid)   | m     | > 0                          | required
/// particles[i].cells         (grid)   | -     | 3 integers in [1, 1e5]       | required
/// particles[i].count         (grid)   | -     | [1, nx·ny·nz], <= 1e8        | nx·ny·nz
/// particles[i].radius_min    (grid)   | m     | > 0                          | required
/// particles[i].radius_max    (grid)   | m     | [radius_min, cell_size/2]    | required
/// particles[i].speed_max     (grid)   | m/s   | >= 0                         | 0
/// particles[i].seed          (grid)   | -     | integer >= 0                 | 1
/// particles[i].file          (csv)    | -     | path from the scene's folder | required
/// stages[i].name                      | -     | non-empty, unique            | "stage<i+1>"
/// stages[i].max_time                  | s     | > 0                          | required
/// stages[i].kinetic_energy_below      | J     | > 0                          | none
/// stages[i].sustain_time              | s     | [0, max_time]                | 0
/// stages[i].place_top_wall_on_surface | -     | boolean                      | false
/// stages[i].reset_clock               | -     | boolean                      | false
/// stages[i].wall_velocity.<wall>      | m/s   | 3 finite numbers             | at rest
/// output.interval                     | s     | > 0                          | 0.01
/// output.snapshots                    | s     | numbers >= 0 (stage clock)   | []
// clang-format on
///
/// The default impact_speed (used by the Hertz time-step check only) is the largest initial
/// particle speed plus the free-fall speed sqrt(2|g|h), h being the height of the highest
/// particle top above the box floor; 1 m/s if that comes out as 0 (no gravity, no motion).
///
/// Sections: 1. material; 2. simulation; 3. box; 4. particles; 5. stages; 6. output; 7. loadScene.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "granular/error.hpp"
#include "granular/scene.hpp"
#include "particle_csv.hpp"
#include "toml_table_reader.hpp"

namespace granular {

namespace {

constexpr double kMaxModulus = 1e12;  // [Pa]; catches a unit slip (MPa vs Pa ×1e6)
constexpr std::int64_t kMaxCellsPerAxis = 100000;
constexpr std::int64_t kMaxParticles = 100000000;
constexpr std::int64_t kMaxInt = std::numeric_limits<std::int64_t>::max();

std::vector<std::string_view> boxWallNames() {
  return {kBoxWallNames.begin(), kBoxWallNames.end()};
}

/// What the particle sources tell about the expected impact speed.
struct MotionBound {
  double highestTop = -std::numeric_limits<double>::infinity();  ///< max z + r [m]
  double fastest = 0.0;                                          ///< max initial speed [m/s]
};

// 1. Material -------------------------------------------------------------------------------------

Material readMaterial(const TomlTableReader& root, const std::string& file) {
  Material m;
  const toml::table* table = root.subTable("material");
  if (!table) return m;
  const TomlTableReader r(*table, "material", file,
                          {"youngs_modulus", "poisson_ratio", "shear_modulus", "density",
                           "friction", "normal_damping", "tangential_damping", "normal_law"});
  m.youngModulus = r.number("youngs_modulus", m.youngModulus, Range::aboveUpTo(0, kMaxModulus));
  m.poissonRatio = r.number("poisson_ratio", m.poissonRatio, Range::halfOpen(0, 0.5));
  m.shearModulus = r.number("shear_modulus", m.shearModulus, Range::aboveUpTo(0, kMaxModulus));
  m.density = r.number("density", m.density, Range::above(0));
  m.friction = r.number("friction", m.friction, Range::closed(0, 10));
  m.normalDamping = r.number("normal_damping", m.normalDamping, Range::atLeast(0));
  m.tangentialDamping = r.number("tangential_damping", m.tangentialDamping, Range::atLeast(0));
  const std::string law = r.choice("normal_law", "hooke", {"hooke", "hertz"});
  m.normalLaw = law == "hertz" ? NormalLaw::Hertz : NormalLaw::Hooke;
  return m;
}

// 2. Simulation -----------------------------------------------------------------------------------

/// Reads [simulation]; returns true when impact_speed was given explicitly.
bool readSimulation(const TomlTableReader& root, const std::string& file,
                    SimulationConfig& config) {
  const toml::table* table = root.subTable("simulation");
  if (!table) root.failMissing("simulation");
  const TomlTableReader r(*table, "simulation", file,
                          {"gravity", "integrator", "time_step", "skin", "impact_speed"});
  config.gravity = r.vec3("gravity", config.gravity, Range::any());
  const std::string integrator = r.choice("integrator", "gear5", {"gear5", "verlet"});
  config.integrator = integrator == "verlet" ? Integrator::VelocityVerlet : Integrator::Gear5;
  config.timeStep = r.number("time_step", Range::above(0));
  config.skin = r.number("skin", 0.0, Range::atLeast(0));
  config.impactSpeed = r.number("impact_speed", config.impactSpeed, Range::above(0));
  return r.has("impact_speed");
}

// 3. Box ------------------------------------------------------------------------------------------

BoxSpec readBox(const TomlTableReader& root, const std::string& file) {
  const toml::table* table = root.subTable("box");
  if (!table) root.failMissing("box");
  const TomlTableReader r(*table, "box", file, {"min", "max", "walls"});
  BoxSpec box;
  box.min = r.vec3("min", Range::any());
  box.max = r.vec3("max", Range::any());
  if ((box.max.array() <= box.min.array()).any()) {
    r.fail("max", "must exceed box.min in every component");
  }
  const std::vector<std::string> names = r.strings("walls", {"x-", "x+", "y-", "y+", "bottom"});
  box.walls.fill(false);
  for (const std::string& name : names) {
    const auto it = std::find(kBoxWallNames.begin(), kBoxWallNames.end(), name);
    if (it == kBoxWallNames.end()) {
      const std::string suggestion = nearestName(name, boxWallNames());
      r.fail("walls", "unknown wall '" + name + "'" +
                          (suggestion.empty() ? "" : "; did you mean '" + suggestion + "'?") +
                          " (walls are x-, x+, y-, y+, bottom, top)");
    }
    const std::size_t index = std::size_t(it - kBoxWallNames.begin());
    if (box.walls[index]) r.fail("walls", "wall '" + name + "' is listed twice");
    box.walls[index] = true;
  }
  return box;
}

// 4. Particles ------------------------------------------------------------------------------------

GridGenerator readGrid(const TomlTableReader& r, MotionBound& bound) {
  r.expectOnly({"type", "origin", "cell_size", "cells", "count", "radius_min", "radius_max",
                "speed_max", "seed"});
  GridGenerator g;
  g.origin = r.vec3("origin", Range::any());
  g.cellSize = r.number("cell_size", Range::above(0));
  const auto cells = r.integers3("cells", 1, kMaxCellsPerAxis);
  const std::int64_t capacity = cells[0] * cells[1] * cells[2];  // <= 1e15: no overflow
  const std::int64_t count = r.integer("count", capacity, 1, capacity);
  if (count > kMaxParticles) {
    r.fail(r.has("count") ? "count" : "cells", "more than 1e8 particles");
  }
  g.cells = {int(cells[0]), int(cells[1]), int(cells[2])};
  g.count = std::size_t(count);
  g.radiusMin = r.number("radius_min", Range::above(0));
  g.radiusMax = r.number("radius_max", Range::above(0));
  if (g.radiusMax < g.radiusMin) {
    r.fail("radius_max", "must be >= radius_min = " + formatNumber(g.radiusMin));
  }
  if (2.0 * g.radiusMax > g.cellSize) {
    r.fail("radius_max", "must be <= cell_size/2 = " + formatNumber(g.cellSize / 2) +
                             " so that neighbouring grid particles cannot overlap");
  }
  g.speedMax = r.number("speed_max", 0.0, Range::atLeast(0));
  g.seed = std::uint64_t(r.integer("seed", 1, 0, kMaxInt));

  // Highest particle top: the last filled layer (z fastest-varying last) plus the largest radius.
  const std::int64_t layers = (count + cells[0] * cells[1] - 1) / (cells[0] * cells[1]);
  bound.highestTop =
      std::max(bound.highestTop, g.origin.z() + (double(layers) - 0.5) * g.cellSize + g.radiusMax);
  bound.fastest = std::max(bound.fastest, g.speedMax);
  return g;
}

CsvGenerator readCsv(const TomlTableReader& r, const std::filesystem::path& folder,
                     MotionBound& bound) {
  r.expectOnly({"type", "file"});
  const std::string name = r.string("file");
  if (name.empty()) r.fail("file", "must name a CSV file");
  CsvGenerator g;
  g.path = std::filesystem::path(name).is_absolute() ? std::filesystem::path(name) : folder / name;
  // Read it now, so a bad row is reported against the scene key that names the file.
  try {
    for (const CsvParticle& p : readParticleCsv(g.path)) {
      bound.highestTop = std::max(bound.highestTop, p.position.z() + p.radius);
      bound.fastest = std::max(bound.fastest, p.velocity.norm());
    }
  } catch (const ConfigError& e) {
    r.fail("file", e.what());
  }
  return g;
}

std::vector<Generator> readParticles(const TomlTableReader& root, const std::string& file,
                                     const std::filesystem::path& folder, MotionBound& bound) {
  const toml::array* array = root.tableArray("particles");
  if (!array) root.failMissing("particles");
  std::vector<Generator> generators;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const TomlTableReader r(*array->get(i)->as_table(), "particles[" + std::to_string(i) + "]",
                            file);
    // Keys of either type first, so that a misspelt "type" gets a suggestion, not "missing".
    r.expectOnly({"type", "origin", "cell_size", "cells", "count", "radius_min", "radius_max",
                  "speed_max", "seed", "file"});
    const std::string type = r.choice("type", "", {"grid", "csv"});
    if (type == "grid") {
      generators.emplace_back(readGrid(r, bound));
    } else {
      generators.emplace_back(readCsv(r, folder, bound));
    }
  }
  return generators;
}

// 5. Stages ---------------------------------------------------------------------------------------

std::vector<WallMotion> readWallMotions(const TomlTableReader& stage, const std::string& file,
                                        const BoxSpec& box, bool topAvailable) {
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
  r.expectOnly(walls);
  std::vector<WallMotion> motions;
  for (auto&& [key, node] : *table) {
    motions.push_back({std::string(key.str()), r.vec3(key.str(), Range::any())});
  }
  return motions;
}

std::vector<StageSpec> readStages(const TomlTableReader& root, const std::string& file,
                                  const BoxSpec& box) {
  const toml::array* array = root.tableArray("stages");
  if (!array) root.failMissing("stages");
  std::vector<StageSpec> stages;
  std::string topPlacedBy;  // name of the stage that placed the top wall, if any
  for (std::size_t i = 0; i < array->size(); ++i) {
    const TomlTableReader r(*array->get(i)->as_table(), "stages[" + std::to_string(i) + "]", file,
                            {"name", "max_time", "kinetic_energy_below", "sustain_time",
                             "place_top_wall_on_surface", "reset_clock", "wall_velocity"});
    StageSpec s;
    s.name = r.string("name", "stage" + std::to_string(i + 1));
    if (s.name.empty()) r.fail("name", "must not be empty");
    for (const StageSpec& earlier : stages) {
      if (earlier.name == s.name) r.fail("name", "another stage has this name");
    }
    s.end.maxTime = r.number("max_time", Range::above(0));
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
    s.wallMotions = readWallMotions(r, file, box, box.walls[5] || !topPlacedBy.empty());
    stages.push_back(std::move(s));
  }
  return stages;
}

// 6. Output ---------------------------------------------------------------------------------------

OutputSpec readOutput(const TomlTableReader& root, const std::string& file) {
  OutputSpec output;
  const toml::table* table = root.subTable("output");
  if (!table) return output;
  const TomlTableReader r(*table, "output", file, {"interval", "snapshots"});
  output.interval = r.number("interval", output.interval, Range::above(0));
  output.snapshotTimes = r.numbers("snapshots", Range::atLeast(0));
  std::sort(output.snapshotTimes.begin(), output.snapshotTimes.end());
  return output;
}

/// Largest initial speed plus the free-fall speed from the highest particle top to the floor.
double defaultImpactSpeed(const MotionBound& bound, const BoxSpec& box, const Vec3& gravity) {
  const double height = std::max(0.0, bound.highestTop - box.min.z());
  const double speed = bound.fastest + std::sqrt(2.0 * gravity.norm() * height);
  return speed > 0.0 ? speed : 1.0;
}

}  // namespace

// 7. loadScene ------------------------------------------------------------------------------------

Scene loadScene(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) {
    throw SceneError(name + ": cannot open scene file");
  }
  toml::table document;
  try {
    document = toml::parse_file(name);
  } catch (const toml::parse_error& e) {
    throw SceneError(locationPrefix(name, e.source()) + std::string(e.description()));
  }

  const TomlTableReader root(
      document, "", name,
      {"material", "simulation", "box", "particles", "total_mass", "stages", "output"});
  Scene scene;
  scene.sourceFile = file;
  scene.simulation.material = readMaterial(root, name);
  const bool impactSpeedGiven = readSimulation(root, name, scene.simulation);
  scene.box = readBox(root, name);
  MotionBound bound;
  scene.generators = readParticles(root, name, file.parent_path(), bound);
  scene.totalMass = root.optionalNumber("total_mass", Range::above(0));
  scene.stages = readStages(root, name, scene.box);
  scene.output = readOutput(root, name);
  if (!impactSpeedGiven) {
    scene.simulation.impactSpeed = defaultImpactSpeed(bound, scene.box, scene.simulation.gravity);
  }
  return scene;
}

}  // namespace granular
