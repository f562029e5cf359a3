/// The GUI's window-free parts (issue 8): the simulation thread steps exactly as the core does,
/// publishes whole snapshots, refuses bad commands with a message and leaves the run as it
/// was; the script parser and the orbit camera.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <thread>

#include "figure_export.hpp"
#include "granular/render/image.hpp"
#include "granular/stage.hpp"
#include "granular/stress.hpp"
#include "gui_script.hpp"
#include "orbit_camera.hpp"
#include "sim_runner.hpp"

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
