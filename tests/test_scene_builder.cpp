/// Tests of the scene builder: the grid generator (reproducible, counts, ranges, placement), the
/// particle checks (outside the box, overlapping: ConfigError naming the index), mass scaling,
/// CSV particles and the walls of the box.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "granular/error.hpp"
#include "granular/scene.hpp"

namespace granular {
namespace {

namespace fs = std::filesystem;

/// A box [0,1]×[0,1]×[0,2] and a 4×4×3 grid of 0.1 m cells from its floor.
Scene gridScene(std::uint64_t seed = 1) {
  Scene scene;
  scene.box.min = Vec3(0, 0, 0);
  scene.box.max = Vec3(1, 1, 2);
  GridGenerator grid;
  grid.origin = Vec3(0, 0, 0);
  grid.cellSize = 0.1;
  grid.cells = {4, 4, 3};
  grid.count = 40;
  grid.radiusMin = 0.03;
  grid.radiusMax = 0.035;
  grid.speedMax = 0.3;
  grid.seed = seed;
  scene.generators.push_back(grid);
  return scene;
}

/// The ConfigError message of building the particles, or a failure if they build.
std::string builderError(const Scene& scene) {
  try {
    buildParticles(scene);
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no ConfigError";
  return {};
}

/// A CSV file in the temporary folder, removed at the end of the test.
class CsvFile {
 public:
  CsvFile(const std::string& name, const std::string& text)
      : path_(fs::temp_directory_path() /
              ("granular_builder_" + std::to_string(::getpid()) + "_" + name)) {
    std::ofstream(path_) << text;
  }
  ~CsvFile() { fs::remove(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

Scene csvScene(const fs::path& path) {
  Scene scene;
  scene.box.min = Vec3(0, 0, 0);
  scene.box.max = Vec3(1, 1, 1);
  scene.generators.push_back(CsvGenerator{path, {}});
  return scene;
}

TEST(SceneBuilder, GridIsReproducibleFromTheSeed) {
  const Particles a = buildParticles(gridScene(5));
  const Particles b = buildParticles(gridScene(5));
  const Particles c = buildParticles(gridScene(6));
  ASSERT_EQ(a.size(), b.size());
  bool differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.position[i], b.position[i]);
    EXPECT_EQ(a.radius[i], b.radius[i]);
    EXPECT_EQ(a.velocity[i], b.velocity[i]);
    differs = differs || a.radius[i] != c.radius[i];
  }
  EXPECT_TRUE(differs) << "another seed gave the same radii";
}

TEST(SceneBuilder, GridCountPlacementAndRanges) {
  const Scene scene = gridScene();
  const Particles p = buildParticles(scene);
  ASSERT_EQ(p.size(), 40u);
  for (std::size_t k = 0; k < p.size(); ++k) {
    // x fastest, then y, then z; particles at cell centres.
    const Vec3 centre =
        (Vec3(double(k % 4), double((k / 4) % 4), double(k / 16)) + Vec3::Constant(0.5)) * 0.1;
    EXPECT_NEAR((p.position[k] - centre).norm(), 0.0, 1e-15) << k;
    EXPECT_GE(p.radius[k], 0.03);
    EXPECT_LE(p.radius[k], 0.035);
    EXPECT_LE(p.velocity[k].norm(), 0.3 + 1e-15);
    const double r = p.radius[k];
    EXPECT_NEAR(p.mass[k], 500.0 * 4.0 / 3.0 * std::numbers::pi * r * r * r, 1e-15);
  }
}

TEST(SceneBuilder, GridVelocitiesAreIsotropicAndKeepRadiiWhenSpeedChanges) {
  Scene scene = gridScene();
  auto& grid = std::get<GridGenerator>(scene.generators[0]);
  grid.cells = {10, 10, 40};
  grid.count = 4000;
  scene.box.max = Vec3(1, 1, 4);
  grid.speedMax = 1.0;
  const Particles p = buildParticles(scene);
  Vec3 meanDirection = Vec3::Zero();
  double meanSpeed = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    meanDirection += p.velocity[i].normalized();
    meanSpeed += p.velocity[i].norm();
  }
  meanDirection /= double(p.size());
  meanSpeed /= double(p.size());
  // Uniform directions: each component of the mean has standard deviation 1/sqrt(3N) ≈ 0.009.
  EXPECT_LT(meanDirection.norm(), 0.05);
  EXPECT_NEAR(meanSpeed, 0.5, 0.03);  // uniform magnitude in [0, 1]

  grid.speedMax = 0.0;
  const Particles still = buildParticles(scene);
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(still.radius[i], p.radius[i]);
    EXPECT_EQ(still.velocity[i], Vec3::Zero());
  }
}

TEST(SceneBuilder, TotalMassScalesTheDensity) {
  Scene scene = gridScene();
  scene.totalMass = 3.25;
  const Particles p = buildParticles(scene);
  double mass = 0.0;
  for (double m : p.mass) mass += m;
  EXPECT_NEAR(mass, 3.25, 1e-12);
}

TEST(SceneBuilder, ParticleOutsideTheBoxNamesItsIndex) {
  const CsvFile file("outside.csv",
                     "x,y,z,r\n0.5,0.5,0.5,0.05\n0.2,0.2,0.2,0.05\n0.98,0.5,0.5,0.05\n");
  const std::string message = builderError(csvScene(file.path()));
  EXPECT_NE(message.find("particle 2 "), std::string::npos) << message;
  EXPECT_NE(message.find("x+"), std::string::npos) << message;
  EXPECT_NE(message.find("(0.98, 0.5, 0.5)"), std::string::npos) << message;
}

TEST(SceneBuilder, ParticlesMayStartAboveAnOpenTop) {
  const CsvFile file("above.csv", "x,y,z,r\n0.5,0.5,3.0,0.05\n");
  Scene scene = csvScene(file.path());
  EXPECT_EQ(buildParticles(scene).size(), 1u);
  scene.box.walls[5] = true;  // with a top wall the same particle is outside
  const std::string message = builderError(scene);
  EXPECT_NE(message.find("particle 0 "), std::string::npos) << message;
  EXPECT_NE(message.find("top"), std::string::npos) << message;
}

TEST(SceneBuilder, BelowTheFloorIsOutside) {
  Scene scene = gridScene();
  std::get<GridGenerator>(scene.generators[0]).origin = Vec3(0, 0, -0.1);
  const std::string message = builderError(scene);
  EXPECT_NE(message.find("particle 0 "), std::string::npos) << message;
  EXPECT_NE(message.find("bottom"), std::string::npos) << message;
}

TEST(SceneBuilder, OverlappingParticlesNameBothIndices) {
  const CsvFile file("overlap.csv",
                     "x,y,z,r,vx,vy,vz\n"
                     "0.2,0.2,0.2,0.05,0,0,0\n"
                     "0.5,0.5,0.5,0.05,0,0,0\n"
                     "0.8,0.8,0.8,0.05,0,0,0\n"
                     "0.5,0.5,0.59,0.05,0,0,0\n");
  const std::string message = builderError(csvScene(file.path()));
  // Both named by their index and by their line in the file (the header is line 1).
  EXPECT_NE(message.find("particle 1 (particles[0], " + file.path().string() +
                         ":3) and particle 3 (particles[0], " + file.path().string() + ":5)"),
            std::string::npos)
      << message;
}

TEST(SceneBuilder, TouchingParticlesAreAllowed) {
  const CsvFile file("touch.csv", "x,y,z,r\n0.25,0.5,0.5,0.25\n0.75,0.5,0.5,0.25\n");
  EXPECT_EQ(buildParticles(csvScene(file.path())).size(), 2u);
}

TEST(SceneBuilder, CsvRowsAndVelocities) {
  const CsvFile file(
      "rows.csv",
      "# comment\nx,y,z,r,vx,vy,vz\n\n0.2,0.3,0.4,0.05,1,-2,3\n0.6,0.6,0.6,0.1,0,0,0\n");
  const Particles p = buildParticles(csvScene(file.path()));
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p.position[0], Vec3(0.2, 0.3, 0.4));
  EXPECT_EQ(p.radius[0], 0.05);
  EXPECT_EQ(p.velocity[0], Vec3(1, -2, 3));
  EXPECT_EQ(p.radius[1], 0.1);
}

TEST(SceneBuilder, BadCsvNamesFileRowAndColumn) {
  const CsvFile file("bad.csv", "x,y,z,r\n0.2,0.3,0.4,0.05\n0.6,0.6,0.6,-0.1\n");
  const std::string message = builderError(csvScene(file.path()));
  EXPECT_NE(message.find(file.path().string() + ":3"), std::string::npos) << message;
  EXPECT_NE(message.find("row 2, column 4 (r)"), std::string::npos) << message;

  const CsvFile noHeader("noheader.csv", "0.2,0.3,0.4,0.05\n");
  EXPECT_NE(builderError(csvScene(noHeader.path())).find("header"), std::string::npos);
  const CsvFile fields("fields.csv", "x,y,z,r\n0.2,0.3,0.4\n");
  EXPECT_NE(builderError(csvScene(fields.path())).find("expected 4 fields"), std::string::npos);
}

TEST(SceneBuilder, InvalidGridIsAConfigError) {
  Scene scene = gridScene();
  std::get<GridGenerator>(scene.generators[0]).count = 49;  // 48 cells
  EXPECT_THROW(buildParticles(scene), ConfigError);
  scene = gridScene();
  std::get<GridGenerator>(scene.generators[0]).radiusMax = 0.06;  // > cell/2
  EXPECT_THROW(buildParticles(scene), ConfigError);
}

TEST(SceneBuilder, WallsPointIntoTheBox) {
  BoxSpec box;
  box.min = Vec3(-1, 0, 0.5);
  box.max = Vec3(2, 3, 4);
  box.walls = {true, true, true, true, true, true};
  const std::vector<Wall> walls = buildWalls(box);
  ASSERT_EQ(walls.size(), 6u);
  const Vec3 centre = 0.5 * (box.min + box.max);
  for (std::size_t f = 0; f < 6; ++f) {
    const Wall& w = walls[f];
    EXPECT_EQ(w.name, kBoxWallNames[f]);
    EXPECT_NEAR(w.normal.norm(), 1.0, 1e-15);
    EXPECT_GT(w.normal.dot(centre - w.point), 0.0) << w.name;  // inward
    const int axis = int(f / 2);
    EXPECT_EQ(w.point[axis], f % 2 == 0 ? box.min[axis] : box.max[axis]) << w.name;
    EXPECT_EQ(w.velocity, Vec3::Zero());
  }
  EXPECT_EQ(walls[4].normal, Vec3(0, 0, 1));   // bottom
  EXPECT_EQ(walls[5].normal, Vec3(0, 0, -1));  // top

  box.walls = BoxSpec().walls;  // open top
  const std::vector<Wall> open = buildWalls(box);
  ASSERT_EQ(open.size(), 5u);
  for (const Wall& w : open) EXPECT_NE(w.name, "top");
}

TEST(SceneBuilder, SimulationCarriesTheScaledDensity) {
  Scene scene = gridScene();
  scene.simulation.timeStep = 1e-4;
  scene.totalMass = 2.0;
  const Simulation sim = buildSimulation(scene);
  EXPECT_EQ(sim.particles().size(), 40u);
  EXPECT_EQ(sim.walls().size(), 5u);
  double volume = 0.0;
  for (double r : sim.particles().radius) volume += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  EXPECT_NEAR(sim.config().material.density, 2.0 / volume, 1e-9);
}

}  // namespace
}  // namespace granular
