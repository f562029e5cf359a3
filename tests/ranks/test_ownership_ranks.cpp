/// Each contact accounted for once over the ranks (Simulation::setOwnership): every rank runs
/// the whole bed, owns the particles of its brick, and merges its sums; the energies, wall
/// reactions and contact counts are then the same bits as one process summing them all, for
/// any rank count. Both integrators, with and without friction, a moving wall.
#include <gtest/gtest.h>

#include "granular/bricks.hpp"
#include "granular/packings.hpp"
#include "granular/scene.hpp"
#include "granular/simulation.hpp"
#include "ranks.hpp"
#include "same_sums.hpp"

using namespace granular;
using granular::testing::world;

namespace {

Simulation bed(Integrator integrator, double friction, BoxSpec& box) {
  Particles p = denseRandomPacking(400, 0.030, 0.035, 500.0, 9, &box, PackingLayout{});
  SimulationConfig cfg;
  cfg.material.friction = friction;
  cfg.material.normalLaw = NormalLaw::Hertz;
  cfg.integrator = integrator;
  cfg.timeStep = 1e-4;
  cfg.threads = 1;
  cfg.exactSums = true;
  Simulation sim(std::move(p), buildWalls(box), cfg);
  sim.setWallVelocity(static_cast<std::size_t>(sim.findWall("x+")), Vec3(-0.05, 0, 0));
  return sim;
}

/// Whose particles: bricks for the frictionless runs; with friction particle i goes to rank
/// i mod N, an ownership that changes at almost every particle (the accounting does not need it
/// to follow space), where a contact counted twice or not at all shows at once.
std::vector<std::uint8_t> ownership(const Simulation& sim, const BoxSpec& box, double friction) {
  const Communicator& w = world();
  const Bricks bricks(w.size(), box.min, box.max);
  std::vector<std::uint8_t> owned;
  std::size_t mine = 0;
  const std::vector<Vec3>& x = sim.particles().position;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const int owner = friction > 0 ? static_cast<int>(i % w.size()) : bricks.owner(x[i]);
    owned.push_back(owner == w.rank() ? 1 : 0);
    mine += owned.back();
  }
  EXPECT_EQ(w.sumOverRanks(mine), x.size());
  return owned;
}

/// Runs the bed alone and with its contacts accounted for among the ranks, both integrators,
/// with and without friction; compares them after the bed has fallen and landed (0.15 s) and
/// twice 100 steps later.
void compareSplitRuns() {
  const Communicator& w = world();
  // The world outlives every simulation here: a shared pointer that does not own it.
  const std::shared_ptr<const Communicator> ranks(&w, [](const Communicator*) {});
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    for (double friction : {0.0, 0.3}) {
      BoxSpec box;
      Simulation alone = bed(integrator, friction, box);
      Simulation split = bed(integrator, friction, box);
      split.setOwnership(ownership(split, box, friction), ranks);
      for (int k = 0; k < 3; ++k) {
        const std::uint64_t steps = k == 0 ? 1500 : 100;
        alone.run(steps);
        split.run(steps);
        SCOPED_TRACE(::testing::Message() << "rank " << w.rank() << " of " << w.size() << ", "
                                          << (friction > 0 ? "frictional " : "frictionless ")
                                          << (integrator == Integrator::Gear5 ? "Gear5" : "Verlet")
                                          << ", step " << split.stepCount());
        ASSERT_EQ(split.stateHash(), alone.stateHash());
        granular::testing::expectSameSums(alone, split);
        EXPECT_EQ(split.kineticEnergy(), alone.kineticEnergy());
        EXPECT_EQ(split.counters().rebuilds, alone.counters().rebuilds);
        EXPECT_NE(alone.energy().wallWork, 0.0);  // the moving wall works on the bed
        EXPECT_GT(alone.counters().particleContacts, 300u);
        EXPECT_GT(alone.counters().wallContacts, 80u);
      }
    }
  }
}

}  // namespace

TEST(Ranks, EachContactIsAccountedForOnceOverTheRanks) {
  // Every rank computes every particle; each accounts for its own contacts and the sums are
  // merged.
  compareSplitRuns();
}
