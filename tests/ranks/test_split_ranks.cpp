/// A run split by space (Simulation::splitAmong): each rank holds the particles of its brick and
/// their ghosts, the particles move between ranks with their springs at the neighbour-list
/// rebuilds, and the whole state, gathered, is one process's to the bit: its checkpoint file,
/// byte for byte (positions, velocities, spins, the integrator's derivatives, the springs, the
/// neighbour list, the ledger, the counters), on 1-4 ranks, both integrators, with and without
/// friction, a moving wall, a fixed and an automatic step, and liquid bridges that pull across
/// gaps (pairs beyond the contacts' reach, whose partners the halo must still hold), and a floor
/// that is a turning plate, flat or of triangles.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "granular/bricks.hpp"
#include "granular/checkpoint.hpp"
#include "granular/engine_studies.hpp"
#include "granular/network_spectrum.hpp"
#include "granular/packings.hpp"
#include "granular/scene.hpp"
#include "granular/simulation.hpp"
#include "granular/wall_mesh.hpp"
#include "mesh_fixtures.hpp"
#include "ranks.hpp"
#include "same_sums.hpp"

using namespace granular;
using granular::testing::world;

namespace {

struct Case {
  Integrator integrator;
  double friction;
  bool automaticStep;
  bool wet = false;        ///< liquid bridges out to 0.6 R_max beyond touch
  bool turntable = false;  ///< the floor a square plate turning about the box's vertical axis
  /// The turning floor a triangle mesh (16 × 16 squares), with its own friction 0.2.
  bool meshFloor = false;
  bool hooke = false;  ///< Hooke's law in place of Hertz's
  /// The spectrum's estimate taken × this (studies::scaleSpectrumEstimate): below 1, steps
  /// above the edge, whose growing modes the run must undo.
  double estimateScale = 1.0;
};

Simulation bed(const Case& c, BoxSpec& box) {
  Particles p = denseRandomPacking(400, 0.030, 0.035, 500.0, 9, &box, PackingLayout{});
  SimulationConfig cfg;
  cfg.material.friction = c.friction;
  cfg.material.normalLaw = c.hooke ? NormalLaw::Hooke : NormalLaw::Hertz;
  cfg.integrator = c.integrator;
  cfg.timeStep = 1e-4;
  cfg.step.automatic = c.automaticStep;
  cfg.threads = 1;
  cfg.exactSums = true;
  if (c.wet) {
    cfg.material.surfaceTension = 0.5;
    cfg.material.bridgeVolume = 1e-5;  // rupture distance 0.0215 m
  }
  // The wall moves from the start, so that the ledger's first powers (the bridges reach it at
  // t = 0) are the same whenever it starts: at construction alone, again at the split.
  std::vector<Wall> walls = buildWalls(box);
  for (Wall& wall : walls) {
    if (wall.name == "x+") wall.velocity = Vec3(-0.05, 0, 0);
    if (wall.name == "bottom" && c.turntable) {
      // A plate wider than the box, whose corners sweep around: the shell's travel rebuilds
      // the lists, and its surface velocity drags the bed round by friction.
      const Vec3 size = box.max - box.min;
      wall.shape = WallShape::Rectangle;
      wall.point =
          Vec3(0.5 * (box.min.x() + box.max.x()), 0.5 * (box.min.y() + box.max.y()), box.min.z());
      wall.edge = Vec3::UnitX();
      wall.halfSide[0] = wall.halfSide[1] = std::max(size.x(), size.y());
      wall.angularVelocity = Vec3(0, 0, 2.0);
      wall.pivot = wall.point;
      if (c.meshFloor) {
        const double half = wall.halfSide[0];
        TriangleMesh plate = granular::testing::flatGrid(16, 2.0 * half);
        for (Vec3& v : plate.vertex) v += wall.point - Vec3(half, half, 0.0);
        wall.shape = WallShape::Mesh;
        wall.mesh = poseMesh(std::make_shared<const TriangleMesh>(std::move(plate)), Vec3::Zero(),
                             Vec3::UnitZ(), Vec3::UnitX());
        wall.point = Vec3::Zero();
        wall.normal = Vec3::UnitZ();
        wall.edge = Vec3::UnitX();
        wall.friction = 0.2;
      }
    }
  }
  Simulation sim(std::move(p), std::move(walls), cfg);
  if (c.estimateScale != 1.0) studies::scaleSpectrumEstimate(sim, c.estimateScale);
  return sim;
}

std::string bytesOf(const Simulation& sim, const std::string& name) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("granular_split_" + std::to_string(::getpid()) + name);
  writeCheckpoint(sim, file, 0);
  std::ifstream in(file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove(file);
  return bytes;
}

/// Whose particles a rank holds now: every particle owned once over the ranks.
void expectEachOwnedOnce(const Simulation& split, std::size_t whole) {
  std::uint64_t mine = 0;
  for (std::size_t i = 0; i < split.particles().size(); ++i) mine += split.owns(i) ? 1 : 0;
  EXPECT_EQ(world().sumOverRanks(mine), whole);
  if (world().size() > 1) {
    EXPECT_LT(split.particles().size(), whole);  // a share, not all
  }
}

void compareSplitBySpace(const Case& c) {
  const Communicator& w = world();
  // The world outlives every simulation here: a shared pointer that does not own it.
  const std::shared_ptr<const Communicator> ranks(&w, [](const Communicator*) {});
  BoxSpec box;
  Simulation alone = bed(c, box);
  Simulation split = bed(c, box);
  split.splitAmong(std::make_shared<Bricks>(w.size(), box.min, box.max), ranks);
  for (int k = 0; k < 3; ++k) {
    const std::uint64_t steps = k == 0 ? 1500 : 100;
    alone.run(steps);
    split.run(steps);
    SCOPED_TRACE(::testing::Message()
                 << "rank " << w.rank() << " of " << w.size() << ", "
                 << (c.friction > 0 ? "frictional " : "frictionless ")
                 << (c.integrator == Integrator::Gear5 ? "Gear5" : "Verlet")
                 << (c.automaticStep ? ", automatic step" : "") << (c.wet ? ", wet" : "")
                 << (c.turntable ? ", turntable" : "") << (c.meshFloor ? " of triangles" : "")
                 << ", step " << split.stepCount());
    const Simulation whole = split.wholeState();
    ASSERT_EQ(whole.particles().size(), alone.particles().size());
    ASSERT_EQ(whole.stateHash(), alone.stateHash());
    EXPECT_TRUE(bytesOf(whole, "_whole.bin") == bytesOf(alone, "_alone.bin"))
        << "the checkpoints differ";
    granular::testing::expectSameSums(alone, split);
    EXPECT_EQ(split.kineticEnergy(), alone.kineticEnergy());
    EXPECT_EQ(split.time(), alone.time());
    EXPECT_EQ(split.counters().rebuilds, alone.counters().rebuilds);
    EXPECT_EQ(split.counters().neighbourPairs, alone.counters().neighbourPairs);
    EXPECT_EQ(split.counters().stepChecks, alone.counters().stepChecks);
    EXPECT_EQ(split.counters().rollbacks, alone.counters().rollbacks);
    EXPECT_EQ(split.stepCheck().omegaMax, alone.stepCheck().omegaMax);
    EXPECT_EQ(split.stepCheck().particle, alone.stepCheck().particle);
    EXPECT_EQ(split.stepCheck().contacts, alone.stepCheck().contacts);
    expectEachOwnedOnce(split, alone.particles().size());
    EXPECT_NE(alone.energy().wallWork, 0.0);  // the moving wall works on the bed
    EXPECT_GT(alone.counters().particleContacts, 300u);
    EXPECT_GT(alone.counters().rebuilds, 20u);  // particles have changed hands
  }
  if (c.estimateScale < 1.0) {
    EXPECT_GE(alone.counters().rollbacks, 1u);
  }
}

/// The largest count of particles a rank owns over the mean.
double imbalanceOf(const Simulation& split) {
  std::uint64_t mine = 0;
  for (std::size_t i = 0; i < split.particles().size(); ++i) mine += split.owns(i) ? 1 : 0;
  const double largest = world().maxOverRanks(static_cast<double>(mine));
  return largest / (static_cast<double>(world().sumOverRanks(mine)) / world().size());
}

}  // namespace

TEST(Ranks, BadlyCutDomainsMoveToBalanceAndTheRunStaysOneProcessToTheBit) {
  // Cuts balanced for a bed crowded into the box's low corner: the first rank's brick holds
  // nearly all particles. At the rebuilds the domains move (DomainMap::rebalanced), the
  // particles change hands, and the run is still one process's to the bit.
  const Communicator& w = world();
  const std::shared_ptr<const Communicator> ranks(&w, [](const Communicator*) {});
  const Case c{Integrator::Gear5, 0.3, false};
  BoxSpec box;
  Simulation alone = bed(c, box);
  Simulation split = bed(c, box);
  auto bricks = std::make_shared<Bricks>(w.size(), box.min, box.max);
  std::vector<Vec3> corner;
  for (int k = 0; k < 100; ++k) corner.push_back(box.min + 0.002 * k * (box.max - box.min));
  bricks->balance(corner, 0.0);
  split.splitAmong(bricks, ranks);
  const double before = imbalanceOf(split);
  if (w.size() > 1) {
    EXPECT_GT(before, 1.5);
  }
  alone.run(600);
  split.run(600);
  const Simulation whole = split.wholeState();
  ASSERT_EQ(whole.stateHash(), alone.stateHash());
  EXPECT_TRUE(bytesOf(whole, "_whole.bin") == bytesOf(alone, "_alone.bin"))
      << "the checkpoints differ";
  granular::testing::expectSameSums(alone, split);
  expectEachOwnedOnce(split, alone.particles().size());
  EXPECT_LT(imbalanceOf(split), 1.3) << "from " << before;  // 400 particles, shared planes
}

TEST(Ranks, SplitBySpaceFrictionlessIsOneProcessToTheBit) {
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    compareSplitBySpace({integrator, 0.0, false});
  }
}

TEST(Ranks, SplitBySpaceFrictionalIsOneProcessToTheBit) {
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    compareSplitBySpace({integrator, 0.3, false});
  }
}

TEST(Ranks, SplitBySpaceWithAnAutomaticStepIsOneProcessToTheBit) {
  // The step is chosen from the contact network's bound, whose power sweeps cross the ranks.
  compareSplitBySpace({Integrator::VelocityVerlet, 0.3, true});
}

TEST(Ranks, SplitBySpaceWithRollbacksIsOneProcessToTheBit) {
  // An estimate too low: the automatic step grows modes, which each rank finds at the same
  // check (the ledger is merged over the ranks) and undoes to the same point.
  Case c{Integrator::VelocityVerlet, 0.3, true};
  c.estimateScale = 0.6;
  compareSplitBySpace(c);
}

TEST(Ranks, SplitBySpaceWithLiquidBridgesIsOneProcessToTheBit) {
  // The bridges reach a third of a diameter beyond touch: the split's ghosts reach as far.
  compareSplitBySpace({Integrator::VelocityVerlet, 0.3, false, true});
}

TEST(Ranks, SplitBySpaceOnATurningPlateIsOneProcessToTheBit) {
  // A shell wall (a square plate under the bed, turning about the vertical axis): every rank
  // moves it alike, its travel rebuilds every rank's lists at the same steps, and its surface
  // velocity reaches the contacts on whichever rank holds them.
  compareSplitBySpace({Integrator::VelocityVerlet, 0.3, false, false, true});
}

TEST(Ranks, SplitBySpaceOnATurningMeshIsOneProcessToTheBit) {
  // The turning floor as 512 triangles (every rank holds the whole mesh): a particle's three
  // entries of the mesh, their springs and their contacts' normals travel with it between
  // ranks; its own wall friction holds on every rank.
  compareSplitBySpace({Integrator::VelocityVerlet, 0.3, false, false, true, true});
}

// The Lanczos estimate of the network's spectrum on a split run: the contacts gathered from the
// ranks and numbered by global id, so every rank gets one process's value to the bit, cold and
// warm-started, and after particles have changed hands. Between runs a ghost's velocity is its
// partial one (its owner's comes before each step check), so the contacts are linearised here
// without it: Hooke's springs, no contacts about to form.
TEST(Ranks, TheSpectrumEstimateIsOneProcessToTheBit) {
  const Communicator& w = world();
  const std::shared_ptr<const Communicator> ranks(&w, [](const Communicator*) {});
  Case c{Integrator::VelocityVerlet, 0.5, false};
  c.hooke = true;
  BoxSpec box;
  Simulation alone = bed(c, box);
  Simulation split = bed(c, box);
  split.splitAmong(std::make_shared<Bricks>(w.size(), box.min, box.max), ranks);
  NetworkSpectrumStart aloneStart, splitStart;
  for (int k = 0; k < 3; ++k) {
    alone.run(k == 0 ? 1500 : 200);
    split.run(k == 0 ? 1500 : 200);
    SCOPED_TRACE(::testing::Message() << "rank " << w.rank() << " of " << w.size() << ", check "
                                      << k << ", step " << split.stepCount());
    const NetworkSpectrum a = networkSpectrumEstimate(alone, 0.0, &aloneStart);
    const NetworkSpectrum b = networkSpectrumEstimate(split, 0.0, &splitStart);
    ASSERT_GT(a.omegaMax, 0.0);
    EXPECT_EQ(b.omegaMax, a.omegaMax);
    EXPECT_EQ(b.dampingRate, a.dampingRate);
    EXPECT_EQ(b.omegaResidual, a.omegaResidual);
    EXPECT_EQ(b.products, a.products);
    EXPECT_EQ(b.contacts, a.contacts);
    EXPECT_TRUE(splitStart.stiffness == aloneStart.stiffness);
    EXPECT_TRUE(splitStart.bodies == aloneStart.bodies);
  }
  EXPECT_GT(alone.counters().rebuilds, 20u);  // particles have changed hands
}
