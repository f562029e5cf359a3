/// Particle CSV files (issue 21, item 4): the header's names say which field is which, in any
/// order; spin columns set the angular velocity; the bytes read are the bytes fingerprinted, and
/// a file changed between loading and building is refused. The malformed headers (unknown,
/// duplicate, missing names) are in the corpus, tests/scenes/malformed/csv-header-*.toml.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "granular/checkpoint.hpp"
#include "granular/error.hpp"
#include "granular/scene.hpp"
#include "particle_csv.hpp"
#include "temp_folder.hpp"

namespace granular {
namespace {

namespace fs = std::filesystem;

/// A fresh folder per test (temp_folder.hpp).
class ParticleCsvFile : public testing::TempFolderTest {
 protected:
  ParticleCsvFile() : TempFolderTest("granular_particle_csv") {}

  /// A scene of the box [0,1]×[0,1]×[0,2] with friction `mu` whose particles come from `csv`.
  fs::path scene(const std::string& csv, double mu = 0.0) const {
    write("particles.csv", csv);
    return write("scene.toml", "[material]\nfriction = " + std::to_string(mu) +
                                   "\n[simulation]\ntime_step = 1e-4\n"
                                   "[box]\nmin = [0, 0, 0]\nmax = [1, 1, 2]\n"
                                   "[[particles]]\ntype = \"csv\"\nfile = \"particles.csv\"\n"
                                   "[[stages]]\nmax_time = 1.0\n");
  }
};

TEST_F(ParticleCsvFile, ColumnsAreReadByTheirNamesInAnyOrder) {
  // Each row, read in the old fixed order x,y,z,r, is also a particle inside the box: a reader
  // that ignored the names would accept these files and put the particles elsewhere.
  struct Case {
    const char* text;
    Vec3 position;
    double radius;
    Vec3 velocity;
  };
  const Case cases[] = {
      {"z,y,x,r\n0.7,0.5,0.2,0.03\n", {0.2, 0.5, 0.7}, 0.03, Vec3::Zero()},
      {"r,x,y,z\n0.1,0.5,0.5,0.1\n", {0.5, 0.5, 0.1}, 0.1, Vec3::Zero()},
      {"vz,z,vy,y,vx,x,radius\n-1,0.6,2,0.3,0.5,0.4,0.05\n", {0.4, 0.3, 0.6}, 0.05, {0.5, 2, -1}},
  };
  for (const Case& c : cases) {
    const Particles p = buildParticles(loadScene(scene(c.text)));
    ASSERT_EQ(p.size(), 1u) << c.text;
    EXPECT_EQ(p.position[0], c.position) << c.text;
    EXPECT_EQ(p.radius[0], c.radius) << c.text;
    EXPECT_EQ(p.velocity[0], c.velocity) << c.text;
  }
}

TEST_F(ParticleCsvFile, SpinColumnsSetTheAngularVelocityOfAFrictionalRun) {
  const Simulation sim =
      buildSimulation(loadScene(scene("x,y,z,r,wy,wz,wx\n0.5,0.5,0.5,0.03,2,3,1\n", 0.3)));
  EXPECT_EQ(sim.particles().angularVelocity[0], Vec3(1, 2, 3));
  // Spinning in free flight (no contact yet): the kinetic energy holds the rotation, I ω²/2.
  const double inertia = sim.particles().inertia(0);
  EXPECT_DOUBLE_EQ(sim.energy().kineticRotational, 0.5 * inertia * 14.0);
}

TEST_F(ParticleCsvFile, SpinInAFrictionlessSceneIsRefusedAndZeroSpinIsNot) {
  try {
    loadScene(scene("x,y,z,r,wx,wy,wz\n0.5,0.5,0.5,0.03,0,0,10\n"));
    ADD_FAILURE() << "a spin without friction loaded";
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("particles.csv:2: row 1 spins at (wx, wy, wz) = (0, 0, 10) rad/s"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("material.friction = 0"), std::string::npos) << message;
  }
  // The builder refuses it too, for a scene made in C++.
  Scene built;
  built.box.max = Vec3(1, 1, 2);
  built.generators.push_back(CsvGenerator{dir_ / "particles.csv", {}});
  EXPECT_THROW(buildParticles(built), ConfigError);

  EXPECT_EQ(buildParticles(loadScene(scene("x,y,z,r,wx,wy,wz\n0.5,0.5,0.5,0.03,0,0,0\n"))).size(),
            1u);
}

TEST_F(ParticleCsvFile, TheHashIsOfTheValuesReadAndAByteOrderMarkIsNotAName) {
  const fs::path file = write("bom.csv", "\xEF\xBB\xBFx,y,z,r\n0.5,0.5,0.5,0.03\n");
  const ParticleCsv csv = readParticleCsv(file);
  ASSERT_EQ(csv.rows.size(), 1u);
  EXPECT_EQ(csv.rows[0].position, Vec3(0.5, 0.5, 0.5));
  // The same values in another spelling, line ends and column order: the same hash.
  const ParticleCsv same = readParticleCsv(
      write("same.csv", "# again\r\nr,z,y,x,vx,vy,vz\r\n3e-2,0.50,.5,0.5,0,0,0\r\n"));
  EXPECT_EQ(same.contentHash, csv.contentHash);
  // Another value, another hash; and the rows' order counts (it numbers the particles).
  EXPECT_NE(readParticleCsv(write("moved.csv", "x,y,z,r\n0.5,0.5,0.51,0.03\n")).contentHash,
            csv.contentHash);
  const std::string two = "x,y,z,r\n0.2,0.5,0.5,0.03\n0.5,0.5,0.5,0.04\n";
  const std::string swapped = "x,y,z,r\n0.5,0.5,0.5,0.04\n0.2,0.5,0.5,0.03\n";
  EXPECT_NE(readParticleCsv(write("two.csv", two)).contentHash,
            readParticleCsv(write("swapped.csv", swapped)).contentHash);
}

TEST_F(ParticleCsvFile, AFileChangedBetweenLoadingAndBuildingIsRefused) {
  const Scene loaded = loadScene(scene("x,y,z,r\n0.5,0.5,0.5,0.03\n"));
  write("particles.csv", "x,y,z,r\n0.4,0.5,0.5,0.03\n");
  try {
    buildSimulation(loaded);
    ADD_FAILURE() << "built from a file other than the one loaded";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("particles.csv: changed since the scene was loaded"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace granular
