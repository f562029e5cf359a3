/// The tangential springs are stored for touching pairs only, in one array per particle block
/// that the force pass rewrites in place, with a bit per candidate pair saying which hold one
/// (core/engine/src/pair_springs.hpp). These tests check that every contact keeps its own spring
/// through that bookkeeping, in beds of several blocks where contacts open and close in bulk.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "granular/engine_studies.hpp"
#include "granular/packings.hpp"
#include "granular/simulation.hpp"

namespace granular {
namespace {

/// 800 spheres of the paper's radii packed at rest 1.3 mm apart in a box (≈ 4000 candidate
/// pairs: several particle blocks of 512 pairs) that fall into contact under gravity, layer by
/// layer from the floor up, so that contacts form in bulk within a few hundred steps.
Simulation landingBed(const SimulationConfig& cfg) {
  BoxSpec box;
  Particles p = denseRandomPacking(800, 0.030, 0.035, cfg.material.density, 11, &box);
  return Simulation(std::move(p), buildWalls(box), cfg);
}

SimulationConfig frictionalVerlet() {
  SimulationConfig cfg;
  cfg.integrator = Integrator::VelocityVerlet;
  cfg.timeStep = 1.5e-4;
  cfg.material.friction = 0.5;
  return cfg;
}

TEST(PairSprings, RebuildingEveryStepGivesTheSameBitsAsRebuildingOnTheSkin) {
  // Rebuilt every step, the springs are laid out afresh by the merge of the old and new lists
  // (carryPairSprings); on the skin criterion, the force pass's cursor carries them in place for
  // tens of steps, setting aside the unread ones when new contacts come first. Different lists
  // (so different blocks, chunks and pair indices) must give the same springs to the same
  // contacts: the same bits, on 1 and 2 threads.
  for (int threads : {1, 2}) {
    SimulationConfig cfg = frictionalVerlet();
    cfg.threads = threads;
    Simulation lazy = landingBed(cfg);
    Simulation eager = landingBed(cfg);
    studies::setRebuildEveryStep(eager, true);
    std::size_t mostContacts = 0;
    for (int k = 0; k < 8; ++k) {
      lazy.run(100);
      eager.run(100);
      mostContacts = std::max(mostContacts, lazy.counters().particleContacts);
    }
    EXPECT_GT(lazy.counters().neighbourPairs, 2048u) << "the bed should span several blocks";
    EXPECT_GT(mostContacts, 1000u) << "the bed should have landed";
    EXPECT_GT(eager.counters().rebuilds, 10 * lazy.counters().rebuilds);
    EXPECT_GT(lazy.energy().of("elastic_tangential_J"), 0.0);  // springs are in use
    EXPECT_EQ(lazy.stateHash(), eager.stateHash()) << threads << " thread(s)";
  }
}

TEST(PairSprings, TheMeasuringPassSeesTheSpringsTheStepStored) {
  // Without dashpots the contact force depends on the positions and the stored springs only: the
  // measuring pass, which finds a pair's spring by counting the holding pairs before it
  // (SpringReader), must then find the force the step computed while storing them (Verlet:
  // a = F/m + g at the step's final positions). A spring given to the wrong pair would show as
  // a tangential force where the step had another.
  SimulationConfig cfg = frictionalVerlet();
  cfg.material.normalDamping = 0.0;
  cfg.material.tangentialDamping = 0.0;
  Simulation sim = landingBed(cfg);
  double largestTangential = 0.0;
  for (int k = 0; k < 8; ++k) {
    sim.run(100);
    const std::vector<Vec3> net = sim.netContactForces();
    const Particles& p = sim.particles();
    double scale = 0.0, worst = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec3 fromStep = p.mass[i] * (sim.acceleration(i) - cfg.gravity);
      scale = std::max(scale, fromStep.norm());
      worst = std::max(worst, (net[i] - fromStep).norm());
    }
    ASSERT_GT(scale, 0.0);
    EXPECT_LT(worst, 1e-9 * scale) << "after " << sim.stepCount() << " steps";
    sim.forEachContact([&](const ContactView& c) {
      if (c.isWall()) return;
      const Vec3 d = p.position[c.otherParticle()] - p.position[c.particle];
      const Vec3 n = d.normalized();
      largestTangential = std::max(largestTangential, (c.force - c.force.dot(n) * n).norm());
    });
  }
  EXPECT_GT(largestTangential, 0.0);  // the springs carried force
}

}  // namespace
}  // namespace granular
