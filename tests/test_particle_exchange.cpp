/// Particles that come and go between steps (Simulation::exchangeParticles) and walls taken
/// away (Simulation::removeWall): a particle removed is as if it had never been; the survivors'
/// contacts keep their springs; the tallies balance exactly and the ledger runs on; checkpoints
/// carry it all; a run may start empty and be filled; a gate taken away lets its load fall.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <vector>

#include "granular/checkpoint.hpp"
#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "physics_fixtures.hpp"
#include "temp_folder.hpp"

using namespace granular;
using granular::testing::fallingGrid;
using granular::testing::sphereMass;

namespace {

SimulationConfig frictionalConfig() {
  SimulationConfig cfg;
  cfg.material.friction = 0.5;
  cfg.integrator = Integrator::VelocityVerlet;
  cfg.threads = 1;
  cfg.timeStep = 2e-4;
  return cfg;
}

/// `sim`'s particles without particle k.
Particles without(const Particles& p, std::size_t k) {
  Particles q;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (i == k) continue;
    q.position.push_back(p.position[i]);
    q.velocity.push_back(p.velocity[i]);
    q.angularVelocity.push_back(p.angularVelocity[i]);
    q.radius.push_back(p.radius[i]);
    q.mass.push_back(p.mass[i]);
  }
  return q;
}

/// Removes the particles `remove` (ascending) from `sim`.
void removeParticles(Simulation& sim, std::vector<std::size_t> remove) {
  sim.exchangeParticles([&](const Particles&) {
    ParticleExchange x;
    x.remove = remove;
    return x;
  });
}

/// A pair's key for comparing contacts across a renumbering: its two particles' positions.
using PairKey = std::pair<std::size_t, std::size_t>;

}  // namespace

// A particle that touches nothing, removed, leaves the others exactly as a run that never had
// it: the renumbered list carries every contact and spring, and nothing else changes.
TEST(ParticleExchange, RemovingAParticleThatTouchesNothingIsAsIfItHadNeverBeen) {
  const SimulationConfig cfg = frictionalConfig();
  Simulation settled = fallingGrid(3, 3, 3, cfg, 0.2);
  settled.run(1500);  // a bed with contacts and stretched springs
  // A copy with one more particle, far above the bed, put in the middle of the numbering.
  Particles withExtra;
  const Particles& bed = settled.particles();
  const std::size_t k = 13;
  for (std::size_t i = 0; i <= bed.size(); ++i) {
    if (i == k) {
      withExtra.add(Vec3(0.15, 0.15, 20.0), 0.03, cfg.material.density);
    }
    if (i == bed.size()) break;
    withExtra.position.push_back(bed.position[i]);
    withExtra.velocity.push_back(bed.velocity[i]);
    withExtra.angularVelocity.push_back(bed.angularVelocity[i]);
    withExtra.radius.push_back(bed.radius[i]);
    withExtra.mass.push_back(bed.mass[i]);
  }
  // Both from the same state (the springs start at zero in both).
  Simulation a(withExtra, settled.walls(), cfg);
  Simulation b(without(withExtra, k), settled.walls(), cfg);
  a.run(400);
  b.run(400);
  ASSERT_EQ(without(a.particles(), k).position, b.particles().position);  // the premise
  removeParticles(a, {k});
  ASSERT_EQ(a.particles().size(), b.particles().size());
  a.run(800);
  b.run(800);
  EXPECT_EQ(a.particles().position, b.particles().position);
  EXPECT_EQ(a.particles().velocity, b.particles().velocity);
  EXPECT_EQ(a.particles().angularVelocity, b.particles().angularVelocity);
}

// Particles removed from the bed: every contact between survivors keeps its friction force
// through the exchange. The forces after it are evaluated at the corrected velocities, the
// step's at the predicted ones, so their dashpots differ by a few per cent of the force; a
// spring dropped would take the whole elastic part, up to μ F_n.
TEST(ParticleExchange, ContactsBetweenSurvivorsKeepTheirSprings) {
  const SimulationConfig cfg = frictionalConfig();
  Simulation sim = fallingGrid(3, 3, 3, cfg, 0.2);
  sim.run(2500);
  const std::vector<std::size_t> remove = {4, 22};
  struct Seen {
    Vec3 force, normal;
  };
  std::map<PairKey, Seen> before;
  sim.forEachContact([&](const ContactView& c) {
    if (c.isWall()) return;
    for (std::size_t r : remove) {
      if (c.particle == r || c.otherParticle() == r) return;
    }
    before[{c.particle, c.otherParticle()}] = {c.force, c.normal};
  });
  auto renumbered = [&](std::size_t i) {
    std::size_t shift = 0;
    for (std::size_t r : remove) shift += r < i ? 1 : 0;
    return i - shift;
  };
  ASSERT_GT(before.size(), 20u);
  removeParticles(sim, remove);
  std::map<PairKey, Vec3> after;
  sim.forEachContact([&](const ContactView& c) {
    if (!c.isWall()) after[{c.particle, c.otherParticle()}] = c.force;
  });
  auto tangential = [](const Vec3& f, const Vec3& n) { return Vec3(f - f.dot(n) * n); };
  std::size_t gripping = 0;
  for (const auto& [pair, seen] : before) {
    const PairKey now{renumbered(pair.first), renumbered(pair.second)};
    ASSERT_TRUE(after.count(now)) << pair.first << "-" << pair.second;
    const Vec3 was = tangential(seen.force, seen.normal);
    const Vec3 is = tangential(after[now], seen.normal);
    EXPECT_LT((is - was).norm(), 0.05 * seen.force.norm() + 1e-9)
        << pair.first << "-" << pair.second;
    gripping += was.norm() > 0.1 * seen.force.norm() ? 1 : 0;
  }
  EXPECT_GE(gripping, 5u);  // contacts whose friction a dropped spring would show
}

// Inserted and removed particles balance exactly, the counts follow, and the ledger's total
// runs on through an exchange (what came and went is the exchanged account).
TEST(ParticleExchange, TalliesBalanceExactlyAndTheLedgerRunsOn) {
  const SimulationConfig cfg = frictionalConfig();
  Simulation sim = fallingGrid(3, 3, 3, cfg, 0.2);
  sim.run(1500);
  const double totalBefore = sim.energy().total();
  const double massBefore = sim.particleTally().heldMass;
  const double removedMass = sim.particles().mass[3] + sim.particles().mass[20];
  Particles add;
  add.add(Vec3(0.1, 0.1, 0.9), 0.031, cfg.material.density, Vec3(0, 0, -1.0));
  add.add(Vec3(0.2, 0.2, 0.9), 0.034, cfg.material.density, Vec3(0.5, 0, 0));
  sim.exchangeParticles([&](const Particles& whole) {
    EXPECT_EQ(whole.size(), 27u);
    ParticleExchange x;
    x.remove = {3, 20};
    x.insert = add;
    x.source = 2;
    return x;
  });
  const ParticleTally t = sim.particleTally();
  EXPECT_EQ(t.held, 27u);
  EXPECT_EQ(t.inserted, 2u);
  EXPECT_EQ(t.removed, 2u);
  EXPECT_EQ(sim.insertedBy(2), 2u);
  EXPECT_EQ(sim.insertedBy(0), 0u);
  EXPECT_EQ(t.massBalance, 0.0);
  EXPECT_DOUBLE_EQ(t.removedMass, removedMass);
  EXPECT_DOUBLE_EQ(t.insertedMass, add.mass[0] + add.mass[1]);
  EXPECT_DOUBLE_EQ(t.startMass, massBefore);
  // The inserted come last, as given.
  EXPECT_EQ(sim.particles().position[25], add.position[0]);
  EXPECT_EQ(sim.particles().velocity[26], add.velocity[1]);
  const EnergyBalance e = sim.energy();
  EXPECT_NEAR(e.total(), totalBefore, 1e-12 * std::abs(e.gravityWork));
  EXPECT_NE(e.exchanged, 0.0);
  sim.run(2000);
  EXPECT_EQ(sim.particleTally().massBalance, 0.0);
}

// A checkpoint after an exchange and a wall taken away resumes bit for bit, tallies included.
class ParticleExchangeFiles : public granular::testing::TempFolderTest {
 protected:
  ParticleExchangeFiles() : TempFolderTest("granular_exchange") {}
};

TEST_F(ParticleExchangeFiles, ACheckpointAfterAnExchangeResumesBitForBit) {
  const SimulationConfig cfg = frictionalConfig();
  Simulation sim = fallingGrid(3, 3, 3, cfg, 0.2);
  sim.run(800);
  Particles add;
  add.add(Vec3(0.15, 0.15, 1.0), 0.032, cfg.material.density);
  sim.exchangeParticles([&](const Particles&) {
    ParticleExchange x;
    x.remove = {0, 9};
    x.insert = add;
    x.source = 1;
    return x;
  });
  sim.removeWall(std::size_t(sim.findWall("x-")));
  sim.run(10);
  const std::filesystem::path file = dir_ / "exchanged.ckpt";
  writeCheckpoint(sim, file, 7);
  Simulation resumed = readCheckpoint(file, 7);
  EXPECT_TRUE(resumed.walls()[std::size_t(resumed.findWall("x-"))].removed);
  EXPECT_EQ(resumed.insertedBy(1), 1u);
  sim.run(500);
  resumed.run(500);
  EXPECT_EQ(sim.stateHash(), resumed.stateHash());
  const ParticleTally a = sim.particleTally(), b = resumed.particleTally();
  EXPECT_EQ(a.removed, b.removed);
  EXPECT_EQ(a.removedMass, b.removedMass);
  EXPECT_EQ(b.massBalance, 0.0);
  EXPECT_EQ(sim.energy().total(), resumed.energy().total());
}

// A run may start with no particle (SimulationConfig::smallestRadius) and be filled: a sphere
// inserted at rest at height h above a floor touches it after sqrt(2 (h − R) / g).
TEST(ParticleExchange, AnEmptyRunFilledByInsertionFallsAsInFreeFall) {
  SimulationConfig cfg = frictionalConfig();
  cfg.smallestRadius = 0.03;
  cfg.gravity = Vec3(0, 0, -9.81);
  std::vector<Wall> walls = {{"bottom", Vec3(0, 0, 0), Vec3(0, 0, 1)}};
  Simulation sim(Particles{}, walls, cfg);
  EXPECT_EQ(sim.particleTally().held, 0u);
  sim.run(10);  // an empty run steps
  const double h = 0.5, r = 0.03;
  sim.exchangeParticles([&](const Particles& whole) {
    EXPECT_EQ(whole.size(), 0u);
    ParticleExchange x;
    x.insert.add(Vec3(0, 0, h), r, cfg.material.density);
    return x;
  });
  const double start = sim.time();
  while (sim.counters().wallContacts == 0 && sim.time() < start + 1.0) sim.step();
  const double landed = sim.time() - start;
  EXPECT_NEAR(landed, std::sqrt(2.0 * (h - r) / 9.81), 1.5 * cfg.timeStep);
  Particles tooSmall;
  tooSmall.add(Vec3(0, 0, 0.5), 0.02, cfg.material.density);
  EXPECT_THROW(sim.exchangeParticles([&](const Particles&) {
    ParticleExchange x;
    x.insert = tooSmall;
    return x;
  }),
               ConfigError);
}

// Exchanges that cannot be made are refused, and change nothing.
TEST(ParticleExchange, RefusesIndicesOutOfOrderOrRangeAndBadParticles) {
  const SimulationConfig cfg = frictionalConfig();
  Simulation sim = fallingGrid(2, 2, 2, cfg, 0.0);
  const std::uint64_t hash = sim.stateHash();
  auto exchange = [&](std::vector<std::size_t> remove, Particles add) {
    sim.exchangeParticles([&](const Particles&) {
      ParticleExchange x;
      x.remove = remove;
      x.insert = add;
      return x;
    });
  };
  EXPECT_THROW(exchange({8}, {}), ConfigError);
  EXPECT_THROW(exchange({3, 1}, {}), ConfigError);
  EXPECT_THROW(exchange({2, 2}, {}), ConfigError);
  Particles noMass;
  noMass.add(Vec3(0.1, 0.1, 0.5), 0.03, cfg.material.density);
  noMass.mass[0] = 0.0;
  EXPECT_THROW(exchange({}, noMass), ConfigError);
  Particles ragged;
  ragged.add(Vec3(0.1, 0.1, 0.5), 0.03, cfg.material.density);
  ragged.radius.push_back(0.03);
  EXPECT_THROW(exchange({}, ragged), ConfigError);
  Particles notFinite;
  notFinite.add(Vec3(0.1, 0.1, NAN), 0.03, cfg.material.density);
  EXPECT_THROW(exchange({}, notFinite), ConfigError);
  EXPECT_EQ(sim.particles().size(), 8u);
  EXPECT_EQ(sim.stateHash(), hash);
}

// A gate taken away lets the sphere resting on it fall freely: a = g at once, and the gate
// carries nothing from then on.
TEST(ParticleExchange, ASphereOnAGateTakenAwayFallsFreely) {
  SimulationConfig cfg = frictionalConfig();
  cfg.gravity = Vec3(0, 0, -9.81);
  const double r = 0.03;
  Wall gate;
  gate.name = "gate";
  gate.shape = WallShape::Frustum;  // a disc of radius 0.1 m
  gate.point = Vec3::Zero();
  gate.normal = Vec3::UnitZ();
  gate.radiusEnd = 0.1;
  Particles p;
  p.add(Vec3(0, 0, r), r, cfg.material.density);
  Simulation sim(p, {gate}, cfg);
  sim.run(3000);  // at rest on the gate
  ASSERT_NEAR(sim.walls()[0].reaction.z(), -p.mass[0] * 9.81, 1e-3 * p.mass[0] * 9.81);
  sim.removeWall(0);
  EXPECT_EQ(sim.acceleration(0), cfg.gravity);
  sim.step();
  EXPECT_EQ(sim.walls()[0].reaction, Vec3::Zero());
  EXPECT_EQ(sim.counters().wallContacts, 0u);
  EXPECT_LT(sim.particles().velocity[0].z(), 0.0);
}
