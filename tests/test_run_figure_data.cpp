/// What the figures of a `granular run` folder are drawn from, computed by hand on tiny inputs:
/// Σ|F_ij| from a contacts table, a wall's pressure against height, the time of a series whose
/// later stage resets its clock, and the walls drawn from a ParaView file as the window draws
/// them from the walls themselves.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>

#include "force_sums.hpp"
#include "granular/error.hpp"
#include "granular/scene.hpp"
#include "series_figures.hpp"
#include "temp_folder.hpp"
#include "vtk_snapshot.hpp"
#include "wall_cell_drawing.hpp"
#include "wall_cells.hpp"
#include "wall_drawing.hpp"
#include "wall_pressure.hpp"

using namespace granular;
using namespace granular::app;

namespace {

namespace fs = std::filesystem;

class RunFigureData : public granular::testing::TempFolderTest {
 protected:
  RunFigureData() : TempFolderTest("granular_run_figure_data") {}
};

const char* kContactHeader =
    "particle,other_particle,wall,point_x_m,point_y_m,point_z_m,overlap_m,normal_x,normal_y,"
    "normal_z,normal_force_N,normal_force_x_N,normal_force_y_N,normal_force_z_N,"
    "tangential_force_N,tangential_force_x_N,tangential_force_y_N,tangential_force_z_N,step,"
    "time_s\n";

// Three particles with ids 10, 11, 12: a pair 10-11 with F = (4, 0, -3), |F| = 5; a pair 11-12
// with F = (0, 6, 8), |F| = 10; particle 12 on the floor with F = (0, 0, 2), |F| = 2.
TEST_F(RunFigureData, ForceSumsCountAPairForBothParticlesAndAWallForItsOwn) {
  const fs::path file =
      write("contacts.csv", std::string(kContactHeader) +
                                "10,11,,0,0,0,1e-4,0,0,1,3,0,0,-3,4,4,0,0,7,0.1\n"
                                "11,12,,0,0,0,1e-4,0,1,0,6,0,6,0,8,0,0,8,7,0.1\n"
                                "12,,floor,0,0,0,1e-4,0,0,-1,2,0,0,2,0,0,0,0,7,0.1\n");
  const std::vector<double> sums = forceSums(readCsv(file, {"wall"}), {10, 11, 12});
  ASSERT_EQ(sums.size(), 3u);
  EXPECT_DOUBLE_EQ(sums[0], 5.0);
  EXPECT_DOUBLE_EQ(sums[1], 5.0 + 10.0);
  EXPECT_DOUBLE_EQ(sums[2], 10.0 + 2.0);
}

TEST_F(RunFigureData, AContactOfAParticleNotInTheSnapshotNamesTheFileAndLine) {
  const fs::path file = write("contacts.csv", std::string(kContactHeader) +
                                                  "0,1,,0,0,0,1e-4,0,0,1,1,0,0,-1,0,0,0,0,7,0.1\n"
                                                  "0,9,,0,0,0,1e-4,0,0,1,1,0,0,-1,0,0,0,0,7,0.1\n");
  try {
    forceSums(readCsv(file, {"wall"}), {0, 1});
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string() + ":3: particle 9"), std::string::npos)
        << e.what();
  }
}

TEST(RunFigurePressure, TheAreaOfAPolygonBetweenTwoHeights) {
  // A vertical square 1 m wide from z = 0 to 1 m, and a right triangle half of it.
  const std::vector<Vec3> square = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  EXPECT_NEAR(areaBetween(square, 0.25, 0.75), 0.5, 1e-12);
  EXPECT_NEAR(areaBetween(square, -1.0, 0.5), 0.5, 1e-12);
  EXPECT_NEAR(areaBetween(square, 2.0, 3.0), 0.0, 1e-12);
  const std::vector<Vec3> triangle = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
  // Below z = 0.5 the triangle is a trapezium of width 1 to 0.5: area 0.375.
  EXPECT_NEAR(areaBetween(triangle, 0.0, 0.5), 0.375, 1e-12);
}

TEST(RunFigurePressure, EachBandIsItsContactsPushOverTheWallsAreaInIt) {
  // A wall 1 m wide and 2 m tall in two cells; bands 1 m high: 3 N in the lower, 1 N + 1 N in
  // the upper.
  WallCells wall;
  wall.name = "side";
  wall.shape = 1;
  wall.cells = {{{0, 0, 0}, {1, 0, 0}, {1, 0, 1.2}, {0, 0, 1.2}},
                {{0, 0, 1.2}, {1, 0, 1.2}, {1, 0, 2}, {0, 0, 2}}};
  WallContacts contacts{{0.5, 1.5, 1.7}, {3.0, 1.0, 1.0}};
  const std::vector<PressureBand> bands = pressureProfile(wall, contacts, 1.0);
  ASSERT_EQ(bands.size(), 2u);
  EXPECT_NEAR(bands[0].z, 0.5, 1e-12);
  EXPECT_NEAR(bands[0].pressure, 3.0, 1e-12);
  EXPECT_EQ(bands[0].contacts, 1);
  EXPECT_NEAR(bands[1].z, 1.5, 1e-12);
  EXPECT_NEAR(bands[1].pressure, 2.0, 1e-12);

  // A horizontal disc-like square of 4 m² is one band at its height.
  WallCells floor;
  floor.shape = 2;
  floor.cells = {{{0, 0, 0.3}, {2, 0, 0.3}, {2, 2, 0.3}, {0, 2, 0.3}}};
  const std::vector<PressureBand> flat = pressureProfile(floor, {{0.31, 0.31}, {2.0, 6.0}}, 0.1);
  ASSERT_EQ(flat.size(), 1u);
  EXPECT_NEAR(flat[0].z, 0.3, 1e-12);
  EXPECT_NEAR(flat[0].pressure, 2.0, 1e-12);
}

TEST_F(RunFigureData, AStageThatResetsItsClockContinuesFromTheStageBefore) {
  const fs::path file = write("timeseries.csv",
                              "stage,time_s,step,kinetic_translational_J,kinetic_rotational_J\n"
                              "settle,0,0,1,0\nsettle,0.5,5,1,0\ncompact,0,6,1,0\n"
                              "compact,0.25,9,1,0\n");
  const RunSeries series = readRunSeries(file);
  ASSERT_EQ(series.time.size(), 4u);
  EXPECT_EQ(series.time, (std::vector<double>{0, 0.5, 0.5, 0.75}));
  EXPECT_TRUE(series.clockJoined);
  ASSERT_EQ(series.stageStarts.size(), 1u);
  EXPECT_EQ(series.stageStarts[0].stage, "compact");
  EXPECT_EQ(series.stageStarts[0].time, 0.5);
}

/// Segments as sets of rounded end points in either order, to compare two drawings.
std::set<std::pair<std::array<long, 3>, std::array<long, 3>>> segmentSet(
    const std::vector<render::Segment>& segments) {
  auto key = [](const Vec3& x) {
    return std::array<long, 3>{std::lround(x.x() * 1e7), std::lround(x.y() * 1e7),
                               std::lround(x.z() * 1e7)};
  };
  std::set<std::pair<std::array<long, 3>, std::array<long, 3>>> out;
  for (const auto& [a, b] : segments) out.insert(std::minmax(key(a), key(b)));
  return out;
}

// The figures draw the walls from the ParaView file; the window draws them from the walls:
// the same triangles and the same outlines, for a cylinder and a disc, a cone and a mesh.
TEST_F(RunFigureData, WallsFromTheParaviewFileAreDrawnAsTheWindowDrawsThem) {
  for (const char* name : {"silo.toml", "hopper.toml", "mesh-bin.toml"}) {
    SCOPED_TRACE(name);
    const Scene scene = loadScene(fs::path(GRANULAR_SOURCE_DIR) / "assets/scenes" / name);
    const Simulation sim = buildSimulation(scene);
    const fs::path file = dir_ / "walls.vtp";
    writeWallsVtp(file, sim, scene.box.min, scene.box.max);
    const SnapshotWalls read = readSnapshotWalls(file);
    EXPECT_EQ(read.boxMin, scene.box.min);
    EXPECT_EQ(read.boxMax, scene.box.max);
    ASSERT_EQ(read.walls.size(), sim.walls().size());
    for (std::size_t w = 0; w < read.walls.size(); ++w) {
      EXPECT_EQ(read.walls[w].name, sim.walls()[w].name);
      EXPECT_EQ(read.walls[w].shape, int(sim.walls()[w].shape));
    }
    const CellDrawing fromFile = cellDrawing(read.walls);
    const gui::WallDrawing fromWalls = gui::wallDrawing(sim.walls());
    EXPECT_EQ(fromFile.triangles.size(), fromWalls.triangles.size());
    ASSERT_FALSE(fromWalls.outlines.empty());
    EXPECT_EQ(segmentSet(fromFile.outlines), segmentSet(fromWalls.outlines));
  }
}

TEST_F(RunFigureData, AWallsFileWithoutTheBoxIsRefusedNamingIt) {
  const fs::path file = write("walls.vtp", "<VTKFile type=\"PolyData\"></VTKFile>\n");
  try {
    readSnapshotWalls(file);
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

}  // namespace
