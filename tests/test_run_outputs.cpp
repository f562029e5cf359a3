/// What `granular run` writes at a snapshot (issue 21, item 11): files named by the step the
/// state was written at, with its exact time inside; a per-contact table whose forces are the
/// contact law's at that state (recomputed here from the particle snapshot); time-series contact
/// columns that say what they count; and a run header that prints the step in full and names
/// only contacts the scene can form.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "csv_output.hpp"
#include "granular/contact_theory.hpp"
#include "granular/scene.hpp"
#include "granular_process.hpp"
#include "run_header.hpp"

namespace granular {
namespace {

namespace fs = std::filesystem;

/// A CSV file as rows of named text fields.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::size_t column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return std::size_t(it - header.begin());
  }
  double number(std::size_t row, const std::string& name) const {
    const std::string& text = rows[row][column(name)];
    double value = std::nan("");
    std::from_chars(text.data(), text.data() + text.size(), value);
    return value;
  }
  bool has(const std::string& name) const {
    return std::find(header.begin(), header.end(), name) != header.end();
  }
  const std::string& text(std::size_t row, const std::string& name) const {
    return rows[row][column(name)];
  }
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

Table readTable(const fs::path& file) {
  Table t;
  std::ifstream in(file);
  std::string line;
  if (std::getline(in, line)) t.header = split(line);
  while (std::getline(in, line)) t.rows.push_back(split(line));
  return t;
}

constexpr double kStep = 1.5e-4;    // [s]
constexpr double kSnapshot = 0.01;  // [s]: 66.7 steps, so the snapshot is taken at step 67
constexpr double kYoung = 0.3e6;    // [Pa], the default
constexpr double kPoisson = 0.3;    // the default
constexpr double kDamping = 60.0;   // [1/s], the default γn

/// Three spheres at rest on the floor of a box, two of them stacked, pressing into their
/// contacts under gravity; two radii.
/// `stages` replaces the one stage "fall" of 0.02 s.
fs::path writeScene(const fs::path& dir, double friction,
                    const std::string& stages = "[[stages]]\nname = \"fall\"\nmax_time = 0.02\n") {
  fs::create_directories(dir);
  // Binary fractions: the stacked spheres touch exactly (0.1875 - 0.0625 = 2 × 0.0625).
  std::ofstream(dir / "spheres.csv") << "x,y,z,r\n"
                                        "0.25,0.5,0.0625,0.0625\n"
                                        "0.25,0.5,0.1875,0.0625\n"
                                        "0.75,0.5,0.046875,0.046875\n";
  std::ofstream(dir / "scene.toml")
      << "[material]\nfriction = " << friction << "\n[simulation]\ntime_step = " << kStep
      << "\n[box]\nmin = [0, 0, 0]\nmax = [1, 1, 2]\n"
         "[[particles]]\ntype = \"csv\"\nfile = \"spheres.csv\"\n"
      << stages << "[output]\nsnapshots = [" << kSnapshot << "]\n";
  return dir / "scene.toml";
}

/// Runs the real binary on the scene of `friction` in a fresh folder; the output folder.
fs::path run(const char* name, double friction, const std::string& stages = "") {
  const fs::path dir = fs::temp_directory_path() / (std::string("granular_run_outputs_") + name +
                                                    "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const fs::path scene =
      stages.empty() ? writeScene(dir, friction) : writeScene(dir, friction, stages);
  testing::GranularProcess run({"run", scene.string(), "--out", (dir / "out").string(), "-q"},
                               dir / "stderr.txt");
  EXPECT_TRUE(run.started());
  EXPECT_EQ(run.wait(), 0) << run.stderrText();
  return dir / "out";
}

/// The first step at or after the snapshot time: its number is in the names.
std::uint64_t snapshotStep() {
  return std::uint64_t(std::ceil(kSnapshot / kStep));
}

TEST(RunOutputs, SnapshotsAreNamedByTheirStepAndHoldTheirExactTime) {
  const fs::path out = run("names", 0.0);
  const std::string step = std::to_string(snapshotStep());
  ASSERT_NE(double(snapshotStep()) * kStep, kSnapshot);  // the case that needs the step
  for (const std::string& name :
       {"snapshot_fall_" + step + ".csv", "contacts_fall_" + step + ".csv",
        "paraview/fall_" + step + "_particles.vtp", "paraview/fall_" + step + "_contacts.vtp",
        "paraview/fall_" + step + "_walls.vtp"}) {
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
  for (const std::string& name :
       {"snapshot_fall_" + step + ".csv", "contacts_fall_" + step + ".csv"}) {
    const Table t = readTable(out / name);
    ASSERT_FALSE(t.rows.empty()) << name;
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      EXPECT_EQ(t.text(r, "step"), step) << name;
      EXPECT_NEAR(t.number(r, "time_s"), double(snapshotStep()) * kStep, 1e-15) << name;
    }
  }
  // The collection's time is the state's, step × Δt.
  std::ifstream pvd(out / "particles.pvd");
  const std::string collection{std::istreambuf_iterator<char>(pvd), {}};
  EXPECT_NE(
      collection.find("timestep=\"" + app::csvNumber(double(snapshotStep()) * kStep) +
                      "\" group=\"\" part=\"0\" file=\"paraview/fall_" + step + "_particles.vtp\""),
      std::string::npos)
      << collection;
  // The time series says what its contact columns count.
  const Table series = readTable(out / "timeseries.csv");
  EXPECT_TRUE(series.has("contacts_particle_overlapping"));
  EXPECT_TRUE(series.has("contacts_wall_overlapping"));
  fs::remove_all(out.parent_path());
}

/// The snapshot files of a stage, by their names' prefix.
std::vector<std::string> snapshotsOf(const fs::path& out, const std::string& stage) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(out)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("snapshot_" + stage + "_", 0) == 0) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

TEST(RunOutputs, AStageThatListsItsOwnSnapshotsWritesThoseInPlaceOfTheOutputs) {
  // "fall" lists none, "hold" lists two, "rest" lists nothing of its own: the output's one.
  const fs::path out =
      run("stage_snapshots", 0.0,
          "[[stages]]\nname = \"fall\"\nmax_time = 0.02\nsnapshots = []\n"
          "[[stages]]\nname = \"hold\"\nmax_time = 0.02\nsnapshots = [0.015, 0.0045]\n"
          "[[stages]]\nname = \"rest\"\nmax_time = 0.02\n");
  EXPECT_TRUE(snapshotsOf(out, "fall").empty());
  // Stage steps 30 and 100 after the 134 of "fall" (0.0045 / 1.5e-4 = 30, 0.015 / 1.5e-4 = 100).
  const std::uint64_t fall = std::uint64_t(std::ceil(0.02 / kStep - 1e-9));
  const std::uint64_t at[] = {fall + std::uint64_t(std::ceil(0.0045 / kStep - 1e-9)),
                              fall + std::uint64_t(std::ceil(0.015 / kStep - 1e-9))};
  EXPECT_EQ(snapshotsOf(out, "hold"),
            (std::vector<std::string>{"snapshot_hold_" + std::to_string(at[0]) + ".csv",
                                      "snapshot_hold_" + std::to_string(at[1]) + ".csv"}));
  EXPECT_EQ(snapshotsOf(out, "rest").size(), 1u);
  fs::remove_all(out.parent_path());
}

TEST(RunOutputs, ContactFileHoldsTheContactLawsForcesAtTheSnapshot) {
  const fs::path out = run("forces", 0.0);
  const std::string step = std::to_string(snapshotStep());
  const Table particles = readTable(out / ("snapshot_fall_" + step + ".csv"));
  const Table contacts = readTable(out / ("contacts_fall_" + step + ".csv"));
  auto vec = [](const Table& t, std::size_t r, const std::string& x, const std::string& y,
                const std::string& z) {
    return Vec3(t.number(r, x), t.number(r, y), t.number(r, z));
  };
  const double k = 2.0 / 3.0 * kYoung / (1.0 - kPoisson * kPoisson);
  std::map<std::string, int> kinds;
  for (std::size_t r = 0; r < contacts.rows.size(); ++r) {
    SCOPED_TRACE("contact row " + std::to_string(r + 1));
    const std::size_t i = std::size_t(contacts.number(r, "particle"));
    const bool wall = contacts.text(r, "other_particle").empty();
    const Vec3 xi = vec(particles, i, "x", "y", "z"), vi = vec(particles, i, "vx", "vy", "vz");
    const double ri = particles.number(i, "radius"), mi = particles.number(i, "mass");
    Vec3 n, vOther = Vec3::Zero();
    double h, radius, mass;
    if (wall) {
      // Only the floor (z = 0, normal +z) is reached by these spheres.
      EXPECT_EQ(contacts.text(r, "wall"), "bottom");
      n = Vec3(0, 0, -1);
      h = ri - xi.z();
      radius = ri;
      mass = mi;
    } else {
      const std::size_t j = std::size_t(contacts.number(r, "other_particle"));
      EXPECT_LT(i, j);  // a pair once
      const Vec3 xj = vec(particles, j, "x", "y", "z");
      const double rj = particles.number(j, "radius"), mj = particles.number(j, "mass");
      n = (xj - xi).normalized();
      h = ri + rj - (xj - xi).norm();
      radius = ri * rj / (ri + rj);
      mass = mi * mj / (mi + mj);
      vOther = vec(particles, j, "vx", "vy", "vz");
    }
    ++kinds[wall ? "wall" : "pair"];
    const double fn = std::max(0.0, k * radius * h + kDamping * mass * (vi - vOther).dot(n));
    const double scale = std::max(fn, 1e-3);
    EXPECT_NEAR(contacts.number(r, "overlap_m"), h, 1e-15);
    EXPECT_NEAR((vec(contacts, r, "normal_x", "normal_y", "normal_z") - n).norm(), 0.0, 1e-14);
    EXPECT_NEAR(
        (vec(contacts, r, "point_x_m", "point_y_m", "point_z_m") - (xi + (ri - h / 2) * n)).norm(),
        0.0, 1e-14);
    EXPECT_NEAR(contacts.number(r, "normal_force_N"), fn, 1e-12 * scale);
    EXPECT_NEAR(
        (vec(contacts, r, "normal_force_x_N", "normal_force_y_N", "normal_force_z_N") + fn * n)
            .norm(),
        0.0, 1e-12 * scale);
    // μ = 0: no tangential force.
    EXPECT_EQ(contacts.number(r, "tangential_force_N"), 0.0);
  }
  // Every overlap of the snapshot has its row: each overlapping pair, each sphere into the floor.
  int pairs = 0, floor = 0;
  for (std::size_t i = 0; i < particles.rows.size(); ++i) {
    const Vec3 xi = vec(particles, i, "x", "y", "z");
    const double ri = particles.number(i, "radius");
    floor += ri - xi.z() > 0 ? 1 : 0;
    for (std::size_t j = i + 1; j < particles.rows.size(); ++j) {
      const Vec3 xj = vec(particles, j, "x", "y", "z");
      pairs += ri + particles.number(j, "radius") - (xj - xi).norm() > 0 ? 1 : 0;
    }
  }
  EXPECT_GE(pairs, 1);  // the stacked spheres press on each other...
  EXPECT_GE(floor, 1);  // ...and on the floor
  EXPECT_EQ(kinds["pair"], pairs);
  EXPECT_EQ(kinds["wall"], floor);
  fs::remove_all(out.parent_path());
}

TEST(RunOutputs, WithFrictionTheTangentialForceLiesInThePlaneUnderTheCoulombCap) {
  const fs::path out = run("friction", 0.3);
  const Table contacts =
      readTable(out / ("contacts_fall_" + std::to_string(snapshotStep()) + ".csv"));
  ASSERT_FALSE(contacts.rows.empty());
  for (std::size_t r = 0; r < contacts.rows.size(); ++r) {
    const Vec3 n(contacts.number(r, "normal_x"), contacts.number(r, "normal_y"),
                 contacts.number(r, "normal_z"));
    const Vec3 ft(contacts.number(r, "tangential_force_x_N"),
                  contacts.number(r, "tangential_force_y_N"),
                  contacts.number(r, "tangential_force_z_N"));
    const double fn = contacts.number(r, "normal_force_N");
    EXPECT_NEAR(ft.dot(n), 0.0, 1e-12 * std::max(fn, 1e-3));
    EXPECT_NEAR(ft.norm(), contacts.number(r, "tangential_force_N"), 1e-12 * std::max(fn, 1e-3));
    EXPECT_LE(ft.norm(), 0.3 * fn * (1 + 1e-12));
  }
  fs::remove_all(out.parent_path());
}

/// One Hertz sphere above the floor, no pair possible: the stiffest contact the radii allow (two
/// such spheres) is one the scene cannot form.
TEST(RunOutputs, HeaderPrintsTheStepInFullAndOnlyContactsTheSceneCanForm) {
  Scene scene;
  scene.simulation.material.normalLaw = NormalLaw::Hertz;
  scene.box.max = Vec3(1, 1, 2);
  GridGenerator one;
  one.origin = Vec3(0.45, 0.45, 0.0);
  one.count = 1;
  scene.generators.push_back(one);
  scene.stages.push_back(StageSpec{});
  const double limit =
      maxStableStep(stiffestContact(scene.simulation.material, 0.03, 1.0), Integrator::Gear5);
  scene.simulation.timeStep = limit / 3.0;  // a number with all 17 digits
  const Simulation sim = buildSimulation(scene);
  ASSERT_FALSE(sim.contactScale().againstWall);  // Hertz: a pair is stiffer than a wall contact
  std::ostringstream header;
  app::printHeader(header, scene, sim, "out");
  const std::string text = header.str();
  EXPECT_EQ(text.find("stiffest particle-particle"), std::string::npos) << text;
  EXPECT_NE(text.find("contact     particle-wall contacts only; the step limit uses a "
                      "particle-particle contact, which this scene cannot form"),
            std::string::npos)
      << text;
  const std::string printed = text.substr(text.find("dt = ") + 5);
  double dt = 0;
  std::from_chars(printed.data(), printed.data() + printed.size(), dt);
  EXPECT_EQ(dt, scene.simulation.timeStep) << text;
}

TEST(RunOutputs, HeaderAtAnAutomaticStepStatesTheFloorItPrints) {
  // Gear5 keeps its own t_c/50 below contact_resolution's t_c/10: the header names the fraction
  // whose value it prints. Verlet's floor is contact_resolution's.
  for (const Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    Scene scene;
    scene.box.max = Vec3(1, 1, 2);
    GridGenerator one;
    one.origin = Vec3(0.45, 0.45, 0.0);
    one.count = 1;
    scene.generators.push_back(one);
    scene.stages.push_back(StageSpec{});
    scene.simulation.integrator = integrator;
    scene.simulation.step.automatic = true;
    const Simulation sim = buildSimulation(scene);
    std::ostringstream header;
    app::printHeader(header, scene, sim, "out");
    const std::string text = header.str();
    const bool gear = integrator == Integrator::Gear5;
    const std::string fraction = gear ? "duration/50 = " : "duration/10 = ";
    const std::size_t at = text.find(fraction);
    ASSERT_NE(at, std::string::npos) << text;
    const double printed = std::stod(text.substr(at + fraction.size()));
    const double duration = sim.contactScale().duration;
    EXPECT_NEAR(printed, duration / (gear ? 50.0 : 10.0), 1e-3 * printed) << text;
  }
}

}  // namespace
}  // namespace granular
