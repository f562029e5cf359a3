/// Checkpoints: a restarted run continues bit for bit; damaged files are refused clearly.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "granular/checkpoint.hpp"
#include "granular/error.hpp"
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
  cfg.timeStep = 1.5e-4;
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
    ASSERT_GT(first.energy().of("elastic_tangential_J"), 0.0);
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
  // Not a checkpoint problem but an I/O one (exit status 1), still naming the file.
  auto expectIoError = [](const std::filesystem::path& path, const char* phrase) {
    try {
      readCheckpoint(path, 7);
      ADD_FAILURE() << "read " << path << " as a checkpoint";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
  };
  expectIoError(file, "No such file");
  std::filesystem::create_directory(file);  // a folder where the checkpoint should be
  expectIoError(file, "it is a folder");
  std::filesystem::remove(file);
  // A device is never read (an endless one like /dev/zero would be read until memory ran out).
  expectIoError("/dev/zero", "not a regular file");
}

// A file that claims to be a checkpoint is read only once its size matches its header: a length
// field corrupted to 2^62 is refused before anything of that size is allocated.
TEST(Checkpoint, AnAnnouncedPayloadLargerThanTheFileIsRefusedBeforeReading) {
  Simulation sim = fallingGrid(2, 2, 2, frictionalGear(), 0.3);
  const auto file = tempFile("huge-header.ckpt");
  writeCheckpoint(sim, file, 7);
  const std::uint64_t claimed = 1ULL << 62;
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(8 + 4 + 8);  // magic, version, fingerprint: the payload length follows
    f.write(reinterpret_cast<const char*>(&claimed), sizeof claimed);
  }
  try {
    readCheckpoint(file, 7);
    ADD_FAILURE() << "accepted a checkpoint announcing a 2^62-byte payload";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("4611686018427387904-byte payload"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(file);
}

TEST(Checkpoint, CallersDataTravelsWithTheState) {
  SimulationConfig cfg;  // frictionless, velocity Verlet: no rotations, no springs
  cfg.integrator = Integrator::VelocityVerlet;
  cfg.timeStep = 1.5e-4;
  Simulation sim = fallingGrid(3, 3, 2, cfg, 0.3);
  sim.run(300);
  const auto file = tempFile("appdata.ckpt");
  const std::string data("stage 2\0progress", 16);  // any bytes, a NUL included
  writeCheckpoint(sim, file, 5, data);
  CheckpointContents restored = readCheckpointWithData(file, 5);
  EXPECT_EQ(restored.appData, data);
  EXPECT_EQ(restored.simulation.stateHash(), sim.stateHash());
  sim.run(300);
  restored.simulation.run(300);
  EXPECT_EQ(restored.simulation.stateHash(), sim.stateHash());
  std::filesystem::remove(file);
}

TEST(Checkpoint, BrokenStateIsNeverWritten) {
  Simulation sim = fallingGrid(2, 2, 2, frictionalGear(), 0.3);
  const auto file = tempFile("broken.ckpt");
  writeCheckpoint(sim, file, 3);
  const std::uint64_t good = fingerprintFile(file);
  Particles& p = const_cast<Particles&>(sim.particles());  // as a bug would
  p.velocity[5].y() = std::numeric_limits<double>::quiet_NaN();
  try {
    writeCheckpoint(sim, file, 3);
    ADD_FAILURE() << "wrote a checkpoint of a state holding a NaN";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("particle 5: velocity"), std::string::npos) << e.what();
  }
  EXPECT_EQ(fingerprintFile(file), good);  // the good one is still there
  std::filesystem::remove(file);
}

// A corrupted payload whose checksum was recomputed (the case a checksum cannot catch: a bug
// in a writer, or a deliberate edit) must be refused, or be harmless: every 8-byte word of a
// real checkpoint is overwritten in turn with values that break counts, indices and numbers,
// and whatever is accepted must step without fault (the sanitizer build watches the memory).
TEST(Checkpoint, EveryCorruptedWordIsRefusedOrHarmless) {
  Simulation sim = fallingGrid(2, 2, 2, frictionalGear(), 0.3);
  sim.run(400);
  const auto file = tempFile("words.ckpt");
  writeCheckpoint(sim, file, 9, "progress");
  std::vector<char> bytes(std::filesystem::file_size(file));
  std::ifstream(file, std::ios::binary).read(bytes.data(), std::streamsize(bytes.size()));
  std::filesystem::remove(file);
  const std::size_t frame = 8 + 4 + 8 + 8;
  const std::size_t payload = bytes.size() - frame - 8;
  auto fnv = [](const char* d, std::size_t n) {
    std::uint64_t h = 1469598103934665603ULL;
    for (std::size_t i = 0; i < n; ++i)
      h = (h ^ static_cast<unsigned char>(d[i])) * 1099511628211ULL;
    return h;
  };
  const std::uint64_t patterns[] = {~0ULL, 0ULL, 0x7ff0000000000000ULL, 1ULL << 31,
                                    0x00000000ffffffffULL};
  std::size_t refused = 0, accepted = 0;
  for (std::size_t at = frame; at + 8 <= frame + payload; at += 8) {
    for (std::uint64_t pattern : patterns) {
      std::vector<char> damaged = bytes;
      std::memcpy(damaged.data() + at, &pattern, 8);
      const std::uint64_t sum = fnv(damaged.data() + frame, payload);
      std::memcpy(damaged.data() + frame + payload, &sum, 8);
      try {
        CheckpointContents c = parseCheckpoint(damaged, "damaged", 9);
        c.simulation.run(5);
        ++accepted;
      } catch (const CheckpointError&) {
        ++refused;
      } catch (const std::exception& e) {  // a ConfigError from the step is a clear refusal too
        ++refused;
      }
    }
  }
  EXPECT_GT(refused, 0u);
  EXPECT_GT(accepted, 0u);  // e.g. a changed velocity is a valid state
}
