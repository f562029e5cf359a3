/// A wall's own friction μ_w (Wall::friction, the scene's `[[walls]] friction`): a belt drags a
/// sphere by μ_w, not by the particles' μ, through the force pass and the contacts reported;
/// walls of two frictions in one chunk each keep their own; a frictionless wall under
/// frictional particles drags nothing; checkpoints carry μ_w; frictionless particles refuse a
/// wall with friction.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "granular/checkpoint.hpp"
#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "physics_fixtures.hpp"
#include "temp_folder.hpp"

using namespace granular;
using granular::testing::sphereMass;

namespace {

constexpr double kR = 0.03;    // [m]
constexpr double kG = 9.81;    // [m/s²]
constexpr double kBelt = 0.5;  // the belts' speed [m/s]

/// A stiff material, so that the tangential spring reaches μ F_n at once.
SimulationConfig stiffConfig(double friction) {
  SimulationConfig cfg;
  cfg.material.friction = friction;
  cfg.material.youngModulus = 1e8;
  cfg.material.shearModulus = 1e8 / 2.6;
  cfg.gravity = Vec3(0, 0, -kG);
  cfg.threads = 1;
  cfg.timeStep = stiffestContact(cfg.material, kR, 1.0).duration / 50.0;
  return cfg;
}

/// A square belt centred at x = `at`, sliding along x at kBelt.
Wall belt(const std::string& name, double at, std::optional<double> friction) {
  Wall w;
  w.name = name;
  w.shape = WallShape::Rectangle;
  w.point = Vec3(at, 0, 0);
  w.normal = Vec3::UnitZ();
  w.edge = Vec3::UnitX();
  w.halfSide[0] = w.halfSide[1] = 0.4;
  w.pivot = w.point;
  w.velocity = Vec3(kBelt, 0, 0);
  w.friction = friction;
  return w;
}

/// A sphere at rest on z = 0 at its static overlap, at x = `at`.
void addResting(Particles& p, const SimulationConfig& cfg, double at) {
  const double m = sphereMass(kR, cfg.material.density);
  p.add(Vec3(at, 0, kR - m * kG / (cfg.material.normalCoefficient() * kR)), kR,
        cfg.material.density);
}

/// The mean centre speed of sphere i over [from, to] s: the sphere rocks on its spring about
/// the rolling motion once it grips.
double meanSpeed(Simulation& sim, std::size_t i, double from, double to) {
  sim.advanceTo(from);
  double sum = 0.0;
  std::uint64_t samples = 0;
  while (sim.time() < to) {
    sim.step();
    sum += sim.particles().velocity[i].x();
    ++samples;
  }
  return sum / double(samples);
}

}  // namespace

TEST(WallFriction, TwoBeltsOfTwoFrictionsEachDragTheirSphereByTheirOwn) {
  // Particles of μ = 0.5 on two belts: "slippery" with μ_w = 0.2 and "plain" with the
  // particles' μ. While a sphere slips, v_c = μ_w g t; it grips at t* = 2v/(7 μ_w g) (20 ms and
  // 73 ms), and then moves at 2v/7 whatever μ_w (a solid sphere, I = (2/5) m R²). Both spheres
  // share the block, so their wall contacts share the force pass's chunks: each contact must
  // take its own wall's law.
  const double muWall = 0.2, mu = 0.5;
  const SimulationConfig cfg = stiffConfig(mu);
  Particles p;
  addResting(p, cfg, 0.0);
  addResting(p, cfg, 1.0);
  Simulation sim(std::move(p), {belt("slippery", 0.0, muWall), belt("plain", 1.0, std::nullopt)},
                 cfg);
  sim.advanceTo(0.015);
  const double t = sim.time();
  EXPECT_NEAR(sim.particles().velocity[0].x(), muWall * kG * t, 1e-3 * muWall * kG * t);
  EXPECT_NEAR(sim.particles().velocity[1].x(), mu * kG * t, 1e-3 * mu * kG * t);
  // The contacts reported (the measuring pass) carry the same laws: |F_t| = μ_w F_n.
  int seen = 0;
  sim.forEachContact([&](const ContactView& c) {
    ASSERT_TRUE(c.isWall());
    const double fn = std::abs(c.force.dot(c.normal));
    const double ft = (c.force - c.force.dot(c.normal) * c.normal).norm();
    EXPECT_NEAR(ft, (c.otherIndex == 0 ? muWall : mu) * fn, 1e-9 * fn) << "wall " << c.otherIndex;
    ++seen;
  });
  EXPECT_EQ(seen, 2);
  sim.advanceTo(0.05);
  EXPECT_NEAR(sim.particles().velocity[0].x(), muWall * kG * sim.time(),
              1e-3 * muWall * kG * sim.time());
  const double rolling = 2.0 * kBelt / 7.0;
  EXPECT_NEAR(meanSpeed(sim, 0, 0.1, 0.3), rolling, 0.005 * rolling);
}

TEST(WallFriction, AFrictionlessWallUnderFrictionalParticlesDragsNothing) {
  const SimulationConfig cfg = stiffConfig(0.5);
  Particles p;
  addResting(p, cfg, 0.0);
  Simulation sim(std::move(p), {belt("ice", 0.0, 0.0)}, cfg);
  sim.advanceTo(0.1);
  EXPECT_EQ(sim.particles().velocity[0].x(), 0.0);
  EXPECT_EQ(sim.particles().angularVelocity[0].norm(), 0.0);
  EXPECT_GT(sim.counters().wallContacts, 0u);
}

class WallFrictionCheckpoint : public granular::testing::TempFolderTest {
 protected:
  WallFrictionCheckpoint() : TempFolderTest("granular_wall_friction") {}
};

TEST_F(WallFrictionCheckpoint, CarriesEachWallsFrictionAndResumesBitForBit) {
  const SimulationConfig cfg = stiffConfig(0.5);
  Particles p;
  addResting(p, cfg, 0.0);
  addResting(p, cfg, 1.0);
  Simulation first(std::move(p), {belt("slippery", 0.0, 0.2), belt("plain", 1.0, std::nullopt)},
                   cfg);
  first.advanceTo(0.01);
  const std::filesystem::path file = dir_ / "friction.ckpt";
  writeCheckpoint(first, file, 7);
  first.advanceTo(0.05);
  Simulation resumed = readCheckpoint(file, 7);
  EXPECT_EQ(resumed.walls()[0].friction, std::optional<double>(0.2));
  EXPECT_FALSE(resumed.walls()[1].friction.has_value());
  resumed.advanceTo(0.05);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(first.particles().position[i], resumed.particles().position[i]) << i;
    EXPECT_EQ(first.particles().velocity[i], resumed.particles().velocity[i]) << i;
  }
}

TEST(WallFriction, FrictionlessParticlesRefuseAWallWithFriction) {
  SimulationConfig cfg = stiffConfig(0.0);
  Particles p;
  addResting(p, cfg, 0.0);
  try {
    Simulation sim(std::move(p), {belt("rough", 0.0, 0.3)}, cfg);
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("wall rough: friction = 0.3 needs frictional particles"),
              std::string::npos)
        << e.what();
  }
  // A frictionless wall is fine; a material turned frictionless under a rough wall is not.
  Particles q;
  addResting(q, cfg, 0.0);
  Simulation sim(std::move(q), {belt("smooth", 0.0, 0.0)}, stiffConfig(0.5));
  EXPECT_NO_THROW(sim.setMaterial(stiffConfig(0.4).material));
  Particles r;
  addResting(r, cfg, 0.0);
  Simulation rough(std::move(r), {belt("rough", 0.0, 0.3)}, stiffConfig(0.5));
  EXPECT_THROW(rough.setMaterial(stiffConfig(0.0).material), ConfigError);
  EXPECT_EQ(rough.config().material.friction, 0.5);
}
