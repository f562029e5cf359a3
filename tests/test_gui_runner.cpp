/// The GUI's window-free parts (issue 8): the simulation thread steps exactly as the core does,
/// publishes whole snapshots, refuses bad commands with a message and leaves the run as it
/// was; the script parser and the orbit camera.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <thread>

#include "figure_export.hpp"
#include "granular/render/image.hpp"
#include "granular/stage.hpp"
#include "granular/stress.hpp"
#include "gui_script.hpp"
#include "orbit_camera.hpp"
#include "sim_runner.hpp"
#include "status_line.hpp"

using namespace granular;
using namespace granular::gui;

namespace {

const std::filesystem::path kDemo =
    std::filesystem::path(GRANULAR_SOURCE_DIR) / "assets/scenes/demo.toml";

Snapshot latest(SimRunner& runner) {
  runner.flush();
  Snapshot s;
  runner.latest(s);
  return s;
}

}  // namespace

TEST(GuiRunner, StepsExactlyAsTheCoreDoes) {
  SimRunner runner(kDemo);
  runner.setStepsPerUpdate(130);  // not a divisor of the steps asked: the last update is short
  runner.step(1200);              // 0.2 s: the spheres have landed
  runner.flush();
  Snapshot s;
  for (int k = 0; k < 2000 && s.steps < 1200; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    runner.latest(s);
  }
  ASSERT_EQ(s.steps, 1200u);
  EXPECT_FALSE(s.running);

  Scene scene = loadScene(kDemo);
  Simulation direct = buildSimulation(scene);
  beginStage(direct, scene.stages.front());
  direct.run(1200);
  ASSERT_EQ(s.centres.size(), direct.particles().size());
  EXPECT_EQ(s.radii.size(), s.centres.size());
  EXPECT_EQ(s.forceSum.size(), s.centres.size());
  for (std::size_t i = 0; i < s.centres.size(); ++i) {
    EXPECT_EQ(s.centres[i], direct.particles().position[i]) << "particle " << i;
  }
  EXPECT_DOUBLE_EQ(s.time, direct.time());

  // Per-particle σ33 times the particle's volume sums to the box's Eq. (1) σ33 times its volume:
  // both are Σ_c F_z (C_z - z_i) over every contact.
  ASSERT_EQ(s.stress33.size(), s.centres.size());
  double sum = 0;
  for (std::size_t i = 0; i < s.radii.size(); ++i) {
    sum += s.stress33[i] * 4.0 / 3.0 * std::numbers::pi * std::pow(s.radii[i], 3);
  }
  const double volume = 1.0;
  const double eq1 = volumeAveragedStress(direct, volume)(2, 2) * volume;
  EXPECT_LT(eq1, 0.0);  // the bed has landed: compression
  EXPECT_NEAR(sum, eq1, 1e-9 * std::abs(eq1));
}

// The colourings by σ33 and by Σ|F| are the analysis layer's per-particle measures, bit for bit:
// one definition for the window, the ParaView snapshots and the figures.
TEST(GuiRunner, PerParticleColoursAreTheAnalysisLayersMeasures) {
  SimRunner runner(kDemo);
  runner.setStepsPerUpdate(1000);
  runner.step(6000);  // 1 s: the spheres have fallen and press on each other in a bed
  Snapshot s;
  for (int k = 0; k < 4000 && s.steps < 6000; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    runner.latest(s);
  }
  ASSERT_EQ(s.steps, 6000u);

  Scene scene = loadScene(kDemo);
  Simulation direct = buildSimulation(scene);
  beginStage(direct, scene.stages.front());
  direct.run(6000);
  ASSERT_EQ(s.centres, direct.particles().position);  // the same state
  const std::vector<Mat3> stresses = particleStresses(direct);
  const std::vector<double> sums = particleForceSums(direct);
  ASSERT_EQ(s.stress33.size(), stresses.size());
  ASSERT_EQ(s.forceSum.size(), sums.size());
  std::size_t compressed = 0;
  for (std::size_t i = 0; i < stresses.size(); ++i) {
    EXPECT_EQ(s.stress33[i], stresses[i](2, 2)) << "particle " << i;
    EXPECT_EQ(s.forceSum[i], sums[i]) << "particle " << i;
    compressed += stresses[i](2, 2) < 0;
  }
  // A bed under its own weight, not a cloud in free flight: (nearly) every sphere is pressed.
  EXPECT_GT(compressed, stresses.size() * 9 / 10);
}

TEST(GuiRunner, ExportsTheFiguresOfTheRunOnScreen) {
  SimRunner runner(kDemo);
  runner.setStepsPerUpdate(200);
  runner.step(600);
  Snapshot s;
  for (int k = 0; k < 2000 && s.steps < 600; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    runner.latest(s);
  }
  const auto folder = std::filesystem::temp_directory_path() / "granular-gui-figures-test";
  std::filesystem::remove_all(folder);
  const std::vector<std::filesystem::path> files = exportFigures(s, folder);
  ASSERT_EQ(files.size(), 6u);
  for (const auto& file : files) {
    const render::Image image = render::readPng(file);
    EXPECT_GT(image.width, 300) << file;
    long coloured = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        const render::Rgba c = image.at(x, y);
        coloured += std::max({c.r, c.g, c.b}) - std::min({c.r, c.g, c.b}) > 50;
      }
    }
    EXPECT_GT(coloured, 500) << file << ": no coloured particles or curves";
  }
  std::filesystem::remove_all(folder);
}

TEST(GuiRunner, RefusedCommandsLeaveTheRunAsItWasAndSayWhy) {
  SimRunner runner(kDemo);
  const Snapshot before = latest(runner);
  Material bad = before.material;
  bad.friction = -1;
  runner.setMaterial(bad);
  Snapshot s = latest(runner);
  EXPECT_NE(s.message.find("friction"), std::string::npos) << s.message;
  EXPECT_EQ(s.material.friction, before.material.friction);

  runner.setIntegrator(Integrator::VelocityVerlet, 10 * s.maxTimeStep);
  s = latest(runner);
  EXPECT_NE(s.message.find("stable limit"), std::string::npos) << s.message;
  EXPECT_EQ(s.integrator, before.integrator);
  EXPECT_EQ(s.timeStep, before.timeStep);

  Material rough = before.material;
  rough.friction = 0.6;
  runner.setMaterial(rough);
  EXPECT_EQ(latest(runner).material.friction, 0.6);
}

TEST(GuiRunner, DtAutoChoosesTheStepFromTheNetworkAndShowsIt) {
  // The "dt auto" box: the engine's time_step = "auto" for the run on screen, the step in use
  // and its range shown; unticked, a fixed step again.
  SimRunner runner(kDemo);
  runner.setIntegrator(Integrator::VelocityVerlet, 0.0, true);
  runner.step(400);
  Snapshot s = latest(runner);
  EXPECT_TRUE(s.automaticStep) << s.message;
  EXPECT_EQ(s.integrator, Integrator::VelocityVerlet);
  EXPECT_GT(s.smallestStep, 0.0);
  EXPECT_LE(s.timeStep, s.maxTimeStep);  // within what the network allows
  runner.setIntegrator(Integrator::VelocityVerlet, 0.5 * s.timeStep, false);
  s = latest(runner);
  EXPECT_FALSE(s.automaticStep) << s.message;
}

TEST(GuiRunner, SecondStagePlacesTheTopWallAndMovesItAtTheChosenSpeed) {
  SimRunner runner(kDemo);
  runner.setTopWallVelocity(-0.02);
  runner.startStage2();
  Snapshot s = latest(runner);
  ASSERT_EQ(s.stage, 2);
  ASSERT_TRUE(s.topWallZ.has_value());
  EXPECT_EQ(s.time, 0.0);  // the paper's stage 2 starts its own clock
  const double z0 = *s.topWallZ;
  runner.step(100);
  for (int k = 0; k < 1000 && s.steps < 100; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    runner.latest(s);
  }
  ASSERT_EQ(s.steps, 100u);
  EXPECT_NEAR(*s.topWallZ - z0, -0.02 * s.time, 1e-12);
}

TEST(GuiRunner, RunAndPauseAndCheckpointRoundTrip) {
  const auto file = std::filesystem::temp_directory_path() / "granular-gui-runner-test.ckpt";
  SimRunner runner(kDemo);
  runner.run();
  Snapshot s;
  for (int k = 0; k < 2000 && s.steps < 100; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    runner.latest(s);
  }
  runner.pause();
  s = latest(runner);
  EXPECT_FALSE(s.running);
  EXPECT_GE(s.steps, 100u);
  runner.saveCheckpoint(file);
  const Snapshot saved = latest(runner);
  runner.step(40);
  for (int k = 0; k < 1000 && s.steps < saved.steps + 40; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    runner.latest(s);
  }
  runner.loadCheckpoint(file);
  s = latest(runner);
  EXPECT_EQ(s.steps, saved.steps);
  EXPECT_EQ(s.centres, saved.centres);
  std::filesystem::remove(file);
}

TEST(GuiScript, ParsesCommandsAndRefusesMistakesByName) {
  const auto c = parseScript("run; wait-steps 300 ;mu 0.5;; colour speed; screenshot a.png; quit");
  ASSERT_EQ(c.size(), 6u);
  EXPECT_EQ(c[1].verb, "wait-steps");
  EXPECT_EQ(c[1].argument, "300");
  EXPECT_EQ(c[4].argument, "a.png");
  auto refusal = [](const std::string& text) {
    try {
      parseScript(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal("jump 3").find("unknown command 'jump'"), std::string::npos);
  EXPECT_NE(refusal("mu lots").find("'mu' needs a number"), std::string::npos);
  EXPECT_NE(refusal("colour pink").find("expected force, speed, stress or none"),
            std::string::npos);
  EXPECT_NE(refusal("run now").find("takes no argument"), std::string::npos);
}

TEST(GuiCamera, StartsAtTheFiguresFramingAndZoomsAndOrbitsAboutTheTarget) {
  const Vec3 lo(0, 0, 0), hi(0.5, 0.5, 1.0);
  OrbitCamera orbit;
  const render::Camera start = orbit.camera(lo, hi, 1.5);
  const render::Camera fitted =
      render::fitCamera(lo, hi, orbit.azimuthDeg, orbit.elevationDeg, 30.0, 1.5);
  EXPECT_LT((start.eye - fitted.eye).norm(), 1e-12);
  orbit.zoomBy(5);  // 1.15^5 closer
  const render::Camera zoomed = orbit.camera(lo, hi, 1.5);
  EXPECT_NEAR((zoomed.eye - zoomed.target).norm() * std::pow(1.15, 5),
              (start.eye - start.target).norm(), 1e-9);
  orbit.orbit(200, -50);  // about the box centre, framed anew from the new direction
  const render::Camera turned = orbit.camera(lo, hi, 1.5);
  EXPECT_LT((turned.target - zoomed.target).norm(), 1e-12);
  EXPECT_GT((turned.eye - zoomed.eye).norm(), 0.1);
  orbit.pan(100, 0, 500);  // the target moves sideways, the eye with it
  const render::Camera panned = orbit.camera(lo, hi, 1.5);
  EXPECT_GT((panned.target - turned.target).norm(), 0.01);
  EXPECT_NEAR((panned.eye - panned.target).norm(), (turned.eye - turned.target).norm(), 1e-9);
  orbit.reset();
  EXPECT_LT((orbit.camera(lo, hi, 1.5).eye - start.eye).norm(), 1e-12);
}

namespace {

/// Steps `count` more and waits until the window's snapshot shows them (or the run stopped).
Snapshot stepAndWait(SimRunner& runner, int count) {
  Snapshot s = latest(runner);
  const std::uint64_t target = s.steps + std::uint64_t(count);
  runner.step(count);
  for (int k = 0; k < 4000 && s.steps < target; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    runner.latest(s);
  }
  return latest(runner);
}

/// The reduced paper scene with a drift limit no integrator meets (10⁻¹²: round-off of a bed
/// with contacts) and `action` on a failed check.
std::filesystem::path unreachableDriftScene(const std::string& action) {
  std::ifstream in(std::filesystem::path(GRANULAR_SOURCE_DIR) /
                   "tests/scenes/reduced-compaction.toml");
  std::string scene{std::istreambuf_iterator<char>(in), {}};
  const std::string output = "[output]\ninterval = 0.01\n";
  scene.replace(scene.find(output), output.size(),
                output + "energy_drift_limit = 1e-12\non_failed_check = \"" + action + "\"\n");
  const auto file =
      std::filesystem::temp_directory_path() / ("granular-gui-run-checks-" + action + ".toml");
  std::ofstream(file) << scene;
  return file;
}

}  // namespace

// The window's run checks itself at every output interval as `granular run` does, and its status
// line says what failed, in the words of the check; "stop" pauses the run there and says it once.
TEST(GuiRunner, AFailedRunCheckIsOnTheStatusLine) {
  const std::filesystem::path warnScene = unreachableDriftScene("warn"),
                              stopScene = unreachableDriftScene("stop");
  {
    SimRunner runner(warnScene);
    runner.setStepsPerUpdate(50);
    const Snapshot s = stepAndWait(runner, 400);  // 0.068 s: six output intervals
    ASSERT_EQ(s.failedChecks.size(), 1u);
    EXPECT_NE(s.failedChecks[0].find("energy balance drifted by "), std::string::npos)
        << s.failedChecks[0];
    EXPECT_NE(s.failedChecks[0].find("(stage settle)"), std::string::npos) << s.failedChecks[0];
    EXPECT_EQ(failedCheckStatus(s), "run check failed: " + s.failedChecks[0]);
  }
  {
    SimRunner runner(stopScene);
    runner.setStepsPerUpdate(50);
    runner.run();
    Snapshot s;
    for (int k = 0; k < 4000 && (s.steps == 0 || s.running); ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      runner.latest(s);
    }
    s = latest(runner);
    EXPECT_FALSE(s.running);
    ASSERT_EQ(s.failedChecks.size(), 1u);
    EXPECT_EQ(s.message, s.failedChecks[0]);
    EXPECT_EQ(failedCheckStatus(s).rfind("run check failed: energy balance drifted by ", 0), 0u);
    EXPECT_EQ(statusLine(s, 60).find("drifted"), std::string::npos) << statusLine(s, 60);
  }
  std::filesystem::remove(warnScene);
  std::filesystem::remove(stopScene);
  // The demo bed at its own limit (5 %) passes, also after its stiffness is raised a hundredfold
  // mid-run: the elastic energy that adds without work is the new material's, not a drift.
  SimRunner runner(kDemo);
  runner.setStepsPerUpdate(200);
  Snapshot s = stepAndWait(runner, 3000);
  ASSERT_EQ(s.steps, 3000u);
  ASSERT_GT(s.particleContacts, 0u);
  EXPECT_TRUE(s.failedChecks.empty()) << s.failedChecks.front();
  Material stiff = s.material;
  stiff.youngModulus *= 100;
  runner.setIntegrator(s.integrator, 0.1 * s.timeStep);  // the contacts' shorter time
  runner.setMaterial(stiff);
  s = stepAndWait(runner, 1000);
  ASSERT_EQ(s.steps, 4000u);
  EXPECT_EQ(s.material.youngModulus, stiff.youngModulus) << s.message;
  EXPECT_TRUE(s.failedChecks.empty()) << s.failedChecks.front();
  EXPECT_EQ(failedCheckStatus(s), "");
  EXPECT_NE(statusLine(s, 60).find("energy balance"), std::string::npos);
}
