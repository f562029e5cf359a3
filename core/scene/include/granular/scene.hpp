#pragma once
/// A scene: everything a run needs, as read from a TOML file (loadScene) or built in C++.
/// Units are SI throughout: m, s, kg, N, Pa, J.
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "granular/simulation.hpp"

namespace granular {

/// A rectangular box [min, max]. Each of its six faces is a wall or open.
struct BoxSpec {
  Vec3 min = Vec3::Zero();  ///< lower corner [m]
  Vec3 max = Vec3::Ones();  ///< upper corner [m]
  /// Which faces are walls, in the order x-, x+, y-, y+, bottom (z-), top (z+).
  std::array<bool, 6> walls = {true, true, true, true, true, false};
};

/// Names of the box faces in BoxSpec::walls order; also the names of the walls built from them.
inline constexpr std::array<const char*, 6> kBoxWallNames = {"x-", "x+",     "y-",
                                                             "y+", "bottom", "top"};

/// Particles at the centres of a uniform cubic grid, filled x fastest, then y, then z, with
/// radii uniform in [radiusMin, radiusMax] and velocities of uniform magnitude in [0, speedMax]
/// in uniformly random directions, all from `seed`.
struct GridGenerator {
  Vec3 origin = Vec3::Zero();            ///< lower corner of the grid [m]
  double cellSize = 0.1;                 ///< cubic cell edge [m]
  std::array<int, 3> cells = {1, 1, 1};  ///< cells along x, y, z
  std::size_t count = 1;                 ///< particles to place (<= cells product)
  double radiusMin = 0.03;               ///< [m]
  double radiusMax = 0.035;              ///< [m]
  double speedMax = 0.0;                 ///< [m/s]
  std::uint64_t seed = 1;
};

/// Particles listed in a CSV file: a header line naming the columns (x, y, z, r or radius;
/// optionally vx, vy, vz and wx, wy, wz; any order), then one row per particle, in m, m/s, rad/s.
struct CsvGenerator {
  std::filesystem::path path;  ///< resolved against the scene file's folder
  /// FNV-1a of the values the file's rows gave when loadScene read it; the builder refuses the
  /// file if they have changed since. Empty for a scene built in C++ (the builder reads whatever
  /// is there).
  std::optional<std::uint64_t> contentHash;
  /// A state granular saved (final_state.csv, a snapshot; type = "state"), taken as it is: the
  /// masses from its mass column, overlaps between its particles and with the walls allowed
  /// (a settled bed has them), every contact's history (tangential and rolling springs) starting
  /// at zero. A particle file (false) gives positions, radii, velocities and spins, its masses
  /// follow from the density, and its particles must not touch.
  bool savedState = false;
};

using Generator = std::variant<GridGenerator, CsvGenerator>;

/// When a stage ends: at `maxTime`, or earlier once the kinetic energy has stayed below
/// `kineticEnergyBelow` for `sustainTime`.
struct StageEnd {
  double maxTime = 1.0;                      ///< stage duration cap [s]
  std::optional<double> kineticEnergyBelow;  ///< quasistatic threshold [J]
  double sustainTime = 0.0;                  ///< how long it must stay below [s]
};

/// A wall velocity set at the start of a stage.
struct WallMotion {
  std::string wall;              ///< wall name (kBoxWallNames)
  Vec3 velocity = Vec3::Zero();  ///< [m/s]
};

/// A region of space particles are inserted into or removed from: a box, or a cylinder (any
/// axis).
struct Region {
  enum class Shape : std::uint8_t { Box, Cylinder };
  Shape shape = Shape::Box;
  Vec3 min = Vec3::Zero();    ///< a box's lower corner [m]
  Vec3 max = Vec3::Zero();    ///< a box's upper corner [m]
  Vec3 base = Vec3::Zero();   ///< the centre of a cylinder's base [m]
  Vec3 axis = Vec3::UnitZ();  ///< a cylinder's unit axis, from its base [-]
  double length = 0;          ///< a cylinder's extent along its axis [m]
  double radius = 0;          ///< a cylinder's radius [m]
  /// Whether a sphere of radius r centred at x lies inside (r = 0: whether x does).
  bool holds(const Vec3& x, double r = 0.0) const;
  Vec3 lower() const;  ///< the corner of its bounding box with the smallest coordinates [m]
  Vec3 upper() const;  ///< the opposite corner [m]
};

/// Particles inserted into a region during a stage, at a steady rate, until `count` are in:
/// each exchange of the stage (StageSpec::exchangeInterval) inserts those due by then, placed at
/// random where they touch no particle and no wall, with radii uniform in [radiusMin,
/// radiusMax], the particles' density and `velocity`. The same particles for a given seed,
/// whatever the thread or process count; a particle that finds no room comes at a later
/// exchange.
struct InsertSpec {
  std::string name = "insert";
  Region region;
  std::uint64_t count = 0;       ///< particles in all [-]
  double rate = 0;               ///< particles per second of stage time [1/s]
  double radiusMin = 0;          ///< [m]
  double radiusMax = 0;          ///< [m]
  Vec3 velocity = Vec3::Zero();  ///< [m/s]
  std::uint64_t seed = 1;
  /// The run's tally of this insert (Simulation::insertedBy): its index among every stage's
  /// inserts, in the order of the file.
  std::size_t source = 0;
};

/// A region that removes every particle whose centre enters it, at each exchange of the
/// stage: an outlet under a silo's orifice. The mass it takes is the run's discharged mass.
struct OutletSpec {
  std::string name = "outlet";
  Region region;
};

struct StageSpec {
  std::string name = "stage";
  StageEnd end;
  std::vector<WallMotion> wallMotions;
  /// Walls taken away when the stage starts (a gate opened: Simulation::removeWall).
  std::vector<std::string> removeWalls;
  std::vector<InsertSpec> inserts;
  std::vector<OutletSpec> outlets;
  /// Stage time between two exchanges of particles by the inserts and outlets [s].
  double exchangeInterval = 0.01;
  /// Adds the top wall at the highest particle surface max(z_i + R_i) when the stage starts.
  bool placeTopWallOnSurface = false;
  /// Starts the stage's own clock at t = 0 (the paper's stage 2).
  bool resetClock = false;
  /// The stage's own snapshot times (stage clock) [s], in place of OutputSpec::snapshotTimes:
  /// a silo's rest alone, not its fill and discharge.
  std::optional<std::vector<double>> snapshotTimes;
};

/// What a run check that fails does (RunChecks, run_checks.hpp).
enum class CheckAction {
  Warn,  ///< report it once and go on
  Stop,  ///< stop the run as for a broken state
};

/// The checks a run makes of itself at its samples (RunChecks).
struct RunCheckSpec {
  /// Largest |drift| of the energy balance, as a fraction of the work done
  /// (RunChecks::workDone) [-]. The integrators at their step limits stay below 0.9 % (Verlet
  /// at t_c/10, the demo bed settling) and 2·10⁻⁵ (Gear5 at t_c/51); a run that breaks grossly
  /// drifts by tens of per cent (γt = 300 1/s in the demo: 19 %) or by factors.
  double energyDriftLimit = 0.05;
  CheckAction onFailedCheck = CheckAction::Warn;
};

struct OutputSpec {
  double interval = 0.01;             ///< time-series sampling interval [s]
  std::vector<double> snapshotTimes;  ///< stage-clock times of particle snapshots [s]
  RunCheckSpec checks;                ///< energy balance and particles outside the box
};

struct Scene {
  std::filesystem::path sourceFile;  ///< the TOML file it came from (empty if built in C++)
  SimulationConfig simulation;       ///< material, gravity, integrator, time step
  BoxSpec box;
  /// The [[walls]] array: walls of any shape beside the box's faces, at their start.
  std::vector<Wall> walls;
  std::vector<Generator> generators;
  /// If set, the density is scaled so that the total mass equals this [kg].
  std::optional<double> totalMass;
  std::vector<StageSpec> stages;
  OutputSpec output;
  /// Where a value that the builder or the engine may still refuse is written, by dotted key:
  /// "scene.toml:16:1: simulation.time_step = 0.01: " (a packed start's step, refused against
  /// its contact network), so that the refusal names the file, the line and the key. Empty for
  /// a scene built in C++.
  std::map<std::string, std::string> keyLocations;
  /// What the loader found legal but likely wrong, each "file:line:column: key = value: why"
  /// (an impact speed whose peak overlap is beyond a radius, a bed that sinks through its floor
  /// at rest): the commands print them as warnings. Empty for a scene built in C++.
  std::vector<std::string> warnings;
};

/// Whether a stage of the scene inserts or removes particles (its outputs then count them).
inline bool exchangesParticles(const Scene& scene) {
  for (const StageSpec& stage : scene.stages) {
    if (!stage.inserts.empty() || !stage.outlets.empty()) return true;
  }
  return false;
}

/// A stage's name as output file names carry it: every character outside [A-Za-z0-9_-] becomes
/// '_'. loadScene refuses two stages whose names map to the same file name.
std::string fileSafeName(const std::string& name);

/// Reads and validates a scene file. Throws SceneError naming the file, the key, the value and
/// the allowed range on any unknown key, wrong type or out-of-range value.
Scene loadScene(const std::filesystem::path& file);

/// Builds the particles of a scene (generators, mass scaling). Throws ConfigError on a particle
/// outside the box, overlapping particles at start, or an unreadable CSV (naming file and row).
Particles buildParticles(const Scene& scene);

/// Builds the walls of the box.
std::vector<Wall> buildWalls(const BoxSpec& box);

/// Builds a ready-to-run simulation from a scene.
Simulation buildSimulation(const Scene& scene);

}  // namespace granular
