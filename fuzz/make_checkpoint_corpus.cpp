/// Writes the seed corpus of fuzz_checkpoint: the payloads (the checkpoint file without its
/// frame) of a few real small checkpoints covering both integrators, both normal laws, the
/// frictional and frictionless paths, a moving wall, contacts with tangential history and the
/// caller's data. Usage: make_checkpoint_corpus OUT_DIR (fuzz/corpus/checkpoint).
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "granular/checkpoint.hpp"
#include "granular/simulation.hpp"
#include "physics_fixtures.hpp"  // the tests' falling-grid bed

using namespace granular;

namespace {

void writePayload(const Simulation& sim, const std::filesystem::path& out,
                  const std::string& appData = {}) {
  const std::filesystem::path tmp = out.string() + ".ckpt";
  writeCheckpoint(sim, tmp, 1, appData);
  std::ifstream in(tmp, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
  in.close();
  std::filesystem::remove(tmp);
  const std::size_t frame = 8 + 4 + 8 + 8, checksum = 8;
  std::ofstream(out, std::ios::binary | std::ios::trunc)
      .write(bytes.data() + frame, static_cast<std::streamsize>(bytes.size() - frame - checksum));
  std::printf("%s: %zu bytes\n", out.c_str(), bytes.size() - frame - checksum);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_checkpoint_corpus OUT_DIR\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);

  SimulationConfig frictional;
  frictional.material.friction = 0.3;
  frictional.timeStep = 1e-4;
  {  // Gear, Hooke, friction: settling with contacts and tangential springs, a moving top wall.
    Simulation sim = testing::fallingGrid(3, 2, 2, frictional, 0.3);
    sim.run(1200);
    const std::size_t top = sim.addWall(Wall{"top", Vec3(0, 0, 0.25), Vec3(0, 0, -1)});
    sim.setWallVelocity(top, Vec3(0, 0, -0.01));
    sim.run(100);
    writePayload(sim, dir / "gear-hooke-friction-top-wall", "stage=compact t=0.01");
  }
  {  // Velocity Verlet, Hertz, friction.
    SimulationConfig cfg = frictional;
    cfg.integrator = Integrator::VelocityVerlet;
    cfg.material.normalLaw = NormalLaw::Hertz;
    Simulation sim = testing::fallingGrid(2, 2, 2, cfg, 0.3);
    sim.run(800);
    writePayload(sim, dir / "verlet-hertz-friction");
  }
  {  // Gear, frictionless path (no torques, no history), freshly built.
    SimulationConfig cfg;
    cfg.timeStep = 1e-4;
    Simulation sim = testing::fallingGrid(2, 2, 1, cfg, 0.3);
    writePayload(sim, dir / "gear-frictionless-fresh");
  }
  {  // Velocity Verlet, frictionless, one sphere resting on the floor.
    SimulationConfig cfg;
    cfg.timeStep = 1e-4;
    cfg.integrator = Integrator::VelocityVerlet;
    Simulation sim = testing::fallingGrid(1, 1, 1, cfg, 0.3);
    sim.run(1000);
    writePayload(sim, dir / "verlet-frictionless-one-sphere", "x");
  }
  return 0;
}
