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
/// (particles may be absent when a stage inserts them)
/// stages[i].name                      | -     | non-empty, unique            | "stage<i+1>"
/// stages[i].max_time                  | s     | > 0, at most 1e12 time steps | required
/// stages[i].kinetic_energy_below      | J     | > 0                          | none
/// stages[i].sustain_time              | s     | [0, max_time]                | 0
/// stages[i].place_top_wall_on_surface | -     | boolean                      | false
/// stages[i].reset_clock               | -     | boolean                      | false
/// stages[i].wall_velocity.<wall>      | m/s   | 3 finite numbers             | at rest
/// stages[i].remove_walls              | -     | names of [[walls]], once     | []
/// stages[i].exchange_interval         | s     | (0, max_time]                | 0.01
/// stages[i].snapshots                 | s     | numbers >= 0                 | output.snapshots
/// stages[i].inserts[k].name           | -     | non-empty                    | "insert<n>"
/// stages[i].inserts[k].shape          | -     | "box" | "cylinder"           | "box"
/// stages[i].inserts[k].min, max (box) | m     | in the box, max > min        | required
/// stages[i].inserts[k].base, axis     | m, -  | the cylinder in the box      | required
/// stages[i].inserts[k].length, radius | m     | > 0                          | required
/// stages[i].inserts[k].count          | -     | [1, 1e8]                     | required
/// stages[i].inserts[k].rate           | 1/s   | > 0                          | required
/// stages[i].inserts[k].radius_min     | m     | > 0                          | required
/// stages[i].inserts[k].radius_max     | m     | >= radius_min, fits region   | required
/// stages[i].inserts[k].velocity       | m/s   | 3 finite numbers             | [0, 0, 0]
/// stages[i].inserts[k].seed           | -     | integer >= 0                 | 1
/// stages[i].outlets[k].name, shape and region keys as an insert's
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
/// Files: the material in material_reader.cpp, the particles in particles_reader.cpp, the stages
/// in stages_reader.cpp, the time-step checks and warnings in step_checks_at_load.cpp; here
/// 1. simulation; 2. box; 3. output; 4. loadScene.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "granular/error.hpp"
#include "granular/scene.hpp"
#include "material_reader.hpp"
#include "particles_reader.hpp"
#include "scene_schema.hpp"
#include "stages_reader.hpp"
#include "step_checks_at_load.hpp"
#include "toml_table_reader.hpp"
#include "walls_reader.hpp"

namespace granular {

namespace {

/// A scene file is a few hundred bytes; anything this large is the wrong file.
constexpr std::uintmax_t kMaxSceneBytes = 16 << 20;

std::vector<std::string_view> boxWallNames() {
  return {kBoxWallNames.begin(), kBoxWallNames.end()};
}

// 1. Simulation -----------------------------------------------------------------------------------

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

// 2. Box ------------------------------------------------------------------------------------------

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

// 3. Output ---------------------------------------------------------------------------------------

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

/// The particles the stages insert: the run starts with none if the file gives none, its
/// smallest radius is theirs where smaller, and the time-step checks and the impact speed take
/// them in (their speed, and their fall from the region's top).
void takeInInserts(const TomlTableReader& root, Scene& scene, MotionBound& bound) {
  bool inserts = false;
  for (const StageSpec& stage : scene.stages) {
    for (const InsertSpec& insert : stage.inserts) {
      inserts = true;
      bound.smallestRadius = std::min(bound.smallestRadius, insert.radiusMin);
      bound.largestRadius = std::max(bound.largestRadius, insert.radiusMax);
      bound.highestTop = std::max(bound.highestTop, insert.region.upper().z());
      bound.fastest = std::max(bound.fastest, insert.velocity.norm());
      scene.simulation.smallestRadius =
          scene.simulation.smallestRadius > 0
              ? std::min(scene.simulation.smallestRadius, insert.radiusMin)
              : insert.radiusMin;
    }
  }
  if (scene.generators.empty() && !inserts) root.failMissing("particles");
  if (inserts && scene.totalMass) {
    root.fail("total_mass",
              "scales the density to a total mass, which a run that inserts particles does not "
              "have; give material.density instead");
  }
}

}  // namespace

// 4. loadScene ------------------------------------------------------------------------------------

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
  scene.walls = readWalls(root, name, scene.box, scene.simulation.material);
  MotionBound bound;
  scene.generators = readParticles(root, name, file.parent_path(), scene.box,
                                   scene.simulation.material.hasFriction(), bound);
  scene.totalMass = root.optionalNumber("total_mass", Range::above(0));
  // An automatic step has no smallest value known here: its stages are not counted in steps.
  scene.stages =
      readStages(root, name, scene.box, scene.walls,
                 scene.simulation.step.automatic ? std::numeric_limits<double>::infinity()
                                                 : scene.simulation.timeStep);
  scene.output = readOutput(root, name);
  takeInInserts(root, scene, bound);
  if (!impactSpeedGiven) {
    scene.simulation.impactSpeed =
        defaultImpactSpeed(bound, scene.box, scene.simulation.gravity, scene.stages, scene.walls);
  }
  checkTimeStep(root, name, scene, bound);
  warnOfDeepOverlaps(root, name, scene, bound, impactSpeedGiven);
  return scene;
}

}  // namespace granular
