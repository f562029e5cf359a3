/// A stage's inserts and outlets (granular/stage_exchange.hpp): particles placed apart, inside
/// their region and clear of the walls, the same for the same seed; a pouring stage that ends
/// when its inserts are done and the bed is quiet; an outlet that empties a silo with the mass
/// balanced exactly at every sample; a stage resumed from a checkpoint mid-discharge, bit for
/// bit.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "granular/checkpoint.hpp"
#include "granular/scene.hpp"
#include "granular/stage.hpp"
#include "granular/stage_exchange.hpp"
#include "temp_folder.hpp"

using namespace granular;

namespace {

const std::filesystem::path kDischarge =
    std::filesystem::path(GRANULAR_SOURCE_DIR) / "tests/scenes/discharge.toml";

InsertSpec boxInsert() {
  InsertSpec insert;
  insert.region.shape = Region::Shape::Box;
  insert.region.min = Vec3(0.0, 0.0, 0.0);
  insert.region.max = Vec3(0.3, 0.2, 0.25);
  insert.count = 1000;
  insert.rate = 1e4;
  insert.radiusMin = 0.02;
  insert.radiusMax = 0.025;
  insert.velocity = Vec3(0, 0, -1);
  insert.seed = 42;
  return insert;
}

}  // namespace

TEST(StageExchange, InsertedParticlesLieInTheirRegionApartFromEachOtherAndTheWalls) {
  const InsertSpec insert = boxInsert();
  Particles present;
  present.add(Vec3(0.15, 0.1, 0.12), 0.05, 500.0);  // a big sphere in the middle of the region
  Wall floor;  // a plane through the region: nothing may be placed across it
  floor.name = "floor";
  floor.point = Vec3(0, 0, 0.05);
  floor.normal = Vec3::UnitZ();
  const Particles placed = placeInserted(insert, 30, 0, 1, present, {floor}, 500.0);
  ASSERT_EQ(placed.size(), 30u);
  for (std::size_t i = 0; i < placed.size(); ++i) {
    const Vec3& x = placed.position[i];
    const double r = placed.radius[i];
    EXPECT_TRUE(insert.region.holds(x, r)) << i;
    EXPECT_GE(r, insert.radiusMin);
    EXPECT_LE(r, insert.radiusMax);
    EXPECT_GE(x.z() - 0.05, r) << i;  // clear of the floor
    EXPECT_GE((x - present.position[0]).norm(), r + present.radius[0]) << i;
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_GE((x - placed.position[j]).norm(), r + placed.radius[j]) << i << " " << j;
    }
    EXPECT_EQ(placed.velocity[i], insert.velocity);
    EXPECT_DOUBLE_EQ(placed.mass[i], 500.0 * 4.0 / 3.0 * M_PI * r * r * r);
  }
  // The same seed and exchange give the same particles; another exchange others.
  const Particles again = placeInserted(insert, 30, 0, 1, present, {floor}, 500.0);
  EXPECT_EQ(again.position, placed.position);
  EXPECT_EQ(again.radius, placed.radius);
  const Particles next = placeInserted(insert, 30, 0, 2, present, {floor}, 500.0);
  EXPECT_NE(next.position, placed.position);
}

TEST(StageExchange, AFullRegionPlacesOnlyWhatFits) {
  InsertSpec insert = boxInsert();
  insert.region.max = Vec3(0.1, 0.1, 0.1);  // room for about (0.1 / 0.05)^3 · 0.6 spheres
  const Particles placed = placeInserted(insert, 200, 0, 1, {}, {}, 500.0);
  EXPECT_LT(placed.size(), 20u);
  EXPECT_GT(placed.size(), 0u);
}

// A particle's radius is its own, drawn from the seed and its number: the same whether it found
// room at once, after others failed, or at a later exchange. A radius drawn per try would leave
// the crowded region with the small ones (the large find less room) and the radii biased.
TEST(StageExchange, AParticlesRadiusDoesNotDependOnWhereOrWhenItFoundRoom) {
  InsertSpec insert = boxInsert();
  const Particles free = placeInserted(insert, 60, 0, 1, {}, {}, 500.0);
  ASSERT_EQ(free.size(), 60u);
  insert.region.max = Vec3(0.1, 0.1, 0.1);  // crowded: few fit
  const Particles crowded = placeInserted(insert, 60, 0, 1, {}, {}, 500.0);
  ASSERT_GT(crowded.size(), 0u);
  ASSERT_LT(crowded.size(), 60u);
  for (std::size_t k = 0; k < crowded.size(); ++k) EXPECT_EQ(crowded.radius[k], free.radius[k]);
  // The rest come later with the radii they were due: particle n keeps its own.
  const Particles later = placeInserted(insert, 5, crowded.size(), 2, {}, {}, 500.0);
  for (std::size_t k = 0; k < later.size(); ++k) {
    EXPECT_EQ(later.radius[k], free.radius[crowded.size() + k]);
  }
}

TEST(StageExchange, ParticlesInOutletsAreThoseWhoseCentresAreInside) {
  OutletSpec below;
  below.region.shape = Region::Shape::Cylinder;
  below.region.base = Vec3(0, 0, -1);
  below.region.axis = Vec3::UnitZ();
  below.region.length = 1.0;
  below.region.radius = 0.5;
  Particles p;
  p.add(Vec3(0, 0, 0.1), 0.05, 500.0);      // above: stays
  p.add(Vec3(0.1, 0, -0.01), 0.05, 500.0);  // centre inside, surface above: removed
  p.add(Vec3(0.6, 0, -0.5), 0.05, 500.0);   // beside the cylinder: stays
  p.add(Vec3(0, 0.2, -0.9), 0.05, 500.0);   // inside
  EXPECT_EQ(particlesInOutlets({below}, p), (std::vector<std::size_t>{1, 3}));
}

// The discharge scene: 300 spheres poured, the gate taken away, the outlet empties the silo. At
// every sample the masses balance to the bit and the particles held are those poured less those
// discharged.
TEST(StageExchange, ASiloFilledAndEmptiedBalancesItsMassAtEverySample) {
  const Scene scene = loadScene(kDischarge);
  Simulation sim = buildSimulation(scene);
  ASSERT_EQ(sim.particles().size(), 0u);
  std::size_t samples = 0;
  StageObserver observer;
  observer.onSample = [&](const Simulation& s) {
    const ParticleTally t = s.particleTally();
    ASSERT_EQ(t.massBalance, 0.0) << "t = " << s.time();
    ASSERT_EQ(t.held, t.inserted - t.removed);
    ASSERT_EQ(t.held, s.particles().size());
    ++samples;
  };
  runStage(sim, scene.stages[0], scene.output, observer);
  EXPECT_EQ(sim.particleTally().inserted, 300u);  // 1500/s for 0.6 s: all 300 by 0.2 s
  EXPECT_EQ(sim.particleTally().removed, 0u);
  runStage(sim, scene.stages[1], scene.output, observer);
  const ParticleTally t = sim.particleTally();
  EXPECT_GT(t.removed, 30u);  // it flows through an orifice of 4 diameters
  EXPECT_TRUE(sim.walls()[std::size_t(sim.findWall("gate"))].removed);
  for (std::size_t i = 0; i < sim.particles().size(); ++i) {
    EXPECT_GT(sim.particles().position[i].z(), -0.05) << "left in the outlet";
  }
  EXPECT_GT(samples, 150u);
}

class StageExchangeFiles : public granular::testing::TempFolderTest {
 protected:
  StageExchangeFiles() : TempFolderTest("granular_stage_exchange") {}
};

// A checkpoint taken mid-discharge, resumed: the same end, bit for bit, as the stage run through.
TEST_F(StageExchangeFiles, ADischargeResumedFromACheckpointEndsBitForBit) {
  const Scene scene = loadScene(kDischarge);
  Simulation through = buildSimulation(scene);
  runStage(through, scene.stages[0], scene.output, {});
  const std::filesystem::path file = dir_ / "mid.ckpt";
  // The same run, checkpointed every 700 steps of the discharge; the one after 2100 kept.
  Simulation first = buildSimulation(scene);
  runStage(first, scene.stages[0], scene.output, {});
  StageProgress kept;
  StageObserver saving;
  saving.checkpointSteps = 700;
  saving.onCheckpoint = [&](const Simulation& s, const StageProgress& p) {
    if (p.time.value_or(0) > 0 && kept.steps == 0 && p.steps >= 2100) {
      writeCheckpoint(s, file, 1);
      kept = p;
    }
  };
  runStage(through, scene.stages[1], scene.output, {});
  runStage(first, scene.stages[1], scene.output, saving);
  ASSERT_GT(kept.steps, 0u);
  EXPECT_EQ(first.stateHash(), through.stateHash());
  Simulation resumed = readCheckpoint(file, 1);
  ASSERT_GT(resumed.particleTally().removed, 0u) << "checkpoint taken before the flow began";
  runStage(resumed, scene.stages[1], scene.output, {}, &kept);
  EXPECT_EQ(resumed.stateHash(), through.stateHash());
  EXPECT_EQ(resumed.particleTally().removedMass, through.particleTally().removedMass);
  EXPECT_EQ(resumed.particleTally().massBalance, 0.0);
}

// Filled and emptied on 1 and 2 threads: the same bits (the exchange itself runs on one).
TEST(StageExchange, TheSameSiloOnOneAndTwoThreadsIsTheSameBits) {
  Scene scene = loadScene(kDischarge);
  std::uint64_t hash[2] = {0, 0};
  for (int threads : {1, 2}) {
    scene.simulation.threads = threads;
    Simulation sim = buildSimulation(scene);
    for (const StageSpec& stage : scene.stages) runStage(sim, stage, scene.output, {});
    ASSERT_GT(sim.particleTally().removed, 0u);
    hash[threads - 1] = sim.stateHash();
  }
  EXPECT_EQ(hash[0], hash[1]);
}
