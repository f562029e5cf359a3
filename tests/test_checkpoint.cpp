/// Checkpoints: a restarted run continues bit for bit; damaged files are refused clearly.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "granular/checkpoint.hpp"
#include "physics_fixtures.hpp"

using namespace granular;
using granular::testing::fallingGrid;

namespace {

std::filesystem::path tempFile(const char* name) {
  return std::filesystem::temp_directory_path() / (std::string("granular_test_") + name);
}

SimulationConfig frictionalGear() {
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.timeStep = 2e-4;
  return cfg;
}

}  // namespace

TEST(Checkpoint, RestartContinuesBitForBit) {
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    SimulationConfig cfg = frictionalGear();
    cfg.integrator = integrator;
    // Mid-run, with contacts, tangential springs and a moving wall in play.
    Simulation first = fallingGrid(4, 4, 3, cfg, 0.3);
    first.run(1500);
    const std::size_t top = first.addWall(Wall{"top", Vec3(0, 0, 0.9), Vec3(0, 0, -1)});
    first.setWallVelocity(top, Vec3(0, 0, -0.01));
    first.run(100);
    ASSERT_GT(first.energy().elasticTangential, 0.0);
    const auto file = tempFile("restart.ckpt");
    writeCheckpoint(first, file, 42);
    Simulation restarted = readCheckpoint(file, 42);
    first.run(1500);
    restarted.run(1500);
    EXPECT_EQ(first.stateHash(), restarted.stateHash());
    EXPECT_EQ(first.time(), restarted.time());
    EXPECT_EQ(first.energy().total(), restarted.energy().total());
    EXPECT_EQ(first.walls().back().point, restarted.walls().back().point);
    std::filesystem::remove(file);
  }
}

TEST(Checkpoint, DamagedOrForeignFilesAreRefused) {
  Simulation sim = fallingGrid(3, 3, 2, frictionalGear(), 0.3);
  sim.run(500);
  const auto file = tempFile("damaged.ckpt");
  writeCheckpoint(sim, file, 7);
  EXPECT_FALSE(std::filesystem::exists(file.string() + ".tmp"));
  const auto size = std::filesystem::file_size(file);
  auto expectError = [&](const char* phrase) {
    try {
      readCheckpoint(file, 7);
      ADD_FAILURE() << "accepted a damaged checkpoint (" << phrase << ")";
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    }
  };
  EXPECT_THROW(readCheckpoint(file, 8), CheckpointError);  // another scene
  std::filesystem::resize_file(file, size - 100);
  expectError("truncated");
  writeCheckpoint(sim, file, 7);
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2));
    f.put('\x5a');
  }
  expectError("checksum");
  {
    std::ofstream f(file, std::ios::binary | std::ios::trunc);
    f << "not a checkpoint at all, just text";
  }
  expectError("not a granular checkpoint");
  std::filesystem::remove(file);
  expectError("cannot open");
}
