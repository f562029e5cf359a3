/// The GUI with a scene of walls of its own (a silo): it opens without the box's walls and
/// plots what it can, its snapshots carry the walls where the run has them, and its exported
/// particle figures draw them.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <thread>

#include "figure_export.hpp"
#include "granular/render/image.hpp"
#include "sim_runner.hpp"

using namespace granular;
using namespace granular::gui;

namespace {

const std::filesystem::path kSilo =
    std::filesystem::path(GRANULAR_SOURCE_DIR) / "assets/scenes/silo.toml";

/// The silo after 100 steps.
Snapshot siloAfter100Steps() {
  SimRunner runner(kSilo);
  runner.setStepsPerUpdate(50);
  runner.step(100);
  Snapshot s;
  for (int k = 0; k < 2000 && s.steps < 100; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    runner.latest(s);
  }
  return s;
}

TEST(GuiWalls, ASceneWithoutTheBoxsWallsRunsAndPlotsItsKineticEnergy) {
  const Snapshot s = siloAfter100Steps();
  ASSERT_EQ(s.steps, 100u) << s.message;
  // Without the box's walls, Eq. (1) and (2) have nothing to measure; the kinetic energy does.
  EXPECT_FALSE(s.series.kinetic.empty());
  EXPECT_TRUE(s.series.eq1[2].empty());
  EXPECT_TRUE(s.series.bottomForce.empty());

  const auto folder = std::filesystem::temp_directory_path() / "granular-gui-no-box-test";
  std::filesystem::remove_all(folder);
  const std::vector<std::filesystem::path> files = exportFigures(s, folder);
  // The two particle figures and the kinetic energy; the box's plots are left out.
  ASSERT_EQ(files.size(), 3u);
  EXPECT_EQ(files[2].filename(), "kinetic_energy.png");
  std::filesystem::remove_all(folder);
}

TEST(GuiWalls, TheSnapshotCarriesTheWallsAndTheFiguresDrawThem) {
  const Snapshot s = siloAfter100Steps();
  ASSERT_EQ(s.steps, 100u) << s.message;
  // The cylinder and its floor, and no plane of the box.
  ASSERT_EQ(s.walls.size(), 2u);
  EXPECT_TRUE(std::all_of(s.walls.begin(), s.walls.end(), [](const Wall& w) { return w.shell(); }));

  const auto folder = std::filesystem::temp_directory_path() / "granular-gui-walls-test";
  std::filesystem::remove_all(folder);
  const std::vector<std::filesystem::path> withWalls = exportFigures(s, folder / "walls");
  Snapshot bare = s;
  bare.walls.clear();
  const std::vector<std::filesystem::path> without = exportFigures(bare, folder / "bare");
  ASSERT_FALSE(withWalls.empty());
  ASSERT_FALSE(without.empty());

  // Where the figure without walls shows the background, the one with them shows the wall's
  // light blue over a good part of the view.
  const render::Image walled = render::readPng(withWalls[0]);
  const render::Image plain = render::readPng(without[0]);
  ASSERT_EQ(walled.width, plain.width);
  ASSERT_EQ(walled.height, plain.height);
  long tinted = 0;
  for (int y = 0; y < plain.height; ++y) {
    for (int x = 0; x < plain.width; ++x) {
      const render::Rgba c = walled.at(x, y);
      tinted += plain.at(x, y) == render::Rgba{255, 255, 255, 255} && int(c.b) > int(c.r) + 25;
    }
  }
  EXPECT_GT(tinted, 10000);
  std::filesystem::remove_all(folder);
}

}  // namespace
