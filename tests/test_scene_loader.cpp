/// Tests of loadScene: a full scene round-trips to the expected values, defaults match the
/// structs' defaults, and malformed scenes throw SceneError naming the file, line, key and value.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "granular/network_step.hpp"
#include "granular/scene.hpp"
#include "granular_process.hpp"
#include "temp_folder.hpp"

namespace granular {
namespace {

namespace fs = std::filesystem;

/// A fresh folder per test (temp_folder.hpp).
class SceneLoader : public testing::TempFolderTest {
 protected:
  SceneLoader() : TempFolderTest("granular_scene_loader") {}

  /// The SceneError message of loading `text`, or a failure if it loads.
  std::string errorOf(const std::string& text) const {
    const fs::path path = write("scene.toml", text);
    try {
      loadScene(path);
    } catch (const SceneError& e) {
      return e.what();
    }
    ADD_FAILURE() << "no SceneError for:\n" << text;
    return {};
  }
};

/// The smallest valid scene: every required key, nothing else.
const std::string kMinimal = R"([simulation]
time_step = 1e-4

[box]
min = [0, 0, 0]
max = [1, 1, 2]

[[particles]]
type = "grid"
origin = [0, 0, 0]
cell_size = 0.1
cells = [2, 2, 2]
radius_min = 0.03
radius_max = 0.035

[[stages]]
max_time = 1.0
)";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

int lineCount(const std::string& text) {
  return int(std::count(text.begin(), text.end(), '\n'));
}

TEST_F(SceneLoader, FullSceneRoundTrips) {
  write("grains.csv", "x,y,z,r,vx,vy,vz\n0.5,0.5,1.5,0.02,0,0,-1\n");
  const fs::path path = write("scene.toml", R"(
total_mass = 12.5

[material]
youngs_modulus = 1e7
poisson_ratio = 0.25
shear_modulus = 4e6
density = 2500
friction = 0.5
normal_damping = 30
tangential_damping = 5
normal_law = "hertz"

[simulation]
gravity = [0.0, 1, -10]
integrator = "verlet"
time_step = 2e-5
skin = 0.004
impact_speed = 3.5
exact_sums = true

[box]
min = [-1, -2, 0]
max = [1, 2, 3]
walls = ["x-", "x+", "bottom", "top"]

[[particles]]
type = "grid"
origin = [-0.5, -0.5, 0.2]
cell_size = 0.2
cells = [3, 4, 5]
count = 50
radius_min = 0.05
radius_max = 0.09
speed_max = 0.3
seed = 42

[[particles]]
type = "csv"
file = "grains.csv"

[[stages]]
name = "settle"
max_time = 2.0
kinetic_energy_below = 1e-3
sustain_time = 0.1

[[stages]]
name = "press"
max_time = 1.0
reset_clock = true
snapshots = [0.3, 0.1]
[stages.wall_velocity]
top = [0, 0, -0.01]
"x+" = [-0.001, 0, 0]

[output]
interval = 0.005
snapshots = [0.5, 0.25]
)");
  const Scene s = loadScene(path);
  EXPECT_EQ(s.sourceFile, path);
  ASSERT_TRUE(s.totalMass.has_value());
  EXPECT_EQ(*s.totalMass, 12.5);

  const Material& m = s.simulation.material;
  EXPECT_EQ(m.youngModulus, 1e7);
  EXPECT_EQ(m.poissonRatio, 0.25);
  EXPECT_EQ(m.shearModulus, 4e6);
  EXPECT_EQ(m.density, 2500.0);
  EXPECT_EQ(m.friction, 0.5);
  EXPECT_EQ(m.normalDamping, 30.0);
  EXPECT_EQ(m.tangentialDamping, 5.0);
  EXPECT_EQ(m.normalLaw, NormalLaw::Hertz);

  EXPECT_EQ(s.simulation.gravity, Vec3(0, 1, -10));
  EXPECT_EQ(s.simulation.integrator, Integrator::VelocityVerlet);
  EXPECT_EQ(s.simulation.timeStep, 2e-5);
  EXPECT_EQ(s.simulation.skin, 0.004);
  EXPECT_EQ(s.simulation.impactSpeed, 3.5);
  EXPECT_TRUE(s.simulation.exactSums);

  EXPECT_EQ(s.box.min, Vec3(-1, -2, 0));
  EXPECT_EQ(s.box.max, Vec3(1, 2, 3));
  EXPECT_EQ(s.box.walls, (std::array<bool, 6>{true, true, false, false, true, true}));

  ASSERT_EQ(s.generators.size(), 2u);
  const auto& grid = std::get<GridGenerator>(s.generators[0]);
  EXPECT_EQ(grid.origin, Vec3(-0.5, -0.5, 0.2));
  EXPECT_EQ(grid.cellSize, 0.2);
  EXPECT_EQ(grid.cells, (std::array<int, 3>{3, 4, 5}));
  EXPECT_EQ(grid.count, 50u);
  EXPECT_EQ(grid.radiusMin, 0.05);
  EXPECT_EQ(grid.radiusMax, 0.09);
  EXPECT_EQ(grid.speedMax, 0.3);
  EXPECT_EQ(grid.seed, 42u);
  const auto& csv = std::get<CsvGenerator>(s.generators[1]);
  EXPECT_EQ(csv.path, path.parent_path() / "grains.csv");  // relative to the scene file

  ASSERT_EQ(s.stages.size(), 2u);
  EXPECT_EQ(s.stages[0].name, "settle");
  EXPECT_EQ(s.stages[0].end.maxTime, 2.0);
  EXPECT_EQ(s.stages[0].end.kineticEnergyBelow, 1e-3);
  EXPECT_EQ(s.stages[0].end.sustainTime, 0.1);
  EXPECT_FALSE(s.stages[0].placeTopWallOnSurface);
  EXPECT_FALSE(s.stages[0].resetClock);
  EXPECT_TRUE(s.stages[0].wallMotions.empty());
  EXPECT_EQ(s.stages[1].name, "press");
  EXPECT_FALSE(s.stages[1].end.kineticEnergyBelow.has_value());
  EXPECT_TRUE(s.stages[1].resetClock);
  ASSERT_EQ(s.stages[1].wallMotions.size(), 2u);
  for (const WallMotion& motion : s.stages[1].wallMotions) {
    if (motion.wall == "top") {
      EXPECT_EQ(motion.velocity, Vec3(0, 0, -0.01));
    } else {
      EXPECT_EQ(motion.wall, "x+");
      EXPECT_EQ(motion.velocity, Vec3(-0.001, 0, 0));
    }
  }

  EXPECT_EQ(s.output.interval, 0.005);
  EXPECT_EQ(s.output.snapshotTimes, (std::vector<double>{0.25, 0.5}));    // sorted
  EXPECT_FALSE(s.stages[0].snapshotTimes.has_value());                    // the output's
  EXPECT_EQ(s.stages[1].snapshotTimes, (std::vector<double>{0.1, 0.3}));  // its own, sorted
}

TEST_F(SceneLoader, DefaultsAreTheStructDefaults) {
  const Scene s = loadScene(write("scene.toml", kMinimal));
  const Material d;
  const Material& m = s.simulation.material;
  EXPECT_EQ(m.youngModulus, d.youngModulus);
  EXPECT_EQ(m.poissonRatio, d.poissonRatio);
  EXPECT_EQ(m.shearModulus, d.shearModulus);
  EXPECT_EQ(m.density, d.density);
  EXPECT_EQ(m.friction, d.friction);
  EXPECT_EQ(m.normalDamping, d.normalDamping);
  EXPECT_EQ(m.tangentialDamping, d.tangentialDamping);
  EXPECT_EQ(m.normalLaw, d.normalLaw);
  EXPECT_EQ(s.simulation.gravity, Vec3(0, 0, -9.81));
  EXPECT_EQ(s.simulation.integrator, Integrator::Gear5);
  EXPECT_EQ(s.simulation.skin, 0.0);
  EXPECT_FALSE(s.simulation.exactSums);  // a run alone sums block by block unless asked
  EXPECT_EQ(s.box.walls, BoxSpec().walls);
  EXPECT_FALSE(s.totalMass.has_value());
  const auto& grid = std::get<GridGenerator>(s.generators[0]);
  EXPECT_EQ(grid.count, 8u);  // all cells
  EXPECT_EQ(grid.speedMax, 0.0);
  EXPECT_EQ(grid.seed, 1u);
  EXPECT_EQ(s.stages[0].name, "stage1");
  EXPECT_EQ(s.stages[0].end.sustainTime, 0.0);
  EXPECT_EQ(s.output.interval, OutputSpec().interval);
  EXPECT_TRUE(s.output.snapshotTimes.empty());
  EXPECT_FALSE(s.stages[0].snapshotTimes.has_value());
}

TEST_F(SceneLoader, DefaultImpactSpeedIsTwoParticlesHeadOnAtTheirLargestSpeed) {
  // Two layers of 0.1 m cells from z = 0: the highest top is 0.15 + 0.035 above the floor. A
  // particle's largest speed is its initial 0.2 m/s plus the free fall from there, plus twice
  // the fastest wall (0.5 m/s: a wall strikes a particle away at up to twice its speed); two of
  // them meet head-on at twice that.
  const std::string text =
      replaced(kMinimal, "radius_max = 0.035", "radius_max = 0.035\nspeed_max = 0.2");
  const double particle = 0.2 + std::sqrt(2 * 9.81 * 0.185);
  EXPECT_NEAR(loadScene(write("scene.toml", text)).simulation.impactSpeed, 2 * particle, 1e-12);
  const std::string moving = replaced(text, "max_time = 1.0",
                                      "max_time = 1.0\n[stages.wall_velocity]\nx- = [0.3, 0.4, 0]");
  EXPECT_NEAR(loadScene(write("moving.toml", moving)).simulation.impactSpeed,
              2 * (particle + 2 * 0.5), 1e-12);
}

TEST_F(SceneLoader, HertzStepCheckUsesTheHeadOnApproachOfTwoSpheres) {
  // Two equal undamped Hertz spheres at ±0.5 m/s along x meet at 1 m/s. Their contact lasts
  // t_c = 3.2181 (m*/K)^(2/5) v^(-1/5) at v = 1 m/s, 2^(-1/5) = 0.87 times the duration at the
  // 0.5 m/s of either sphere: the step check must take the duration of the contact that happens.
  // Measured on the impact itself (at t_c/1300), the duration is the engine's t_c. The scene
  // starts with the pair apart and closing: the engine's network counts the coming contact at
  // the peak overlap of a head-on impact at 1 m/s, and a step above that network's refuses to
  // build, naming the key (velocity Verlet: gear5 keeps its binary limit, t_c/50, as well).
  // 5 mm apart: within the neighbour list's skin (0.3 R), so the network sees them coming.
  write("pair.csv",
        "x,y,z,r,vx,vy,vz\n0.4675,0.5,0.5,0.03,0.5,0,0\n0.5325,0.5,0.5,0.03,-0.5,0,0\n");
  const std::string scene = R"([material]
normal_law = "hertz"
normal_damping = 0.0
[simulation]
integrator = "verlet"
time_step = 1e-5
gravity = [0, 0, 0]
[box]
min = [0, 0, 0]
max = [1, 1, 1]
walls = []
[[particles]]
type = "csv"
file = "pair.csv"
[[stages]]
max_time = 0.2
)";
  const Scene s = loadScene(write("pair.toml", scene));
  EXPECT_EQ(s.simulation.impactSpeed, 1.0);
  Simulation sim = buildSimulation(s);
  sim.setThreads(1);  // two spheres: a team of threads would only wait
  const Particles& p = sim.particles();
  const double K = s.simulation.material.normalCoefficient() * std::sqrt(0.015);
  const double duration = hertzUndampedImpact(K, 0.5 * p.mass[0], 1.0).forceDuration;
  const double slower = hertzUndampedImpact(K, 0.5 * p.mass[0], 0.5).forceDuration;
  EXPECT_NEAR(duration / slower, std::pow(2.0, -0.2), 1e-12);
  EXPECT_NEAR(sim.contactScale().duration, duration, 1e-12 * duration);
  double touch = -1, apart = -1;
  while (apart < 0 && sim.time() < 0.1) {
    sim.step();
    const bool touching = p.position[1].x() - p.position[0].x() < 0.06;
    if (touching && touch < 0) touch = sim.time();
    if (!touching && touch >= 0) apart = sim.time();
  }
  EXPECT_NEAR(apart - touch, duration, 2e-5);  // each end found within a step
  const Simulation fresh = buildSimulation(s);
  const NetworkStep allowed = networkStableStep(fresh, 1.0);  // 1 s ahead: the pair counts
  const double mass = 0.5 * p.mass[0], reduced = 0.015;
  const double kappa = s.simulation.material.normalCoefficient();
  const double peak = std::pow(5.0 * mass * 1.0 / (4.0 * kappa * std::sqrt(reduced)), 0.4);
  const double k = 1.5 * kappa * std::sqrt(reduced * peak);  // dF/dh at the peak
  EXPECT_NEAR(allowed.omegaMax, std::sqrt(k / mass), 1e-9 * allowed.omegaMax);
  const Scene above =
      loadScene(write("above.toml", replaced(scene, "time_step = 1e-5",
                                             "time_step = " + std::to_string(1.05 * allowed.dt))));
  try {
    buildSimulation(above);
    ADD_FAILURE() << "a step above the network's was accepted";
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("above.toml:6:1: simulation.time_step = "), std::string::npos)
        << message;
    EXPECT_NE(message.find("above the step the contact network allows"), std::string::npos)
        << message;
  }
  EXPECT_NO_THROW(buildSimulation(loadScene(write(
      "below.toml",
      replaced(scene, "time_step = 1e-5", "time_step = " + std::to_string(0.95 * allowed.dt))))));
}

TEST_F(SceneLoader, MessageNamesFileLineKeyValueAndRange) {
  const std::string text = kMinimal + "\n[material]\nfriction = -0.3\n";
  const fs::path path = dir_ / "scene.toml";
  const std::string expected = path.string() + ":" + std::to_string(lineCount(kMinimal) + 3) +
                               ":1: material.friction = -0.3: must be in [0, 10]";
  EXPECT_EQ(errorOf(text), expected);
}

TEST_F(SceneLoader, TheConstantTangentialLawWithoutItsStiffnessNamesTheLawsLine) {
  const std::string text =
      kMinimal + "\n[material]\nfriction = 0.3\ntangential_law = \"constant\"\n";
  const fs::path path = dir_ / "scene.toml";
  EXPECT_EQ(errorOf(text), path.string() + ":" + std::to_string(lineCount(kMinimal) + 4) +
                               ":1: material.tangential_law = \"constant\": needs "
                               "tangential_stiffness > 0 N/m, the constant law's k_t");
  const Scene scene = loadScene(write("scene.toml", text + "tangential_stiffness = 650\n"));
  EXPECT_EQ(scene.simulation.material.tangentialLaw, TangentialLaw::Constant);
  EXPECT_EQ(scene.simulation.material.tangentialStiffness, 650.0);
}

TEST_F(SceneLoader, ParseErrorHasLineAndColumn) {
  const std::string message = errorOf(kMinimal + "oops = [1, 2\n");
  EXPECT_NE(message.find("scene.toml:" + std::to_string(lineCount(kMinimal) + 1) + ":"),
            std::string::npos)
      << message;
}

TEST_F(SceneLoader, TimeStepLimitIsTheEngines) {
  // The loader refuses exactly the steps the engine refuses: just below the loader's limit, the
  // simulation builds.
  const std::string message = errorOf(replaced(kMinimal, "time_step = 1e-4", "time_step = 1e-2"));
  const std::string tag = "above the stable limit ";
  const auto at = message.find(tag);
  ASSERT_NE(at, std::string::npos) << message;
  const double limit = std::stod(message.substr(at + tag.size()));
  auto exact = [](double x) {
    std::ostringstream o;
    o.precision(17);
    o << x;
    return o.str();
  };
  const std::string below = "time_step = " + exact(0.999 * limit);
  const Scene s = loadScene(write("ok.toml", replaced(kMinimal, "time_step = 1e-4", below)));
  EXPECT_NO_THROW(buildSimulation(s));
  const std::string above = "time_step = " + exact(1.001 * limit);
  EXPECT_THROW(loadScene(write("bad.toml", replaced(kMinimal, "time_step = 1e-4", above))),
               SceneError);
}

TEST_F(SceneLoader, MissingFileIsASceneError) {
  EXPECT_THROW(loadScene(dir_ / "absent.toml"), SceneError);
}

struct BadCase {
  const char* what;
  std::string text;
  std::vector<std::string> expected;  // substrings of the message
};

TEST_F(SceneLoader, MalformedScenesNameTheKey) {
  write("bad_row.csv", "x,y,z,r\n0.5,0.5,0.5,0.03\n0.2,0.2,abc,0.03\n");
  write("negative.csv", "x,y,z,r\n0.5,0.5,0.5,-0.03\n");
  write("nan.csv", "x,y,z,r\n0.5,nan,0.5,0.03\n");
  write("outside.csv", "x,y,z,r\n0.5,0.5,0.5,0.03\n1.2,0.5,0.5,0.03\n");
  write("overlap.csv", "x,y,z,r\n0.5,0.5,0.5,0.03\n0.54,0.5,0.5,0.03\n");
  const std::string gridKeys =
      "type = \"grid\"\norigin = [0, 0, 0]\ncell_size = 0.1\ncells = [2, 2, 2]\n"
      "radius_min = 0.03\nradius_max = 0.035\n";
  const std::string csvScene = replaced(kMinimal, gridKeys, "type = \"csv\"\nfile = \"FILE\"\n");
  const std::vector<BadCase> cases = {
      {"unknown key",
       kMinimal + "[material]\nfrcition = 0.3\n",
       {"material.frcition", "unknown key", "did you mean 'friction'?"}},
      {"unknown table",
       kMinimal + "[simulaton]\nskin = 0\n",
       {"simulaton", "did you mean 'simulation'?"}},
      {"unknown key far from any",
       kMinimal + "[output]\ncolour = 1\n",
       {"output.colour", "valid keys are 'interval', 'snapshots'"}},
      {"wrong type",
       kMinimal + "[material]\nfriction = \"high\"\n",
       {"material.friction = \"high\"", "expected a number, got a string"}},
      {"out of range",
       kMinimal + "[material]\npoisson_ratio = 0.5\n",
       {"material.poisson_ratio = 0.5", "must be in [0, 0.5)"}},
      {"modulus above bound",
       kMinimal + "[material]\nyoungs_modulus = 3e14\n",
       {"material.youngs_modulus = 3e+14", "(0, 1e+12]"}},
      {"nan literal",
       kMinimal + "[material]\ndensity = nan\n",
       {"material.density = nan", "must be finite and in (0, 1e+12]"}},
      {"inf literal",
       replaced(kMinimal, "time_step = 1e-4", "time_step = inf"),
       {"simulation.time_step = inf", "finite"}},
      {"missing required",
       replaced(kMinimal, "time_step = 1e-4", ""),
       {"simulation.time_step", "required key is missing"}},
      {"missing table",
       replaced(kMinimal, "[box]\nmin = [0, 0, 0]\nmax = [1, 1, 2]\n", ""),
       {"box", "required key is missing"}},
      {"bad law",
       kMinimal + "[material]\nnormal_law = \"hertzian\"\n",
       {"material.normal_law = \"hertzian\"", "did you mean 'hertz'?"}},
      {"bad integrator",
       replaced(kMinimal, "time_step", "integrator = \"rk4\"\ntime_step"),
       {"simulation.integrator = \"rk4\"", "'gear5', 'verlet'"}},
      {"gravity of 2",
       replaced(kMinimal, "time_step", "gravity = [0, -9.81]\ntime_step"),
       {"simulation.gravity = [0, -9.81]",
        "expected an array of 3 numbers, got an array of 2 values"}},
      {"bad wall name",
       replaced(kMinimal, "max = [1, 1, 2]", "max = [1, 1, 2]\nwalls = [\"x-\", \"botom\"]"),
       {"box.walls", "unknown wall 'botom'", "did you mean 'bottom'?"}},
      {"duplicate wall",
       replaced(kMinimal, "max = [1, 1, 2]", "max = [1, 1, 2]\nwalls = [\"x-\", \"x-\"]"),
       {"box.walls", "listed twice"}},
      {"box inverted",
       replaced(kMinimal, "max = [1, 1, 2]", "max = [1, -1, 2]"),
       {"box.max = [1, -1, 2]", "must exceed box.min"}},
      {"float cell count",
       replaced(kMinimal, "cells = [2, 2, 2]", "cells = [2, 2.5, 2]"),
       {"particles[0].cells[1] = 2.5", "expected an integer"}},
      {"count above capacity",
       replaced(kMinimal, "cells = [2, 2, 2]", "cells = [2, 2, 2]\ncount = 9"),
       {"particles[0].count = 9", "must be in [1, 8]"}},
      {"radius above half cell",
       replaced(kMinimal, "radius_max = 0.035", "radius_max = 0.06"),
       {"particles[0].radius_max = 0.06", "cell_size/2 = 0.05"}},
      {"radii inverted",
       replaced(kMinimal, "radius_max = 0.035", "radius_max = 0.02"),
       {"particles[0].radius_max = 0.02", "radius_min = 0.03"}},
      {"negative seed",
       replaced(kMinimal, "radius_max = 0.035", "radius_max = 0.035\nseed = -1"),
       {"particles[0].seed = -1", "must be >= 0"}},
      {"generator type",
       replaced(kMinimal, "type = \"grid\"", "type = \"grd\""),
       {"particles[0].type = \"grd\"", "did you mean 'grid'?"}},
      {"misspelt type",
       replaced(kMinimal, "type = \"grid\"", "typ = \"grid\""),
       {"particles[0].typ", "did you mean 'type'?"}},
      {"csv key on a grid",
       replaced(kMinimal, "type = \"grid\"", "type = \"grid\"\nfile = \"a.csv\""),
       {"particles[0].file", "unknown key"}},
      {"bad csv row",
       replaced(csvScene, "FILE", "bad_row.csv"),
       {"particles[0].file = \"bad_row.csv\"", "bad_row.csv:3", "row 2", "column 3 (z)",
        "not a number"}},
      {"negative csv radius",
       replaced(csvScene, "FILE", "negative.csv"),
       {"particles[0].file", "row 1", "column 4 (r)", "radius must be > 0"}},
      {"nan in csv",
       replaced(csvScene, "FILE", "nan.csv"),
       {"particles[0].file", "column 2 (y)", "finite"}},
      {"missing csv",
       replaced(csvScene, "FILE", "absent.csv"),
       {"particles[0].file = \"absent.csv\"", "cannot open"}},
      {"no particles",
       replaced(kMinimal, "[[particles]]\n" + gridKeys, ""),
       {"particles", "required key is missing"}},
      {"particles not an array of tables",
       "particles = 3\n" + replaced(kMinimal, "[[particles]]\n" + gridKeys, ""),
       {"particles = 3", "expected an array of tables"}},
      {"no stages",
       replaced(kMinimal, "[[stages]]\nmax_time = 1.0\n", ""),
       {"stages", "required key is missing"}},
      {"stage without max_time",
       replaced(kMinimal, "max_time = 1.0", "name = \"a\""),
       {"stages[0].max_time", "required key is missing"}},
      {"sustain above max",
       replaced(kMinimal, "max_time = 1.0",
                "max_time = 1.0\nkinetic_energy_below = 1\nsustain_time = 2"),
       {"stages[0].sustain_time = 2", "must be in [0, 1]"}},
      {"sustain without threshold",
       replaced(kMinimal, "max_time = 1.0", "max_time = 1.0\nsustain_time = 0.5"),
       {"stages[0].sustain_time", "kinetic_energy_below"}},
      {"boolean as string",
       replaced(kMinimal, "max_time = 1.0", "max_time = 1.0\nreset_clock = \"yes\""),
       {"stages[0].reset_clock = \"yes\"", "expected true or false"}},
      {"moving a top that is not there",
       kMinimal + "[stages.wall_velocity]\ntop = [0, 0, -0.01]\n",
       {"stages[0].wall_velocity.top", "no top wall", "place_top_wall_on_surface"}},
      {"misspelt wall to move",
       replaced(kMinimal, "max_time = 1.0", "max_time = 1.0\nplace_top_wall_on_surface = true") +
           "[stages.wall_velocity]\ntopp = [0, 0, -0.01]\n",
       {"stages[0].wall_velocity.topp", "did you mean 'top'?"}},
      {"top placed on a box with a top",
       replaced(
           replaced(kMinimal, "max = [1, 1, 2]", "max = [1, 1, 2]\nwalls = [\"bottom\", \"top\"]"),
           "max_time = 1.0", "max_time = 1.0\nplace_top_wall_on_surface = true"),
       {"stages[0].place_top_wall_on_surface", "already has a top wall"}},
      {"duplicate stage names",
       kMinimal + "[[stages]]\nname = \"stage1\"\nmax_time = 1\n",
       {"stages[1].name = \"stage1\"", "another stage"}},
      {"negative snapshot",
       kMinimal + "[output]\nsnapshots = [0.1, -0.2]\n",
       {"output.snapshots[1] = -0.2", "must be >= 0"}},
      {"negative stage snapshot",
       kMinimal + "snapshots = [-0.1]\n",
       {"stages[0].snapshots[0] = -0.1", "must be >= 0"}},
      {"zero interval",
       kMinimal + "[output]\ninterval = 0\n",
       {"output.interval = 0", "must be > 0"}},
      {"zero total mass", "total_mass = 0\n" + kMinimal, {"total_mass = 0", "must be > 0"}},
      {"time step above the engine's limit",
       replaced(kMinimal, "time_step = 1e-4", "time_step = 1e-3"),
       {"simulation.time_step = 0.001", "above the stable limit", "contact duration"}},
      {"grid below the floor",
       replaced(kMinimal, "origin = [0, 0, 0]", "origin = [0, 0, -0.1]"),
       {"particles[0].origin", "grid particle 0", "outside the box", "face bottom at z = 0 m"}},
      {"csv row outside the box",
       replaced(csvScene, "FILE", "outside.csv"),
       {"particles[0].file", "outside.csv:3", "row 2", "crosses the box face x+ at x = 1 m"}},
      {"csv rows overlapping",
       replaced(csvScene, "FILE", "overlap.csv"),
       {"particles[0].file", "overlap.csv:3", "row 2 overlaps row 1 (line 2)"}},
      {"stage of more than 1e12 steps",
       replaced(kMinimal, "max_time = 1.0", "max_time = 1e9"),
       {"stages[0].max_time = 1e+09", "at most 1e12 time steps"}},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.what);
    const std::string message = errorOf(c.text);
    EXPECT_EQ(message.rfind((dir_ / "scene.toml").string() + ":", 0), 0u) << message;
    for (const std::string& part : c.expected) {
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
    }
  }
}

TEST_F(SceneLoader, AnImpactSpeedThatOverlapsBeyondARadiusIsWarnedOfNamingTheKey) {
  // The paper's material holds a head-on impact of its 3 cm spheres up to about 12 m/s.
  const std::string declared =
      replaced(kMinimal, "time_step = 1e-4", "time_step = 1e-4\nimpact_speed = 100");
  const Scene fast = loadScene(write("scene.toml", declared));
  ASSERT_EQ(fast.warnings.size(), 1u);
  const std::string& w = fast.warnings[0];
  EXPECT_NE(w.find("scene.toml:3:1: simulation.impact_speed = 100: an impact at 100 m/s"),
            std::string::npos)
      << w;
  EXPECT_NE(w.find("whatever the time step"), std::string::npos) << w;
  EXPECT_NE(w.find("this material holds impacts up to"), std::string::npos) << w;
  EXPECT_TRUE(loadScene(write("slow.toml", replaced(declared, "= 100", "= 5"))).warnings.empty());
  // Initial speeds that imply it, without the key: the warning says where the speed comes from.
  const Scene launched =
      loadScene(write("launched.toml", replaced(kMinimal, "radius_max = 0.035",
                                                "radius_max = 0.035\nspeed_max = 40")));
  ASSERT_EQ(launched.warnings.size(), 1u);
  EXPECT_NE(launched.warnings[0].find("initial speeds, fall height and wall speeds let a particle"),
            std::string::npos)
      << launched.warnings[0];
}

TEST_F(SceneLoader, ABedThatSinksThroughItsFloorAtRestIsWarnedOf) {
  const fs::path paper = fs::path(GRANULAR_SOURCE_DIR) / "assets/scenes/paper-mu0.toml";
  const Scene shipped = loadScene(paper);
  EXPECT_TRUE(shipped.warnings.empty()) << shipped.warnings.front();
  // E/100: the paper's bed presses its bottom spheres several radii into the floor at rest.
  std::string soft = testing::readFile(paper);
  soft = replaced(soft, "youngs_modulus = 0.3e6", "youngs_modulus = 0.3e4");
  soft = replaced(soft, "shear_modulus = 0.11e6", "shear_modulus = 0.11e4");
  soft = replaced(soft, "time_step = 1.7e-4", "time_step = 1.2e-3");
  const Scene sinking = loadScene(write("soft.toml", soft));
  bool found = false;
  for (const std::string& w : sinking.warnings) {
    found = found ||
            (w.find("material.youngs_modulus = 3000: at rest on the floor") != std::string::npos &&
             w.find("sink through the floor") != std::string::npos);
  }
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace granular
