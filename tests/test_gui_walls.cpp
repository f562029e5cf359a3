/// The GUI with a scene of walls of its own (a silo): it opens without the box's walls and
/// plots what it can.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "figure_export.hpp"
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

}  // namespace
