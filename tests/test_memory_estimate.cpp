/// The memory a scene needs, estimated before anything per particle is allocated
/// (granular/memory_estimate.hpp): the estimate must cover what a real bed's arrays hold, for
/// every model, with room for a neighbour-list rebuild; a scene beyond the machine is refused
/// at once with the estimate and what is available.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "granular/error.hpp"
#include "granular/memory_estimate.hpp"
#include "granular/output_file.hpp"
#include "granular/scene.hpp"
#include "granular_process.hpp"

namespace {

namespace fs = std::filesystem;
using namespace granular;

/// A bed of touching spheres on the floor: every particle has its full set of contacts.
Scene touchingBed(int side, Integrator integrator, double friction) {
  Scene scene;
  scene.simulation.material.friction = friction;
  scene.simulation.integrator = integrator;
  scene.simulation.timeStep = 1e-5;
  GridGenerator grid;
  grid.cells = {side, side, side};
  grid.count = std::size_t(side) * side * side;
  grid.cellSize = 0.06 * (1.0 + 1e-9);
  grid.radiusMin = grid.radiusMax = 0.03;
  scene.generators.push_back(grid);
  scene.box.max = Vec3(side * grid.cellSize, side * grid.cellSize, side * grid.cellSize + 1.0);
  scene.stages.push_back(StageSpec{});
  return scene;
}

}  // namespace

// The rebuild needs the new candidate list beside the old one for a moment (bench/CHANGELOG.md,
// "Peak through a rebuild": ≈ 75 B a particle at most); the estimate must hold the arrays and
// that, and each of its terms (friction, Gear5) must cover what that choice adds to the arrays.
TEST(MemoryEstimate, CoversTheArraysOfEveryModelWithRoomForARebuild) {
  const int side = 16;
  double arraysOf[2][2] = {}, estimateOf[2][2] = {};  // [Gear5][friction]
  for (Integrator integrator : {Integrator::VelocityVerlet, Integrator::Gear5}) {
    for (double friction : {0.0, 0.5}) {
      const Scene scene = touchingBed(side, integrator, friction);
      Simulation sim = buildSimulation(scene);
      sim.run(3);
      const double n = double(sim.particles().size());
      const double arrays = double(sim.memoryUse().total()) / n;
      const MemoryEstimate e = estimateMemory(scene);
      EXPECT_EQ(e.particles, sim.particles().size());
      EXPECT_GE(e.bytesPerParticle, arrays + 75.0)
          << e.model << ": arrays " << arrays << " B a particle";
      // Not so loose that it refuses what fits: within 2× of the arrays.
      EXPECT_LT(e.bytesPerParticle, 2.0 * arrays) << e.model;
      const int g = integrator == Integrator::Gear5, f = friction > 0;
      arraysOf[g][f] = arrays;
      estimateOf[g][f] = e.bytesPerParticle;
    }
  }
  for (int g : {0, 1}) {
    EXPECT_GE(estimateOf[g][1] - estimateOf[g][0], arraysOf[g][1] - arraysOf[g][0])
        << "what friction adds, " << (g ? "Gear5" : "Verlet");
  }
  for (int f : {0, 1}) {
    EXPECT_GE(estimateOf[1][f] - estimateOf[0][f], arraysOf[1][f] - arraysOf[0][f])
        << "what Gear5 adds, " << (f ? "frictional" : "frictionless");
  }
}

// An automatic velocity-Verlet step at rest comes from the spectrum's estimate, and its checks
// keep the state to return to (MemoryUse::rollback): the estimate covers both copies.
TEST(MemoryEstimate, CoversAnAutomaticStepsBedWithTheStateItKeeps) {
  Scene scene = touchingBed(16, Integrator::VelocityVerlet, 0.5);
  scene.simulation.step.automatic = true;
  Simulation sim = buildSimulation(scene);
  sim.run(500);  // the bed pressed together by its weight and come to rest
  const MemoryUse use = sim.memoryUse();
  ASSERT_GT(use.rollback, 0u) << "no state kept: the step did not come from the estimate";
  const double arrays = double(use.total()) / double(sim.particles().size());
  const MemoryEstimate e = estimateMemory(scene);
  EXPECT_GE(e.bytesPerParticle, arrays + 75.0) << e.model << ": arrays " << arrays;
  EXPECT_LT(e.bytesPerParticle, 2.0 * arrays) << e.model;
}

// A scene of 5·10⁷ frictional Gear5 spheres needs about 30 GB: refused at once by `granular run`
// (exit 2, one line with the estimate and the memory available), not by std::bad_alloc later.
TEST(MemoryEstimate, ASceneBeyondTheMachineIsRefusedBeforeAllocating) {
  const fs::path dir = fs::temp_directory_path() / "granular_memory_estimate";
  fs::create_directories(dir);
  const fs::path scene = dir / "huge.toml";
  std::ofstream(scene) << "[material]\nfriction = 0.3\n"
                          "[simulation]\ntime_step = 1e-4\n"
                          "[box]\nmin = [0, 0, 0]\nmax = [100, 100, 10]\n"
                          "[[particles]]\ntype = \"grid\"\norigin = [0, 0, 0]\ncell_size = 0.1\n"
                          "cells = [1000, 1000, 50]\nradius_min = 0.03\nradius_max = 0.03\n"
                          "[[stages]]\nmax_time = 1.0\n";
  // The arrays alone hold over 500 B a particle for this model (the test above).
  const double needs = 5e7 * 500;
  const std::uint64_t available = availableMemoryBytes();
  if (available == 0 || double(available) > needs) {
    GTEST_SKIP() << "this machine has " << available / 1000000000
                 << " GB available: the scene would fit";
  }
  granular::testing::GranularProcess run({"run", scene.string(), "--out", (dir / "out").string()},
                                         dir / "stderr.txt", {"OMP_NUM_THREADS=1"});
  ASSERT_TRUE(run.started());
  EXPECT_EQ(run.wait(), 2);
  const std::string message = run.stderrText();
  EXPECT_NE(message.find("50000000 particles need about"), std::string::npos) << message;
  EXPECT_NE(message.find("available"), std::string::npos) << message;
  EXPECT_EQ(message.find("bad_alloc"), std::string::npos) << message;
  fs::remove_all(dir);
}
