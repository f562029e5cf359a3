/// Engine-level checks: determinism, history across list rebuilds, static equilibrium, and the
/// refusal of an unstable time step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>

#include "granular/bricks.hpp"
#include "granular/engine_studies.hpp"
#include "granular/error.hpp"
#include "granular/packings.hpp"
#include "physics_fixtures.hpp"
#include "same_sums.hpp"

using namespace granular;
using granular::testing::fallingGrid;

namespace {

SimulationConfig frictional(Integrator integrator) {
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.integrator = integrator;
  cfg.timeStep = 1.5e-4;
  return cfg;
}

}  // namespace

TEST(Simulation, SameSceneAndSeedGiveBitIdenticalState) {
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    Simulation a = fallingGrid(4, 4, 4, frictional(integrator), 0.3, 11);
    Simulation b = fallingGrid(4, 4, 4, frictional(integrator), 0.3, 11);
    Simulation c = fallingGrid(4, 4, 4, frictional(integrator), 0.3, 12);
    a.run(3000);
    b.run(3000);
    c.run(3000);
    EXPECT_EQ(a.stateHash(), b.stateHash());
    EXPECT_NE(a.stateHash(), c.stateHash());
  }
}

TEST(Simulation, ResultsDoNotDependOnTheThreadCount) {
  // Every particle receives its contacts in one order and the sums run in fixed blocks, so 1, 2
  // or 3 threads give the same bits (64 particles: one block, one thread does the work).
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    std::uint64_t reference = 0;
    for (int threads : {1, 2, 3}) {
      SimulationConfig cfg = frictional(integrator);
      cfg.threads = threads;
      Simulation sim = fallingGrid(4, 4, 4, cfg, 0.3, 11);
      sim.run(3000);
      if (threads == 1) reference = sim.stateHash();
      EXPECT_EQ(sim.stateHash(), reference) << threads << " threads";
      EXPECT_GT(sim.counters().particleContacts, 10u);
    }
  }
}

TEST(Simulation, PairsStraddlingTwoThreadsGiveTheSameBits) {
  // A dense frictional bed of 1500 spheres: several particle blocks per thread, and pairs
  // whose particles belong to two threads, computed by the first's thread into a slot the
  // second's thread adds (the only scratch the force pass keeps). Hertz, so the law's square
  // roots go through both thread paths too.
  std::uint64_t reference = 0;
  for (int threads : {1, 2, 3}) {
    BoxSpec box;
    Particles p = denseRandomPacking(1500, 0.030, 0.035, 500.0, 5, &box, PackingLayout{});
    SimulationConfig cfg = frictional(Integrator::Gear5);
    cfg.material.normalLaw = NormalLaw::Hertz;
    cfg.threads = threads;
    Simulation sim(std::move(p), buildWalls(box), cfg);
    sim.run(2000);
    if (threads == 1) reference = sim.stateHash();
    EXPECT_EQ(sim.stateHash(), reference) << threads << " threads";
    EXPECT_GT(sim.counters().particleContacts, 1000u);
    if (threads > 1) {
      EXPECT_GT(sim.memoryUse().scratch, 0u) << "no pair straddles two threads";
    }
  }
}

TEST(Simulation, ChangingTheThreadCountMidRunKeepsTheBits) {
  // The force plan is built for a thread count and a list; switching the count after list
  // rebuilds must build it for the current list and count, not use a stale one.
  SimulationConfig cfg = frictional(Integrator::Gear5);
  cfg.threads = 1;
  Simulation steady = fallingGrid(4, 4, 4, cfg, 0.3, 11);
  Simulation switching = fallingGrid(4, 4, 4, cfg, 0.3, 11);
  steady.run(3000);
  for (int threads : {1, 2, 1, 2, 3, 1}) {
    switching.setThreads(threads);
    switching.run(500);
  }
  EXPECT_GT(switching.counters().rebuilds, 5u);
  EXPECT_EQ(switching.stateHash(), steady.stateHash());
}

TEST(Simulation, WallContactsInSeveralBlocksDoNotDependOnTheThreadCount) {
  // 24 × 24 particles in one layer land on the floor: 576 floor candidates, two blocks of 512,
  // 576 particles: two particle blocks, so the floor is split between the threads.
  std::uint64_t reference = 0;
  Vec3 floorReaction = Vec3::Zero();
  for (int threads : {1, 2}) {
    SimulationConfig cfg = frictional(Integrator::Gear5);
    cfg.threads = threads;
    Simulation sim = fallingGrid(24, 24, 1, cfg, 0.05, 3);
    sim.run(3000);
    // Most rest on the floor (the rest bounce within the skin): over 512 floor candidates.
    ASSERT_GT(sim.counters().wallContacts, 500u);
    if (threads == 1) {
      reference = sim.stateHash();
      floorReaction = sim.walls().back().reaction;
    }
    EXPECT_EQ(sim.stateHash(), reference) << threads << " threads";
    EXPECT_EQ(sim.walls().back().reaction, floorReaction) << threads << " threads";
  }
}

TEST(Simulation, TheSkinChangesTheWorkNotTheResult) {
  // The skin only decides how many candidates the list holds and how often it is rebuilt: the
  // touching pairs, their order and their springs are the same, so the state is the same bits.
  for (int threads : {1, 2}) {
    SimulationConfig cfg = frictional(Integrator::Gear5);
    cfg.threads = threads;
    Simulation wide = fallingGrid(4, 4, 4, cfg, 0.3, 11);
    Simulation thin = fallingGrid(4, 4, 4, cfg, 0.3, 11);
    thin.setSkin(0.002);
    EXPECT_EQ(thin.skin(), 0.002);
    EXPECT_NEAR(wide.skin(), 0.009, 0.0002);  // the default: 0.3 × the smallest radius (≈ 0.03 m)
    wide.run(3000);
    thin.run(3000);
    EXPECT_GT(thin.counters().rebuilds, wide.counters().rebuilds);
    EXPECT_LT(thin.counters().neighbourPairs, wide.counters().neighbourPairs);
    EXPECT_EQ(thin.stateHash(), wide.stateHash()) << threads << " threads";
  }
  Simulation sim = fallingGrid(2, 2, 2, frictional(Integrator::Gear5), 0.3);
  EXPECT_THROW(sim.setSkin(-0.001), ConfigError);
  EXPECT_THROW(sim.setSkin(std::nan("")), ConfigError);
}

TEST(Simulation, EnergiesAndReactionsDoNotDependOnHowTheContactsAreSplit) {
  // The skin moves the particle blocks' bounds (512 candidate pairs at most a block), and with
  // them the split of the contacts among the force pass's sums. With exactSums the energies,
  // the powers they integrate and the walls' reactions are exact sums (ExactSum), the same bits
  // for any split, as they must be for any split among processes. Summed block by block in
  // double (exactSums off), they are not: this bed gives other last bits with a thinner skin
  // (ExactSumsAreNeededForThat below).
  BoxSpec box;
  const Particles bed = denseRandomPacking(1500, 0.030, 0.035, 500.0, 5, &box, PackingLayout{});
  SimulationConfig cfg = frictional(Integrator::Gear5);
  cfg.material.normalLaw = NormalLaw::Hertz;
  cfg.threads = 1;
  cfg.exactSums = true;
  Simulation wide(bed, buildWalls(box), cfg);
  Simulation thin(bed, buildWalls(box), cfg);
  thin.setSkin(0.25 * wide.skin());
  for (int k = 0; k < 4; ++k) {
    wide.run(400);
    thin.run(400);
    ASSERT_EQ(thin.stateHash(), wide.stateHash());
    ASSERT_NE(thin.counters().neighbourPairs, wide.counters().neighbourPairs);
    granular::testing::expectSameSums(wide, thin);
    EXPECT_GT(wide.energy().of("elastic_normal_J"), 0.0);
  }
}

TEST(Simulation, ExactSumsAreNeededForThat) {
  // The same two runs with the energies summed block by block: the state is the same bits (the
  // motion never reads a sum), the stored energy is not, which is what makes the test above
  // able to fail; and the exact sums agree with the block sums to rounding.
  BoxSpec box;
  const Particles bed = denseRandomPacking(1500, 0.030, 0.035, 500.0, 5, &box, PackingLayout{});
  SimulationConfig cfg = frictional(Integrator::Gear5);
  cfg.material.normalLaw = NormalLaw::Hertz;
  cfg.threads = 1;
  Simulation wide(bed, buildWalls(box), cfg);
  Simulation thin(bed, buildWalls(box), cfg);
  cfg.exactSums = true;
  Simulation exact(bed, buildWalls(box), cfg);
  thin.setSkin(0.25 * wide.skin());
  wide.run(400);
  thin.run(400);
  exact.run(400);
  ASSERT_EQ(thin.stateHash(), wide.stateHash());
  ASSERT_EQ(exact.stateHash(), wide.stateHash());
  const double a = wide.energy().of("elastic_normal_J"), b = thin.energy().of("elastic_normal_J");
  const double e = exact.energy().of("elastic_normal_J");
  EXPECT_NE(a, b);
  EXPECT_NEAR(a, e, 1e-12 * e);
  EXPECT_NEAR(b, e, 1e-12 * e);
}

TEST(Simulation, ContactHistorySurvivesNeighbourListRebuilds) {
  // Rebuilding every step must give the very same trajectory as rebuilding on the skin
  // criterion: the tangential springs are carried across rebuilds, not restarted.
  Simulation lazy = fallingGrid(4, 4, 4, frictional(Integrator::Gear5), 0.3);
  Simulation eager = fallingGrid(4, 4, 4, frictional(Integrator::Gear5), 0.3);
  studies::setRebuildEveryStep(eager, true);
  lazy.run(4000);
  eager.run(4000);
  EXPECT_GT(eager.counters().rebuilds, 10 * lazy.counters().rebuilds);
  EXPECT_GT(lazy.energy().of("elastic_tangential_J"), 0.0);  // springs are in use
  EXPECT_EQ(lazy.stateHash(), eager.stateHash());
}

TEST(Simulation, TheListIsRebuiltWhenTheTwoLargestMovesMayHaveClosedTheSkin) {
  // Two particles close a gap by at most the sum of their moves, so the list is rebuilt where
  // the two largest moves since its build may have closed the skin, and no sooner. Two scenes
  // among spheres at rest: a pair thrown head-on at 4 m/s each from just beyond the list's
  // reach (rebuilt at half the skin each), and one sphere thrown at a sphere at rest (rebuilt at
  // the whole skin while it flies alone). Every contact is in the list when it forms: each run
  // is the very run that rebuilds its list at every step, to the bit.
  SimulationConfig cfg = frictional(Integrator::VelocityVerlet);
  cfg.gravity = Vec3::Zero();
  cfg.timeStep = 2e-6;                                    // [s]
  cfg.skin = 2e-3;                                        // [m]
  const double r = 0.01, speed = 4.0, gap = 2e-3 * 1.01;  // [m], [m/s], [m]: beyond the skin
  const std::uint64_t steps = 3000;                       // 6 ms: 24 mm of flight
  for (bool headOn : {true, false}) {
    SCOPED_TRACE(headOn ? "head-on pair" : "one sphere thrown");
    Particles p;
    for (int k = 0; k < 5; ++k) p.add(Vec3(0.1 + 0.025 * k, 0.3, 0.1), r, 2500.0);  // at rest
    p.add(Vec3(0.1, 0.1, 0.1), r, 2500.0, Vec3(speed, 0, 0));
    const Vec3 other(0.1 + 2 * r + (headOn ? 1 : 5) * gap, 0.1, 0.1);
    p.add(other, r, 2500.0, headOn ? Vec3(-speed, 0, 0) : Vec3::Zero());
    Simulation lazy(p, {}, cfg), eager(p, {}, cfg);
    studies::setRebuildEveryStep(eager, true);
    lazy.run(steps);
    eager.run(steps);
    EXPECT_EQ(lazy.stateHash(), eager.stateHash());
    // The impact happened: the thrown sphere bounced back, or passed its speed on.
    EXPECT_LT(lazy.particles().velocity[5].x(), headOn ? 0.0 : 0.5 * speed);
    EXPECT_GT(lazy.particles().velocity[6].x(), headOn ? 0.0 : 0.5 * speed);
    // One sphere in flight at a time: a rebuild each 2 mm of its 24 mm (at half the skin: 24).
    if (!headOn) {
      EXPECT_LE(lazy.counters().rebuilds, 14u);
    }
  }
}

TEST(Simulation, RestingColumnFloorReactionEqualsWeight) {
  // Five spheres stacked on the floor, released just touching: once the dashpots have damped the
  // motion, the floor carries the whole weight (frictionless, no side walls: exact). The dashpot
  // c = γn m_ij is proportional to the stiffness like Rayleigh damping, so the chain's slow modes
  // decay far slower than e^{-γn t/2} (about e^{-2t} here): give it 20 s.
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    SimulationConfig cfg;
    cfg.integrator = integrator;
    cfg.timeStep = 1e-4;
    Particles p;
    double z = 0, weight = 0;
    for (int k = 0; k < 5; ++k) {
      const double r = 0.03 + 0.001 * k;
      z += r;
      p.add(Vec3(0.5, 0.5, z), r, cfg.material.density);
      weight += p.mass.back() * 9.81;
      z += r;
    }
    Simulation sim(std::move(p), {Wall{"bottom", Vec3::Zero(), Vec3::UnitZ()}}, cfg);
    sim.run(200000);
    EXPECT_LT(sim.kineticEnergy(), 1e-20);
    const Vec3 reaction = sim.walls()[0].reaction;
    EXPECT_NEAR(reaction.z() / weight, -1.0, 1e-9);  // the particles push the floor down
    EXPECT_NEAR(reaction.x(), 0.0, 1e-12);
    EXPECT_EQ(sim.counters().particleContacts, 4u);
  }
}

TEST(Simulation, UnstableTimeStepIsRefusedWithTheLimit) {
  // Hard case 8: each integrator's limit, a fraction of the analytic contact duration (Gear's
  // five times smaller: it gains energy in a damped bed above it), is named in the refusal.
  for (const auto& [integrator, fraction, name] :
       {std::tuple{Integrator::VelocityVerlet, 0.1, "velocity Verlet"},
        std::tuple{Integrator::Gear5, 0.02, "gear5"}}) {
    SimulationConfig cfg;
    cfg.integrator = integrator;
    cfg.timeStep = 1e-6;
    const Simulation probe = fallingGrid(2, 2, 2, cfg, 0.0);
    const ContactScale scale = probe.contactScale();
    const Particles& p = probe.particles();
    const double rMin = *std::min_element(p.radius.begin(), p.radius.end());
    // The stiffest contact is the smallest sphere's, from theory (here against a wall).
    EXPECT_DOUBLE_EQ(scale.duration, stiffestContact(cfg.material, rMin, 1.0).duration);
    const double limit = fraction * scale.duration;
    EXPECT_DOUBLE_EQ(maxStableStep(scale, integrator), limit);
    cfg.timeStep = 1.01 * limit;
    try {
      fallingGrid(2, 2, 2, cfg, 0.0);
      ADD_FAILURE() << "an unstable step was accepted for " << name;
    } catch (const ConfigError& e) {
      const std::string msg = e.what();
      std::ostringstream shown;
      shown << "above the stable limit " << limit << " s of " << name;
      EXPECT_NE(msg.find(shown.str()), std::string::npos) << msg;
      EXPECT_NE(msg.find("contact duration"), std::string::npos) << msg;
    }
    cfg.timeStep = 0.99 * limit;
    EXPECT_NO_THROW(fallingGrid(2, 2, 2, cfg, 0.0));
  }
}

TEST(Simulation, ContactViewsSeeEachPairFromBothSides) {
  Simulation sim = fallingGrid(3, 3, 3, frictional(Integrator::Gear5), 0.3);
  sim.run(5000);
  std::size_t pairViews = 0, wallViews = 0;
  Vec3 sum = Vec3::Zero();
  sim.forEachContact([&](const ContactView& c) {
    (c.isWall() ? wallViews : pairViews)++;
    if (!c.isWall()) sum += c.force;  // Newton's third law: pair forces cancel
  });
  EXPECT_EQ(pairViews, 2 * sim.counters().particleContacts);
  EXPECT_EQ(wallViews, sim.counters().wallContacts);
  EXPECT_LT(sum.norm(), 1e-9);
}

// Changing the step keeps the clock continuous and refuses an unstable step.
TEST(Simulation, SetTimeStepKeepsTheClockAndRefusesUnstableSteps) {
  granular::Particles p;
  p.add(granular::Vec3(0, 0, 1), 0.03, 500.0);
  granular::SimulationConfig config;
  config.timeStep = 1e-4;
  granular::Simulation sim(std::move(p), {}, config);
  sim.run(10);
  sim.setTimeStep(5e-5);
  sim.run(4);
  EXPECT_NEAR(sim.time(), 10 * 1e-4 + 4 * 5e-5, 1e-15);
  EXPECT_THROW(sim.setTimeStep(1.0), granular::ConfigError);
  EXPECT_THROW(sim.setTimeStep(-1e-4), granular::ConfigError);
  EXPECT_DOUBLE_EQ(sim.config().timeStep, 5e-5);
}

// The memory account sees what the model needs: a frictionless scene holds no tangential
// history and no torques, a frictional one does; every part grows with the particle count.
TEST(Simulation, MemoryUseFollowsTheModel) {
  auto build = [](double friction) {
    granular::BoxSpec box;
    granular::Particles p =
        granular::denseRandomPacking(500, 0.030, 0.035, 500.0, 7, &box, granular::PackingLayout{});
    granular::SimulationConfig config;
    config.material.friction = friction;
    config.timeStep = 1e-4;
    granular::Simulation sim(std::move(p), granular::buildWalls(box), config);
    sim.run(5);
    return sim.memoryUse();
  };
  const granular::MemoryUse frictionless = build(0.0), frictional = build(0.3);
  EXPECT_EQ(frictionless.history, 0u);
  EXPECT_GT(frictional.history, 0u);
  EXPECT_GT(frictional.integrator, frictionless.integrator);  // torques, rotational derivatives
  EXPECT_GE(frictional.scratch, frictionless.scratch);        // n × F and h per straddling pair
  // Positions, velocities, ω (3 × 24 B) and radius, mass (2 × 8 B) per particle at least.
  EXPECT_GE(frictionless.particles, 500u * 88u);
  EXPECT_EQ(frictionless.total(), frictionless.particles + frictionless.integrator +
                                      frictionless.neighbours + frictionless.history +
                                      frictionless.forcePlan + frictionless.scratch);
}

// Hard case 9 in the engine: a NaN put into the state between two steps is caught by the end
// of the next step (the integrators check every position and velocity they write), and the
// error names that step and the particle, for both integrators and both paths.
TEST(Simulation, NaNInTheStateIsCaughtWithinOneStepNamingStepAndParticle) {
  for (Integrator integrator : {Integrator::Gear5, Integrator::VelocityVerlet}) {
    for (double friction : {0.0, 0.3}) {
      SimulationConfig cfg;
      cfg.integrator = integrator;
      cfg.material.friction = friction;
      cfg.timeStep = 1e-4;
      Simulation sim = fallingGrid(3, 3, 2, cfg, 0.2);
      sim.run(50);
      // Particle 7 in free flight or in contact, its angular velocity on the frictional path.
      Particles& p = const_cast<Particles&>(sim.particles());
      if (friction > 0) {
        p.angularVelocity[7].z() = std::numeric_limits<double>::quiet_NaN();
      } else {
        p.velocity[7].x() = std::numeric_limits<double>::infinity();
      }
      try {
        sim.step();
        ADD_FAILURE() << "a broken state stepped on silently";
      } catch (const NumericalError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("step 51 "), std::string::npos) << msg;
        EXPECT_NE(msg.find("particle 7: "), std::string::npos) << msg;
        EXPECT_NE(msg.find("not finite"), std::string::npos) << msg;
      }
    }
  }
}

// A front end steers μ, E and damping mid-run (issue 8): the change takes effect, friction can be
// switched on and off, a bad value or a step the new contacts cannot resolve is refused with
// the state untouched, and setting the same material changes nothing, not even the bits.
TEST(Simulation, MaterialChangesMidRunAreAppliedOrRefusedCleanly) {
  SimulationConfig cfg = frictional(Integrator::Gear5);
  cfg.material.friction = 0.0;
  Simulation steady = fallingGrid(4, 4, 4, cfg, 0.3, 11);
  Simulation steered = fallingGrid(4, 4, 4, cfg, 0.3, 11);
  steady.run(500);
  steered.run(500);
  steered.setMaterial(steered.config().material);  // the same: a no-op
  steady.run(500);
  steered.run(500);
  EXPECT_EQ(steered.stateHash(), steady.stateHash());

  // Friction on: rotations appear (contacts between falling spheres spin them).
  Material rough = steered.config().material;
  rough.friction = 0.5;
  steered.setMaterial(rough);
  EXPECT_TRUE(steered.frictional());
  EXPECT_EQ(steered.config().material.friction, 0.5);
  steered.run(2000);
  double spin = 0;
  for (const Vec3& w : steered.particles().angularVelocity) spin = std::max(spin, w.norm());
  EXPECT_GT(spin, 0.0);
  EXPECT_GT(steered.energy().kineticRotational, 0.0);

  // Refused: out of range, and a stiffness whose contacts the step cannot resolve.
  const std::uint64_t before = steered.stateHash();
  Material bad = rough;
  bad.friction = -0.1;
  EXPECT_THROW(steered.setMaterial(bad), ConfigError);
  Material stiff = rough;
  stiff.youngModulus *= 1e6;
  EXPECT_THROW(steered.setMaterial(stiff), ConfigError);
  EXPECT_EQ(steered.stateHash(), before);
  EXPECT_EQ(steered.config().material.youngModulus, rough.youngModulus);

  // Friction off again: no rotations, and the run goes on with a finite state.
  Material smooth = rough;
  smooth.friction = 0.0;
  steered.setMaterial(smooth);
  EXPECT_FALSE(steered.frictional());
  steered.run(1000);
  for (const Vec3& w : steered.particles().angularVelocity) EXPECT_EQ(w, Vec3::Zero());
  for (const Vec3& x : steered.particles().position) EXPECT_TRUE(x.allFinite());
}

TEST(Simulation, OwnershipIsRefusedWithoutOneFlagPerParticleOrWithoutRanks) {
  Simulation sim = fallingGrid(2, 2, 2, frictional(Integrator::Gear5), 0.3);
  const std::shared_ptr<const Communicator> one = singleProcess();
  EXPECT_THROW(sim.setOwnership(std::vector<std::uint8_t>(7, 1), one), ConfigError);
  EXPECT_THROW(sim.setOwnership(std::vector<std::uint8_t>(8, 1), nullptr), ConfigError);
  // Owning every particle on one process is the exact sums of the whole run.
  Simulation exact = fallingGrid(2, 2, 2, frictional(Integrator::Gear5), 0.3);
  exact.setExactSums(true);
  sim.setOwnership(std::vector<std::uint8_t>(8, 1), one);
  sim.run(2000);
  exact.run(2000);
  EXPECT_EQ(sim.stateHash(), exact.stateHash());
  EXPECT_EQ(sim.energy().of("elastic_normal_J"), exact.energy().of("elastic_normal_J"));
  EXPECT_EQ(sim.energy().of("dissipated_normal_J"), exact.energy().of("dissipated_normal_J"));
}

TEST(Simulation, SplitAmongDomainsOfAnotherRankCountIsRefused) {
  Simulation sim = fallingGrid(2, 2, 2, frictional(Integrator::Gear5), 0.3);
  const std::shared_ptr<const Communicator> one = singleProcess();
  EXPECT_THROW(sim.splitAmong(std::make_shared<Bricks>(2, Vec3::Zero(), Vec3::Ones()), one),
               ConfigError);
  EXPECT_THROW(sim.splitAmong(nullptr, one), ConfigError);
  // One domain on one process: the run itself, and its whole state is itself.
  Simulation alone = fallingGrid(2, 2, 2, frictional(Integrator::Gear5), 0.3);
  alone.setExactSums(true);
  sim.splitAmong(std::make_shared<Bricks>(1, Vec3::Zero(), Vec3::Ones()), one);
  EXPECT_THROW(sim.splitAmong(std::make_shared<Bricks>(1, Vec3::Zero(), Vec3::Ones()), one),
               ConfigError);
  sim.run(2000);
  alone.run(2000);
  EXPECT_EQ(sim.wholeState().stateHash(), alone.stateHash());
  EXPECT_EQ(sim.stateHash(), alone.stateHash());
  EXPECT_EQ(sim.globalId(5), 5u);
  EXPECT_TRUE(sim.owns(5));
}
