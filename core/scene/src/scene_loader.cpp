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
/// material.density                    | kg/m³ | (0, 1e12]                    | 500
/// material.friction                   | -     | [0, 10]                      | 0
/// material.normal_damping             | 1/s   | >= 0                         | 60
/// material.tangential_damping         | 1/s   | >= 0; μ > 0: <= z/(21 Δt)    | 10
/// material.normal_law                 | -     | "hooke" | "hertz"            | "hooke"
/// material.tangential_law             | -     | "mindlin" | "constant"        | "mindlin"
/// material.tangential_stiffness       | N/m   | [0, 1e12]; constant: > 0     | 0
/// material.no_pull                    | -     | boolean                      | true
/// simulation.gravity                  | m/s²  | 3 finite numbers             | [0, 0, -9.81]
/// simulation.integrator               | -     | "gear5" | "verlet"           | "gear5"
/// simulation.time_step                | s     | > 0, or "auto"               | required
/// simulation.step_safety    (auto)    | -     | (0, 1]                       | 0.9
/// simulation.contact_resolution(auto) | -     | >= 1 steps per t_c           | 10
/// simulation.on_unstable    (fixed)   | -     | "stop" | "warn"              | "stop"
/// simulation.skin                     | m     | >= 0 (0 = automatic)         | 0
/// simulation.impact_speed             | m/s   | > 0                          | computed
/// box.min, box.max                    | m     | 3 finite numbers, max > min  | required
/// box.walls                           | -     | x- x+ y- y+ bottom top       | all but top
/// particles[i].type                   | -     | "grid" | "csv" | "state"     | required
/// particles[i].origin        (grid)   | m     | 3 finite numbers             | required
/// particles[i].cell_size     (grid)   | m     | > 0                          | required
/// particles[i].cells         (grid)   | -     | 3 integers in [1, 1e5]       | required
/// particles[i].count         (grid)   | -     | [1, nx·ny·nz], <= 1e8        | nx·ny·nz
/// particles[i].radius_min    (grid)   | m     | > 0                          | required
/// particles[i].radius_max    (grid)   | m     | [radius_min, cell_size/2]    | required
/// particles[i].speed_max     (grid)   | m/s   | >= 0                         | 0
/// particles[i].seed          (grid)   | -     | integer >= 0                 | 1
/// particles[i].file    (csv, state)   | -     | path from the scene's folder | required
/// stages[i].name                      | -     | non-empty, unique            | "stage<i+1>"
/// stages[i].max_time                  | s     | > 0, at most 1e12 time steps | required
/// stages[i].kinetic_energy_below      | J     | > 0                          | none
/// stages[i].sustain_time              | s     | [0, max_time]                | 0
/// stages[i].place_top_wall_on_surface | -     | boolean                      | false
/// stages[i].reset_clock               | -     | boolean                      | false
/// stages[i].wall_velocity.<wall>      | m/s   | 3 finite numbers             | at rest
/// output.interval                     | s     | > 0                          | 0.01
/// output.snapshots                    | s     | numbers >= 0 (stage clock)   | []
/// output.energy_drift_limit           | -     | > 0 (fraction of work done)  | 0.05
/// output.on_failed_check              | -     | "warn" | "stop"              | "warn"
// clang-format on
///
/// The default impact_speed (used by the Hertz time-step check only) is the largest approach
/// speed: twice the largest particle speed, which is the largest initial speed plus the
/// free-fall speed sqrt(2|g|h), h being the height of the highest particle top above the box
/// floor, plus twice the fastest wall of any stage; 1 m/s if that comes out as 0 (no gravity,
/// no motion).
///
/// Particles are checked as the builder will place them: each must lie inside the box, the rows
/// of a CSV file must not overlap. A fixed time step of a scene whose particles all come from
/// grids (which start apart: no contact) must be below the engine's limit for a scene without
/// contacts (maxStableStep: a fraction of the stiffest contact's duration that depends on the
/// integrator) and, with friction, γt at most maxTangentialDamping: z/(21 Δt), z = 0.163
/// (gear5) or 1 (verlet). A scene read from CSV files may start packed: the engine checks its
/// step against the contact network when it is built (buildSimulation names the key then).
/// The loader does these checks so that the message names the file, the key and the CSV line; the
/// builder and the engine check again.
///
/// Sections: 1. material; 2. simulation; 3. box; 4. particles; 5. stages; 6. output;
/// 7. time step; 8. loadScene.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "granular/network_step.hpp"
#include "granular/scene.hpp"
#include "grid_sampling.hpp"
#include "material_reader.hpp"
#include "particle_csv.hpp"
#include "scene_schema.hpp"
#include "toml_table_reader.hpp"

namespace granular {

namespace {

constexpr std::int64_t kMaxCellsPerAxis = 100000;
constexpr std::int64_t kMaxParticles = 100000000;
constexpr std::int64_t kMaxInt = std::numeric_limits<std::int64_t>::max();
/// A stage longer than this many steps is a unit slip or a "forever"; it would never end.
constexpr double kMaxStageSteps = 1e12;
/// A scene file is a few hundred bytes; anything this large is the wrong file.
constexpr std::uintmax_t kMaxSceneBytes = 16 << 20;

std::vector<std::string_view> boxWallNames() {
  return {kBoxWallNames.begin(), kBoxWallNames.end()};
}

/// What the particle sources tell about the expected impact speed and the time-step limit.
struct MotionBound {
  double highestTop = -std::numeric_limits<double>::infinity();     ///< max z + r [m]
  double fastest = 0.0;                                             ///< max initial speed [m/s]
  double smallestRadius = std::numeric_limits<double>::infinity();  ///< [m]
  double largestRadius = 0.0;                                       ///< [m]
  double volume = 0.0;  ///< Σ (4/3)π R³ in particle order, as the builder sums it [m³]
  void add(double radius) {
    smallestRadius = std::min(smallestRadius, radius);
    largestRadius = std::max(largestRadius, radius);
    volume += 4.0 / 3.0 * std::numbers::pi * std::pow(radius, 3);
  }
};

std::string formatPoint(const Vec3& x) {
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "(" + std::string + ...
  std::string out = "(";
  out += formatNumber(x.x());
  out += ", ";
  out += formatNumber(x.y());
  out += ", ";
  out += formatNumber(x.z());
  out += ')';
  return out;
}

/// "" if a sphere at `centre` lies inside the box, else which face it crosses. The x and y faces
/// and the floor always bound it; the top only when it is a wall (particles may start above an
/// open box). The same rule as the builder's.
std::string boxCrossing(const Vec3& centre, double radius, const BoxSpec& box,
                        bool savedState = false) {
  // A saved state's particle may press into a wall, as in the settled bed it was saved from.
  const double reach = savedState ? 0.0 : radius;
  for (std::size_t face = 0; face < kBoxWallNames.size(); ++face) {
    if (face == 5 && !box.walls[5]) continue;
    const int axis = int(face / 2);
    const bool lower = face % 2 == 0;
    const double x = centre[axis];
    if (lower ? x - reach < box.min[axis] : x + reach > box.max[axis]) {
      return std::string("is outside the box: ") +
             (savedState ? "its centre is beyond" : "crosses") + " the box face " +
             kBoxWallNames[face] + " at " + "xyz"[axis] + " = " +
             formatNumber(lower ? box.min[axis] : box.max[axis]) + " m";
    }
  }
  return {};
}

// 1. Material -------------------------------------------------------------------------------------

}  // namespace

Material readMaterial(const TomlTableReader& root, const std::string& file,
                      std::span<const ParameterSpec> table) {
  Material m;
  const toml::table* section = root.subTable("material");
  if (!section) return m;
  const TomlTableReader r(*section, "material", file);
  std::vector<std::string_view> keys;
  for (const ParameterSpec& p : table) keys.push_back(p.key);
  r.expectOnly(keys);
  for (const ParameterSpec& p : table) {
    switch (p.kind) {
      case ParameterKind::Number:
        p.set(m, r.number(p.key, p.get(m), p.range));
        break;
      case ParameterKind::Choice: {
        const std::size_t now = static_cast<std::size_t>(p.get(m));
        const std::string name = r.choice(
            p.key, p.names[now], std::vector<std::string_view>(p.names.begin(), p.names.end()));
        p.set(m, double(std::find(p.names.begin(), p.names.end(), name) - p.names.begin()));
        break;
      }
      case ParameterKind::Flag:
        p.set(m, r.boolean(p.key, p.get(m) != 0.0) ? 1.0 : 0.0);
        break;
    }
  }
  const RuleProblem rule = materialRuleProblem(m);  // here, so that the message has a line
  if (!rule.key.empty()) r.fail(rule.key, std::string(rule.requirement));
  // A key the other values leave without effect is refused, as [simulation] refuses
  // step_safety beside a fixed step: the user believes it acts.
  for (const IdleParameter& idle : idleParameters(m)) {
    if (r.has(idle.key)) r.fail(idle.key, std::string(idle.reason));
  }
  return m;
}

namespace {

// 2. Simulation -----------------------------------------------------------------------------------

/// Reads [simulation]; returns true when impact_speed was given explicitly.
bool readSimulation(const TomlTableReader& root, const std::string& file, Scene& scene) {
  SimulationConfig& config = scene.simulation;
  const toml::table* table = root.subTable("simulation");
  if (!table) root.failMissing("simulation");
  const TomlTableReader r(*table, "simulation", file);
  r.expectOnly(scene_schema::list(scene_schema::kSimulation));
  config.gravity = r.vec3("gravity", config.gravity, Range::any());
  const std::string integrator = r.choice("integrator", "gear5", {"gear5", "verlet"});
  config.integrator = integrator == "verlet" ? Integrator::VelocityVerlet : Integrator::Gear5;
  const toml::node* step = table->get("time_step");
  if (step && step->is_string()) {
    r.choice("time_step", "", {"auto"});
    config.step.automatic = true;
    config.timeStep = 1.0;  // replaced by the engine's first choice (checkTimeStep: the floor)
  } else {
    config.timeStep = r.number("time_step", Range::above(0));
  }
  scene.keyLocations["simulation.time_step"] = r.messagePrefix("time_step");
  config.step.safety = r.number("step_safety", config.step.safety, Range::aboveUpTo(0, 1));
  config.step.contactResolution =
      r.number("contact_resolution", config.step.contactResolution, Range::closed(1, 1e6));
  if (!config.step.automatic) {
    for (const char* key : {"step_safety", "contact_resolution"}) {
      if (r.has(key)) r.fail(key, "applies to time_step = \"auto\" only");
    }
  }
  const std::string unstable = r.choice("on_unstable", "stop", {"stop", "warn"});
  if (config.step.automatic && r.has("on_unstable")) {
    r.fail("on_unstable", "applies to a fixed time_step only (\"auto\" chooses a stable one)");
  }
  config.step.onUnstable = unstable == "warn" ? OnUnstable::Warn : OnUnstable::Stop;
  config.skin = r.number("skin", 0.0, Range::atLeast(0));
  config.impactSpeed = r.number("impact_speed", config.impactSpeed, Range::above(0));
  // Off, a run alone sums the energies and wall reactions block by block in double (cheaper);
  // on, exactly, as a run under mpirun always does: then its files are the same bytes as one.
  config.exactSums = r.boolean("exact_sums", false);
  return r.has("impact_speed");
}

// 3. Box ------------------------------------------------------------------------------------------

BoxSpec readBox(const TomlTableReader& root, const std::string& file) {
  const toml::table* table = root.subTable("box");
  if (!table) root.failMissing("box");
  const TomlTableReader r(*table, "box", file);
  r.expectOnly(scene_schema::list(scene_schema::kBox));
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

/// Samples the grid as the builder will (grid_sampling.hpp), to find each particle's radius and
/// centre: the smallest radius and total volume set the time-step limit,
/// and a particle outside the box is reported here, against the scene file. Cheap next to the
/// run: a few nanoseconds a particle.
void checkGridParticles(const TomlTableReader& r, const GridGenerator& g, const BoxSpec& box,
                        MotionBound& bound) {
  forEachGridParticle(g, [&](std::size_t k, const CsvParticle& p) {
    const std::string crossing = boxCrossing(p.position, p.radius, box);
    if (!crossing.empty()) {
      r.fail("origin", "grid particle " + std::to_string(k) + " at " + formatPoint(p.position) +
                           " with radius " + formatNumber(p.radius) + " m " + crossing +
                           " (check origin, cell_size and cells against box.min and box.max)");
    }
    bound.add(p.radius);
  });
}

GridGenerator readGrid(const TomlTableReader& r, const BoxSpec& box, MotionBound& bound) {
  r.expectOnly(scene_schema::list(scene_schema::kGridParticles));
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
  checkGridParticles(r, g, box, bound);

  // Highest particle top: the last filled layer (z fastest-varying last) plus the largest radius.
  const std::int64_t layers = (count + cells[0] * cells[1] - 1) / (cells[0] * cells[1]);
  bound.highestTop =
      std::max(bound.highestTop, g.origin.z() + (double(layers) - 0.5) * g.cellSize + g.radiusMax);
  bound.fastest = std::max(bound.fastest, g.speedMax);
  return g;
}

/// The first row (in file order) that overlaps an earlier row, reported with both. Rows are
/// binned into cells of edge 2·R_max, so overlapping rows are in the same or adjacent cells.
void checkNoOverlap(const TomlTableReader& r, const std::filesystem::path& path,
                    const std::vector<CsvParticle>& rows) {
  double maxRadius = 0.0;
  for (const CsvParticle& p : rows) maxRadius = std::max(maxRadius, p.radius);
  using Cell = std::array<long long, 3>;
  // Clamped before the cast: a row 1e54 m away is legal above an open box and must not
  // overflow the integer; rows sharing a clamped cell are still compared by their distance.
  auto cellOf = [&](const Vec3& x) {
    const Vec3 c = (x / (2.0 * maxRadius)).array().floor().cwiseMax(-0x1p60).cwiseMin(0x1p60);
    return Cell{(long long)c.x(), (long long)c.y(), (long long)c.z()};
  };
  std::map<Cell, std::vector<std::size_t>> cells;
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const Cell home = cellOf(rows[j].position);
    for (long long dx = -1; dx <= 1; ++dx) {
      for (long long dy = -1; dy <= 1; ++dy) {
        for (long long dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find(Cell{home[0] + dx, home[1] + dy, home[2] + dz});
          if (it == cells.end()) continue;
          for (const std::size_t i : it->second) {
            const double gap = (rows[j].position - rows[i].position).norm();
            const double reach = rows[i].radius + rows[j].radius;
            if (gap >= reach) continue;
            r.fail("file", path.string() + ":" + std::to_string(rows[j].line) + ": row " +
                               std::to_string(j + 1) + " overlaps row " + std::to_string(i + 1) +
                               " (line " + std::to_string(rows[i].line) + "): centres " +
                               formatPoint(rows[i].position) + " and " +
                               formatPoint(rows[j].position) + " are " + formatNumber(gap) +
                               " m apart, radii sum " + formatNumber(reach) + " m");
          }
        }
      }
    }
    cells[home].push_back(j);
  }
}

CsvGenerator readCsv(const TomlTableReader& r, const std::filesystem::path& folder,
                     const BoxSpec& box, bool frictional, bool savedState, MotionBound& bound) {
  r.expectOnly(scene_schema::list(scene_schema::kCsvParticles));
  const std::string name = r.string("file");
  if (name.empty()) r.fail("file", "must name a CSV file");
  CsvGenerator g;
  g.path = std::filesystem::path(name).is_absolute() ? std::filesystem::path(name) : folder / name;
  g.savedState = savedState;
  // Read it now, so a bad row is reported against the scene key that names the file.
  ParticleCsv file;
  try {
    file = readParticleCsv(g.path, savedState ? CsvKind::SavedState : CsvKind::Particles);
  } catch (const ConfigError& e) {
    r.fail("file", e.what());
  }
  g.contentHash = file.contentHash;
  const std::vector<CsvParticle>& rows = file.rows;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CsvParticle& p = rows[i];
    const std::string row =
        g.path.string() + ":" + std::to_string(p.line) + ": row " + std::to_string(i + 1);
    const std::string crossing = boxCrossing(p.position, p.radius, box, savedState);
    if (!crossing.empty()) {
      r.fail("file", row + " at " + formatPoint(p.position) + " with radius " +
                         formatNumber(p.radius) + " m " + crossing);
    }
    if (!frictional && (p.angularVelocity.array() != 0.0).any()) {
      r.fail("file", row + " spins at (wx, wy, wz) = " + formatPoint(p.angularVelocity) +
                         " rad/s, but material.friction = 0: without friction nothing turns a "
                         "particle and the run ignores rotation; set material.friction > 0, or "
                         "zero the spin");
    }
    bound.highestTop = std::max(bound.highestTop, p.position.z() + p.radius);
    bound.fastest = std::max(bound.fastest, p.velocity.norm());
    bound.add(p.radius);
  }
  if (!savedState) checkNoOverlap(r, g.path, rows);  // a saved state's contacts are its own
  return g;
}

std::vector<Generator> readParticles(const TomlTableReader& root, const std::string& file,
                                     const std::filesystem::path& folder, const BoxSpec& box,
                                     bool frictional, MotionBound& bound) {
  const toml::array* array = root.tableArray("particles");
  if (!array) root.failMissing("particles");
  std::vector<Generator> generators;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const TomlTableReader r(*array->get(i)->as_table(), "particles[" + std::to_string(i) + "]",
                            file);
    // Keys of either type first, so that a misspelt "type" gets a suggestion, not "missing".
    std::vector<std::string_view> either = scene_schema::list(scene_schema::kGridParticles);
    either.push_back("file");
    r.expectOnly(either);
    const std::string type = r.choice("type", "", {"grid", "csv", "state"});
    if (type == "grid") {
      generators.emplace_back(readGrid(r, box, bound));
    } else {
      generators.emplace_back(readCsv(r, folder, box, frictional, type == "state", bound));
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
  r.expectOnly(walls);
  std::vector<WallMotion> motions;
  for (auto&& [key, node] : *table) {
    motions.push_back({std::string(key.str()), r.vec3(key.str(), Range::any())});
  }
  return motions;
}

std::vector<StageSpec> readStages(const TomlTableReader& root, const std::string& file,
                                  const BoxSpec& box, double timeStep) {
  const toml::array* array = root.tableArray("stages");
  if (!array) root.failMissing("stages");
  std::vector<StageSpec> stages;
  std::string topPlacedBy;  // name of the stage that placed the top wall, if any
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
  const TomlTableReader r(*table, "output", file);
  r.expectOnly(scene_schema::list(scene_schema::kOutput));
  output.interval = r.number("interval", output.interval, Range::above(0));
  output.snapshotTimes = r.numbers("snapshots", Range::atLeast(0));
  std::sort(output.snapshotTimes.begin(), output.snapshotTimes.end());
  output.checks.energyDriftLimit =
      r.number("energy_drift_limit", output.checks.energyDriftLimit, Range::above(0));
  const std::string action = r.choice("on_failed_check", "warn", {"warn", "stop"});
  output.checks.onFailedCheck = action == "stop" ? CheckAction::Stop : CheckAction::Warn;
  return output;
}

/// The largest approach speed a contact can have: two particles head-on, each at the largest
/// speed a particle can reach, which is its largest initial speed, plus the free-fall speed from
/// the highest particle top to the floor, plus twice the fastest wall's speed (a particle struck
/// by a wall leaves it at up to twice the wall's speed). A particle meets a wall at most at that
/// speed plus the wall's, which is less than twice it.
double defaultImpactSpeed(const MotionBound& bound, const BoxSpec& box, const Vec3& gravity,
                          const std::vector<StageSpec>& stages) {
  const double height = std::max(0.0, bound.highestTop - box.min.z());
  double wall = 0.0;
  for (const StageSpec& stage : stages) {
    for (const WallMotion& motion : stage.wallMotions)
      wall = std::max(wall, motion.velocity.norm());
  }
  const double particle = bound.fastest + std::sqrt(2.0 * gravity.norm() * height) + 2.0 * wall;
  return particle > 0.0 ? 2.0 * particle : 1.0;
}

// 7. Time step ------------------------------------------------------------------------------------

/// A reader of `key`'s table, or of the root when the table is absent (a default is at fault).
TomlTableReader tableOrRoot(const TomlTableReader& root, std::string_view key,
                            const std::string& file) {
  if (const toml::table* table = root.subTable(key)) {
    return TomlTableReader(*table, std::string(key), file);
  }
  return root;
}

/// x to 4 significant digits, "%.4g", rounded down when `down` (a limit a user may copy).
std::string fourDigits(double x, bool down = false) {
  if (down && x > 0.0) {
    const double unit = std::pow(10.0, std::floor(std::log10(x)) - 3.0);
    x = std::floor(x / unit) * unit;
  }
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", x);
  return buffer;
}

/// Why a fixed step is above the one the network of a dense bed allows (denseBedStep).
std::string denseBedRefusal(const SimulationConfig& config, const NetworkStep& bed, double radius) {
  const bool gear = config.integrator == Integrator::Gear5;
  return "time step " + formatNumber(config.timeStep) +
         " s is above the step the contact network of a dense bed allows with rolling "
         "resistance, " +
         fourDigits(bed.dt) + " s: " + (gear ? "gear5" : "velocity Verlet") +
         " is stable for ω Δt <= " + fourDigits(bed.dt * bed.omegaMax) +
         " at the network's damping ratio " + fourDigits(bed.zeta) +
         " (the rolling dashpots turn the spheres' own rotation), and its highest frequency is "
         "at most " +
         fourDigits(bed.omegaMax) + " rad/s (a face-centred cubic block of spheres of radius " +
         fourDigits(radius) + " m, 12 contacts each, on the floor); use at most " +
         fourDigits(bed.dt, true) + " s, or time_step = \"auto\"";
}

/// The engine's stability rule (Simulation refuses the same step), checked with the density the
/// builder will use, so that the message can name the key. Also refuses a total_mass that would
/// give a density beyond the declared bound, and a damping that over-damps the stiffest contact.
void checkTimeStep(const TomlTableReader& root, const std::string& file, Scene& scene,
                   const MotionBound& bound) {
  Material material = scene.simulation.material;
  if (scene.totalMass) {
    material.density = *scene.totalMass / bound.volume;
    const double maxDensity = findParameter("density")->range.hi;  // the declared bound
    if (!(material.density <= maxDensity)) {
      root.fail("total_mass", "gives the particles a density of " + formatNumber(material.density) +
                                  " kg/m³; must be at most " + formatNumber(maxDensity));
    }
  }
  ContactScale scale;
  try {
    scale = stiffestContact(material, bound.smallestRadius, scene.simulation.impactSpeed);
  } catch (const ConfigError& e) {
    tableOrRoot(root, "material", file).fail("normal_damping", e.what());
  }
  if (scene.simulation.step.automatic) {
    // The largest step the engine may choose: the accuracy floor.
    scene.simulation.timeStep = scale.duration / scene.simulation.step.contactResolution;
    return;
  }
  const TomlTableReader simulation(*root.subTable("simulation"), "simulation", file);
  if (RollingResistance::active(material)) {
    // The rolling dashpots act on the spheres' own rotation, whose inertia is small: their rates
    // shrink Gear's interval, which the binary contact's duration does not see. The step is
    // judged on the network of a dense bed of the smallest spheres instead.
    SimulationConfig config = scene.simulation;
    config.material = material;
    const NetworkStep bed = denseBedStep(config, bound.smallestRadius);
    if (!(scene.simulation.timeStep <= bed.dt)) {
      simulation.fail("time_step", denseBedRefusal(scene.simulation, bed, bound.smallestRadius));
    }
  }
  for (const Generator& g : scene.generators) {
    if (std::holds_alternative<CsvGenerator>(g)) return;  // the engine checks the network
  }
  try {
    requireStableStep(scene.simulation.timeStep, scale, scene.simulation.integrator);
  } catch (const ConfigError& e) {
    if (scene.totalMass) {
      // The density, hence the contact duration, comes from total_mass: name both keys.
      root.fail("total_mass", "gives the particles a density of " + formatNumber(material.density) +
                                  " kg/m³, so " + e.what() +
                                  "; raise total_mass or lower simulation.time_step");
    }
    simulation.fail("time_step", e.what());
  }
  try {
    requireStableTangentialDamping(material, scene.simulation.timeStep,
                                   scene.simulation.integrator);
  } catch (const ConfigError& e) {
    tableOrRoot(root, "material", file).fail("tangential_damping", e.what());
  }
}

/// Where a warning about `key` of `table` points: the key's line, or the table's, or the file.
std::string warningPrefix(const TomlTableReader& root, const std::string& file,
                          std::string_view table, std::string_view key) {
  if (const toml::table* t = root.subTable(table)) {
    const TomlTableReader r(*t, std::string(table), file);
    if (r.has(key)) return r.messagePrefix(key);
  }
  return file + ": ";
}

/// Warnings of overlaps beyond a radius, which no time step mends (the contact is too soft for
/// the load): an impact at the expected approach speed, and the bed's weight on its floor.
void warnOfDeepOverlaps(const TomlTableReader& root, const std::string& file, Scene& scene,
                        const MotionBound& bound, bool impactSpeedGiven) {
  Material material = scene.simulation.material;
  if (scene.totalMass) material.density = *scene.totalMass / bound.volume;
  const double r = bound.smallestRadius;
  const double m = material.density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  // A declared approach speed as it is; the default's bound (two spheres head-on, each at the
  // largest speed a particle reaches) far exceeds what a bed's impacts meet, so a particle at
  // that largest speed striking a wall or a sphere at rest stands for it.
  const double u =
      impactSpeedGiven ? scene.simulation.impactSpeed : 0.5 * scene.simulation.impactSpeed;
  try {
    // A wall contact and a pair of the smallest spheres (a pair's overlap beyond a radius puts
    // each centre inside the other sphere).
    const double wall = peakImpactOverlap(material, r, m, u);
    const double pair = peakImpactOverlap(material, 0.5 * r, 0.5 * m, u);
    if (std::max(wall, pair) > r) {
      const double held = std::min(speedForPeakOverlap(material, r, m, r),
                                   speedForPeakOverlap(material, 0.5 * r, 0.5 * m, r));
      const std::string where =
          impactSpeedGiven
              ? warningPrefix(root, file, "simulation", "impact_speed")
              : file + ": the particles' initial speeds, fall height and wall speeds let a " +
                    "particle strike at up to " + fourDigits(u) + " m/s: ";
      scene.warnings.push_back(
          where + "an impact at " + fourDigits(u) + " m/s overlaps spheres of radius " +
          fourDigits(r) + " m by " + fourDigits(std::max(wall, pair) / r) +
          " radii (the peak overlap of a head-on impact under the normal law): beyond a radius "
          "spheres pass through each other and through walls, whatever the time step; this "
          "material holds impacts up to " +
          fourDigits(held) + " m/s: stiffen material.youngs_modulus, or slow the particles");
    }
  } catch (const ConfigError&) {
    // An over-damped contact: refused by the time-step check already.
  }
  // At rest on the floor: the bed's weight over the floor's area, on each bottom sphere's
  // square of side 2R (the largest spheres press in deepest: k_n grows as R, the load as R²).
  const double down = -scene.simulation.gravity.z();
  if (!scene.box.walls[4] || !(down > 0.0)) return;
  const Vec3 size = scene.box.max - scene.box.min;
  const double big = bound.largestRadius;
  const double load =
      material.density * bound.volume * down / (size.x() * size.y()) * (2.0 * big) * (2.0 * big);
  const double kn = material.normalCoefficient();
  const double sunk = material.normalLaw == NormalLaw::Hooke
                          ? load / (kn * big)
                          : std::pow(load / (kn * std::sqrt(big)), 2.0 / 3.0);
  if (sunk > big) {
    scene.warnings.push_back(
        warningPrefix(root, file, "material", "youngs_modulus") + "at rest on the floor, the " +
        "bed's weight (" + fourDigits(material.density * bound.volume * down) + " N over " +
        fourDigits(size.x() * size.y()) + " m²) presses each bottom sphere of radius " +
        fourDigits(big) + " m " + fourDigits(sunk / big) +
        " radii into it: the spheres sink through the floor, whatever the time step; stiffen "
        "material.youngs_modulus");
  }
}

}  // namespace

// 8. loadScene ------------------------------------------------------------------------------------

std::string fileSafeName(const std::string& name) {
  std::string safe;
  for (char c : name) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '-' || c == '_';
    safe += plain ? c : '_';
  }
  return safe;
}

Scene loadScene(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(file, error);
  if (!std::filesystem::exists(status)) {
    throw SceneError(name + ": cannot open scene file: no such file");
  }
  if (std::filesystem::is_directory(status)) {
    throw SceneError(name + ": cannot open scene file: it is a folder (give the .toml file)");
  }
  if (!std::filesystem::is_regular_file(status)) {
    throw SceneError(name + ": cannot open scene file: not a regular file (a device or pipe?)");
  }
  if (std::filesystem::file_size(file, error) > kMaxSceneBytes) {
    throw SceneError(name + ": cannot open scene file: larger than " +
                     formatNumber(double(kMaxSceneBytes)) + " bytes; a scene is a few lines " +
                     "(particles go in a CSV file)");
  }
  toml::table document;
  try {
    document = toml::parse_file(name);
  } catch (const toml::parse_error& e) {
    throw SceneError(locationPrefix(name, e.source()) + std::string(e.description()));
  }
  if (document.empty()) {
    throw SceneError(name + ": the scene is empty (no keys); docs/scenes.md lists them");
  }

  const TomlTableReader root(document, "", name);
  root.expectOnly(scene_schema::list(scene_schema::kTopLevel));
  Scene scene;
  scene.sourceFile = file;
  scene.simulation.material = readMaterial(root, name);
  const bool impactSpeedGiven = readSimulation(root, name, scene);
  scene.box = readBox(root, name);
  MotionBound bound;
  scene.generators = readParticles(root, name, file.parent_path(), scene.box,
                                   scene.simulation.material.hasFriction(), bound);
  scene.totalMass = root.optionalNumber("total_mass", Range::above(0));
  // An automatic step has no smallest value known here: its stages are not counted in steps.
  scene.stages =
      readStages(root, name, scene.box,
                 scene.simulation.step.automatic ? std::numeric_limits<double>::infinity()
                                                 : scene.simulation.timeStep);
  scene.output = readOutput(root, name);
  if (!impactSpeedGiven) {
    scene.simulation.impactSpeed =
        defaultImpactSpeed(bound, scene.box, scene.simulation.gravity, scene.stages);
  }
  checkTimeStep(root, name, scene, bound);
  warnOfDeepOverlaps(root, name, scene, bound, impactSpeedGiven);
  return scene;
}

}  // namespace granular
