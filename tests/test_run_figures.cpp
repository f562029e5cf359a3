/// `granular run --figures` and `granular figures RUN_DIR` on a real run of the silo scene: the
/// figures it draws (valid PNGs of their sizes, the walls' tint where the walls are), what it
/// says it could not draw, and the folders and files it refuses.
#include <gtest/gtest.h>
#include <unistd.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "force_sums.hpp"
#include "granular/render/image.hpp"
#include "granular/render/particle_figure.hpp"
#include "granular_process.hpp"
#include "run_figures.hpp"
#include "snapshot_figure.hpp"
#include "snapshot_files.hpp"

using namespace granular;
using namespace granular::app;

namespace {

namespace fs = std::filesystem;

/// The small silo run once for every test here (a fraction of a second), each test working on
/// its own copy.
class RunFigures : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("granular_run_figures_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    granular::testing::GranularProcess run(
        {"run", std::string(GRANULAR_SOURCE_DIR) + "/tests/scenes/run-figures-silo.toml", "--out",
         (root_ / "silo").string(), "--quiet", "--figures", "--checkpoint-every", "0"},
        root_ / "run.stderr");
    status_ = run.wait();
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }

  void SetUp() override {
    ASSERT_EQ(status_, 0) << granular::testing::readFile(root_ / "run.stderr");
  }

  /// A copy of the run folder, for a test that changes it.
  fs::path copy(const std::string& name) const {
    const fs::path to = root_ / name;
    fs::remove_all(to);
    fs::copy(root_ / "silo", to, fs::copy_options::recursive);
    return to;
  }

  static fs::path root_;
  static int status_;
};
fs::path RunFigures::root_;
int RunFigures::status_ = -1;

/// `granular figures FOLDER`: its exit status and stderr.
std::pair<int, std::string> figuresOf(const fs::path& folder, const fs::path& stderrFile) {
  granular::testing::GranularProcess figures({"figures", folder.string()}, stderrFile);
  const int status = figures.wait();
  return {status, figures.stderrText()};
}

TEST_F(RunFigures, TheRunDrawsEveryFigureAsAValidImageOfItsSize) {
  const fs::path figures = root_ / "silo" / "figures";
  const std::vector<SnapshotFiles> snapshots = listSnapshots(root_ / "silo");
  ASSERT_FALSE(snapshots.empty());
  for (const char* plot :
       {"energies.png", "kinetic_energy.png", "wall_reactions.png", "contacts.png"}) {
    SCOPED_TRACE(plot);
    const render::Image image = render::readPng(figures / plot);
    EXPECT_EQ(image.width, 1200);
    EXPECT_EQ(image.height, 750);
  }
  for (const SnapshotFiles& s : snapshots) {
    SCOPED_TRACE(s.name);
    const render::Image image = render::readPng(figures / ("particles_" + s.name + ".png"));
    EXPECT_EQ(image.width, 1100);
    // The silo is 7 times taller than wide: the tallest the figure goes.
    EXPECT_EQ(image.height, 1800);
  }
  const render::Image pressure =
      render::readPng(figures / ("wall_pressure_" + snapshots.back().name + ".png"));
  EXPECT_EQ(pressure.width, 1200);
  EXPECT_EQ(pressure.height, 900);
}

// The figures' Σ|F_ij|, summed from the contacts CSV, is the engine's own force_sum_N that the
// ParaView file beside it carries.
TEST_F(RunFigures, ForceSumsFromTheContactsFileAreTheEnginesOwn) {
  const std::vector<SnapshotFiles> snapshots = listSnapshots(root_ / "silo");
  ASSERT_FALSE(snapshots.empty());
  const SnapshotFiles& s = snapshots.back();
  const CsvTable particles = readCsv(s.particles);
  const std::vector<double> sums = forceSums(readCsv(s.contacts, {"wall"}), particles.column("id"));
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((root_ / "silo/paraview" / (s.name + "_particles.vtp")).c_str());
  reader->Update();
  vtkDataArray* engine = reader->GetOutput()->GetPointData()->GetArray("force_sum_N");
  ASSERT_NE(engine, nullptr);
  ASSERT_EQ(std::size_t(engine->GetNumberOfTuples()), sums.size());
  const double largest = *std::max_element(sums.begin(), sums.end());
  ASSERT_GT(largest, 0.0);
  for (std::size_t i = 0; i < sums.size(); ++i) {
    EXPECT_NEAR(sums[i], engine->GetComponent(vtkIdType(i), 0), 1e-9 * largest) << "particle " << i;
  }
}

// Where the figure without walls shows the background, the one with them shows the walls'
// light blue over a good part of the view.
TEST_F(RunFigures, TheParticleFigureIsTintedByTheWallsWhereTheyAre) {
  const std::vector<SnapshotFiles> snapshots = listSnapshots(root_ / "silo");
  ASSERT_FALSE(snapshots.empty());
  const SnapshotData walled = readSnapshot(snapshots.back());
  ASSERT_TRUE(walled.walls);
  SnapshotData bare = walled;
  bare.walls->walls.clear();  // the same box, no walls
  render::FigureRenderer renderer;
  const render::Image withWalls = particleFigure(renderer, walled).image;
  const render::Image without = particleFigure(renderer, bare).image;
  ASSERT_EQ(withWalls.width, without.width);
  ASSERT_EQ(withWalls.height, without.height);
  long tinted = 0, background = 0;
  for (int y = 0; y < without.height; ++y) {
    for (int x = 0; x < without.width; ++x) {
      if (without.at(x, y) != render::Rgba{255, 255, 255, 255}) continue;
      ++background;
      const render::Rgba c = withWalls.at(x, y);
      tinted += int(c.b) > int(c.r) + 25;
    }
  }
  // The cylinder, 0.12 m across and 1 m tall, covers most of the 0.14 m box's view.
  EXPECT_GT(tinted, background / 10) << tinted << " of " << background;
}

TEST_F(RunFigures, WhatCannotBeDrawnIsSaidWithTheReason) {
  const fs::path run = copy("partial");
  std::vector<SnapshotFiles> snapshots = listSnapshots(run);
  ASSERT_FALSE(snapshots.empty());
  // The first snapshot without its contacts: drawn in one colour, and said so.
  fs::remove(snapshots.front().contacts);
  RunFigureSet set = drawRunFigures(run);
  ASSERT_FALSE(set.notes.empty());
  EXPECT_NE(set.notes[0].find("particles in one colour: " +
                              snapshots.front().contacts.filename().string() + " is missing"),
            std::string::npos)
      << set.notes[0];

  // No snapshots at all: the time plots, and the particle figures named as not drawn.
  for (const SnapshotFiles& s : snapshots) fs::remove(s.particles);
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(runFiguresCommand(run), 0);
  const std::string said = ::testing::internal::GetCapturedStdout();
  EXPECT_NE(said.find("wrote " + (run / "figures" / "energies.png").string()), std::string::npos)
      << said;
  EXPECT_NE(said.find("not drawn: particle figures and wall pressures (no snapshots in this run"),
            std::string::npos)
      << said;
  // The particle figures of the earlier call are gone with the snapshots they showed.
  EXPECT_FALSE(fs::exists(run / "figures" / ("particles_" + snapshots.front().name + ".png")));
}

TEST_F(RunFigures, AFolderThatIsNoRunIsRefusedNamingIt) {
  const fs::path empty = root_ / "not-a-run";
  fs::create_directories(empty);
  const auto [status, message] = figuresOf(empty, root_ / "figures.stderr");
  EXPECT_EQ(status, 1);
  EXPECT_NE(message.find(empty.string() + ": nothing to draw"), std::string::npos) << message;
  EXPECT_NE(message.find("`granular run`"), std::string::npos) << message;
  const auto [missingStatus, missing] = figuresOf(root_ / "nowhere", root_ / "figures.stderr");
  EXPECT_EQ(missingStatus, 1);
  EXPECT_NE(missing.find((root_ / "nowhere").string() + ": not a folder"), std::string::npos)
      << missing;
}

TEST_F(RunFigures, AnUnreadableTimeSeriesIsAnErrorNamingItsFileAndLine) {
  const fs::path run = copy("broken");
  std::ofstream(run / "timeseries.csv", std::ios::app) << "fill,1.5,3\n";  // cells missing
  std::ifstream in(run / "timeseries.csv");
  long lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  const auto [status, message] = figuresOf(run, root_ / "figures.stderr");
  EXPECT_EQ(status, 1);
  EXPECT_NE(message.find((run / "timeseries.csv").string() + ":" + std::to_string(lines) + ":"),
            std::string::npos)
      << message;
}

}  // namespace
