/// Walls of finite shape (docs/physics.md §2.19): rectangles, cylinders, cones and discs, still
/// or moving. A sphere at rest against a shape feels the flat-wall law at the overlap from the
/// shape's closest point, along the normal from that point, by the formulas of the geometry; a
/// moving shape's surface velocity enters the contact (a belt carries a sphere to 2/7 of its
/// speed; a drum spins a sphere up to roll with it) and the ledger counts the wall's work; a
/// checkpoint resumes a run with turning shells bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "granular/checkpoint.hpp"
#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "granular/network_frequency.hpp"
#include "granular/scene.hpp"
#include "granular/stage.hpp"
#include "physics_fixtures.hpp"
#include "temp_folder.hpp"

using namespace granular;
using granular::testing::sphereMass;

namespace {

constexpr double kR = 0.03;  // [m]

SimulationConfig config(double friction, const Vec3& gravity) {
  SimulationConfig cfg;
  cfg.material.friction = friction;
  cfg.gravity = gravity;
  cfg.threads = 1;
  cfg.timeStep = stiffestContact(cfg.material, kR, 1.0).duration / 50.0;
  return cfg;
}

Wall cylinder(const Vec3& base, const Vec3& axis, double length, double radius) {
  Wall w;
  w.name = "cylinder";
  w.shape = WallShape::Frustum;
  w.point = base;
  w.normal = axis.normalized();
  w.length = length;
  w.radiusStart = w.radiusEnd = radius;
  w.pivot = base;
  return w;
}

Wall cone(const Vec3& base, const Vec3& axis, double length, double r0, double r1) {
  Wall w = cylinder(base, axis, length, r0);
  w.name = "cone";
  w.radiusEnd = r1;
  return w;
}

Wall rectangle(const Vec3& centre, const Vec3& normal, const Vec3& edge, double a, double b) {
  Wall w;
  w.name = "rectangle";
  w.shape = WallShape::Rectangle;
  w.point = centre;
  w.normal = normal;
  w.edge = edge;
  w.halfSide[0] = a;
  w.halfSide[1] = b;
  w.pivot = centre;
  return w;
}

/// A still sphere of radius kR at x against one wall, no gravity.
Simulation stillSphere(const Vec3& x, const Wall& wall) {
  Particles p;
  p.add(x, kR, 500.0);
  return Simulation(std::move(p), {wall}, config(0.0, Vec3::Zero()));
}

/// The sphere's one contact.
ContactView onlyContact(const Simulation& sim) {
  std::vector<ContactView> seen;
  sim.forEachContact([&](const ContactView& c) { seen.push_back(c); });
  EXPECT_EQ(seen.size(), 1u);
  return seen.empty() ? ContactView{} : seen.front();
}

/// The flat-wall law of a still contact: the force on the sphere −c R h n, at the point
/// x + (R − h/2) n, for the expected overlap h and normal n (out of the sphere into the wall).
void expectFlatLaw(const Simulation& sim, const Vec3& x, double h, const Vec3& n) {
  const ContactView c = onlyContact(sim);
  ASSERT_TRUE(c.isWall());
  EXPECT_NEAR(c.overlap, h, 1e-12 * kR);
  EXPECT_LT((c.normal - n).norm(), 1e-12);
  const Vec3 force = -sim.config().material.normalCoefficient() * kR * h * n;
  EXPECT_LT((c.force - force).norm(), 1e-9 * force.norm());
  EXPECT_LT((c.point - (x + (kR - 0.5 * h) * n)).norm(), 1e-12 * kR);
}

}  // namespace

TEST(WallShapes, ASphereInsideOrOutsideACylinderOfAnyAxisIsPushedAlongItsRadius) {
  // A cylinder on a skew axis; the sphere at overlap h against its inner face, then its outer.
  const Vec3 axis = Vec3(1, 2, 2) / 3.0;
  const Vec3 base(0.1, -0.2, 0.3);
  const double radius = 0.2, h = 2e-4, along = 0.35;
  const Vec3 radial = axis.cross(Vec3::UnitX()).normalized();
  const Wall wall = cylinder(base, axis, 1.0, radius);
  const Vec3 inside = base + along * axis + (radius - (kR - h)) * radial;
  expectFlatLaw(stillSphere(inside, wall), inside, h, radial);
  const Vec3 outside = base + along * axis + (radius + (kR - h)) * radial;
  expectFlatLaw(stillSphere(outside, wall), outside, h, -radial);
}

TEST(WallShapes, ASphereInAConeIsPushedAlongTheConesNormalAndOverItsRimAlongTheRim) {
  // A hopper: radius 0.1 at the base, 0.3 at the top, 0.4 above. Its half-angle α has
  // tan α = 0.2/0.4; a point at height z and radius ρ inside is (r(z) − ρ) cos α from it.
  const double r0 = 0.1, r1 = 0.3, length = 0.4, h = 1e-4;
  const Wall wall = cone(Vec3::Zero(), Vec3::UnitZ(), length, r0, r1);
  const double alpha = std::atan((r1 - r0) / length);
  const double z = 0.2, surface = r0 + z * std::tan(alpha);
  const double rho = surface - (kR - h) / std::cos(alpha);
  const Vec3 azimuth = Vec3(3, 4, 0) / 5.0;
  const Vec3 x = z * Vec3::UnitZ() + rho * azimuth;
  const Vec3 n = std::cos(alpha) * azimuth - std::sin(alpha) * Vec3::UnitZ();
  expectFlatLaw(stillSphere(x, wall), x, h, n);
  // Over the top rim, outside: the closest point is the rim, d = (0.5 R, 0.5 R) from it.
  const Vec3 over = (length + 0.5 * kR) * Vec3::UnitZ() + (r1 + 0.5 * kR) * azimuth;
  const Vec3 toRim = -(Vec3::UnitZ() + azimuth).normalized();
  expectFlatLaw(stillSphere(over, wall), over, kR - std::sqrt(0.5) * kR, toRim);
}

TEST(WallShapes, ARectangleIsTouchedOnEitherFaceAlongItsNormalAndBeyondItsOutlineAtItsRim) {
  const Vec3 normal = Vec3(0, 0, 1), edge = Vec3(1, 0, 0);
  const Wall wall = rectangle(Vec3::Zero(), normal, edge, 0.1, 0.2);
  const double h = 3e-4;
  const Vec3 above(0.09, -0.19, kR - h), below(-0.05, 0.1, -(kR - h));
  expectFlatLaw(stillSphere(above, wall), above, h, -normal);
  expectFlatLaw(stillSphere(below, wall), below, h, normal);
  // Beyond the x edge, and beyond a corner: the closest point is on the rim.
  const Vec3 edgeOffset = Vec3(0.6, 0, 0.8) * (kR - h);
  const Vec3 atEdge = Vec3(0.1, 0.05, 0) + edgeOffset;
  expectFlatLaw(stillSphere(atEdge, wall), atEdge, h, -edgeOffset.normalized());
  const Vec3 cornerOffset = Vec3(-0.48, -0.6, 0.64) * (kR - h);
  const Vec3 atCorner = Vec3(-0.1, -0.2, 0) + cornerOffset;
  expectFlatLaw(stillSphere(atCorner, wall), atCorner, h, -cornerOffset.normalized());
}

TEST(WallShapes, ADiscTouchesAlongItsAxisAndAnAnnulusNotOverItsHole) {
  Wall disc = cylinder(Vec3::Zero(), Vec3::UnitZ(), 0.0, 0.0);
  disc.radiusEnd = 0.2;
  const double h = 1e-4;
  const Vec3 x(0.05, 0.1, kR - h);
  expectFlatLaw(stillSphere(x, disc), x, h, -Vec3::UnitZ());
  Wall annulus = disc;
  annulus.radiusStart = 0.15;
  Particles p;
  p.add(x, kR, 500.0);
  const Simulation sim(std::move(p), {annulus}, config(0.0, Vec3::Zero()));
  int contacts = 0;
  sim.forEachContact([&](const ContactView&) { ++contacts; });
  EXPECT_EQ(contacts, 0);  // 0.112 m from the axis, more than R inside the hole's 0.15 m rim
}

TEST(WallShapes, ASphereRestsOnATiltedRectangleUnderItsWeight) {
  // A rectangle whose normal leans 0.3 rad from z, gravity along −normal: at rest the reaction
  // is the weight, along the normal.
  const Vec3 normal = Vec3(std::sin(0.3), 0, std::cos(0.3));
  const Wall wall =
      rectangle(Vec3::Zero(), normal, normal.cross(Vec3::UnitY()).normalized(), 0.2, 0.2);
  SimulationConfig cfg = config(0.0, -9.81 * normal);
  Particles p;
  p.add(Vec3(0.01, 0.02, 0) + kR * normal, kR, 500.0);
  Simulation sim(std::move(p), {wall}, cfg);
  sim.advanceTo(2.0);
  const double weight = sphereMass(kR, 500.0) * 9.81;
  EXPECT_LT((sim.walls()[0].reaction + weight * normal).norm(), 1e-9 * weight);
}

TEST(WallShapes, ABeltCarriesASphereDroppedOnItToTwoSeventhsOfItsSpeed) {
  // A rectangle sliding along x at v under a sphere at rest: friction μ m g accelerates the
  // centre (v_c = μ g t) and spins it back until its contact point moves with the belt, at
  // t* = 2v/(7 μ g), v_c = 2v/7, spin −(5/7) v/R (a solid sphere: I = (2/5) m R²). A stiff
  // material, so that the tangential spring reaches μ F_n at once; after t* the sphere rocks on
  // the spring about the rolling motion, which the mean over many periods gives.
  const double v = 0.5, mu = 0.5, g = 9.81;
  Wall belt = rectangle(Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitX(), 0.5, 0.5);
  belt.velocity = Vec3(v, 0, 0);
  SimulationConfig cfg = config(mu, Vec3(0, 0, -g));
  cfg.material.youngModulus = 1e8;
  cfg.material.shearModulus = 1e8 / 2.6;
  cfg.timeStep = stiffestContact(cfg.material, kR, 1.0).duration / 50.0;
  const double m = sphereMass(kR, cfg.material.density);
  Particles p;
  p.add(Vec3(0, 0, kR - m * g / (cfg.material.normalCoefficient() * kR)), kR, cfg.material.density);
  Simulation sim(std::move(p), {belt}, cfg);
  sim.advanceTo(0.02);  // slipping until t* = 29 ms
  EXPECT_NEAR(sim.particles().velocity[0].x(), mu * g * sim.time(), 1e-3 * mu * g * sim.time());
  sim.advanceTo(0.04);
  double speed = 0.0, spin = 0.0;
  std::uint64_t samples = 0;
  while (sim.time() < 0.2) {
    sim.step();
    speed += sim.particles().velocity[0].x();
    spin += sim.particles().angularVelocity[0].y();
    ++samples;
  }
  EXPECT_NEAR(speed / double(samples), 2.0 * v / 7.0, 0.005 * 2.0 * v / 7.0);
  EXPECT_NEAR(spin / double(samples), -5.0 * v / (7.0 * kR), 0.005 * 5.0 * v / (7.0 * kR));
}

TEST(WallShapes, ATurningDrumSpinsARestingSphereByCoulombUntilItRollsWithItsWall) {
  // A drum of radius 0.2 m turning at 2 rad/s about its horizontal axis (y); a sphere at rest
  // at its bottom. The wall slides under it at ω R_d: friction is μ F_n while it slips, then
  // the sphere rolls with the wall (its contact point moves with the wall's). The ledger counts
  // the drum's work: the energy balance closes on it.
  const double rd = 0.2, omega = 2.0, mu = 0.4, g = 9.81;
  Wall drum = cylinder(Vec3(0, -0.1, 0), Vec3::UnitY(), 0.2, rd);
  drum.angularVelocity = Vec3(0, omega, 0);
  SimulationConfig cfg = config(mu, Vec3(0, 0, -g));
  const double m = sphereMass(kR, cfg.material.density);
  Particles p;
  p.add(Vec3(0, 0, -rd + kR - m * g / (cfg.material.normalCoefficient() * kR)), kR,
        cfg.material.density);
  Simulation sim(std::move(p), {drum}, cfg);
  const double start = sim.energy().total();
  for (int k = 0; k < 40; ++k) sim.step();  // the spring has reached the Coulomb limit
  {
    const ContactView c = onlyContact(sim);
    const double fn = c.force.dot(c.normal);
    const Vec3 ft = c.force - fn * c.normal;
    EXPECT_NEAR(ft.norm(), mu * std::abs(fn), 1e-9 * std::abs(fn));
    // Along the wall's surface velocity at the contact, ω × (C − pivot): −x at the bottom.
    EXPECT_GT(-ft.x(), 0.999 * ft.norm());
  }
  sim.advanceTo(1.0);
  const ContactView c = onlyContact(sim);
  const Particles& s = sim.particles();
  const Vec3 sphereAtContact = s.velocity[0] + s.angularVelocity[0].cross(c.point - s.position[0]);
  const Vec3 wallAtContact = sim.walls()[0].velocityAt(c.point);
  EXPECT_GT(wallAtContact.norm(), 0.99 * omega * rd);
  EXPECT_LT((sphereAtContact - wallAtContact).norm(), 1e-3 * omega * rd);
  const EnergyBalance e = sim.energy();
  EXPECT_GT(e.wallWork, 0.0);
  EXPECT_LT(std::abs(e.total() - start), 1e-3 * e.wallWork);
}

class WallShapesCheckpoint : public granular::testing::TempFolderTest {
 protected:
  WallShapesCheckpoint() : TempFolderTest("granular_wall_shapes") {}
};

TEST_F(WallShapesCheckpoint, ResumesARunWithTurningAndSlidingShellsBitForBit) {
  Wall drum = cylinder(Vec3(0.5, 0.3, 0.5), Vec3::UnitY(), 0.4, 0.45);
  drum.angularVelocity = Vec3(0, 3.0, 0);
  Wall paddle = rectangle(Vec3(0.5, 0.5, 0.2), Vec3::UnitZ(), Vec3::UnitX(), 0.1, 0.1);
  paddle.angularVelocity = Vec3(0, 3.0, 0);
  paddle.pivot = Vec3(0.5, 0.5, 0.5);
  Wall hopper = cone(Vec3(0.5, 0.5, 0.2), Vec3::UnitZ(), 0.3, 0.05, 0.4);
  hopper.velocity = Vec3(0, 0, 0.01);
  SimulationConfig cfg = config(0.5, Vec3(0, 0, -9.81));
  Particles p;
  for (int k = 0; k < 27; ++k) {
    p.add(Vec3(0.4 + 0.08 * (k % 3), 0.42 + 0.08 * (k / 3 % 3), 0.3 + 0.08 * (k / 9)), kR, 500.0);
  }
  Simulation first(std::move(p), {drum, paddle, hopper}, cfg);
  first.run(400);
  const std::filesystem::path file = dir_ / "shells.ckpt";
  writeCheckpoint(first, file, 7);
  first.run(600);
  Simulation resumed = readCheckpoint(file, 7);
  resumed.run(600);
  ASSERT_EQ(first.particles().size(), resumed.particles().size());
  for (std::size_t i = 0; i < first.particles().size(); ++i) {
    EXPECT_EQ(first.particles().position[i], resumed.particles().position[i]) << i;
    EXPECT_EQ(first.particles().angularVelocity[i], resumed.particles().angularVelocity[i]) << i;
  }
  for (std::size_t w = 0; w < 3; ++w) {
    EXPECT_EQ(first.walls()[w].point, resumed.walls()[w].point);
    EXPECT_EQ(first.walls()[w].normal, resumed.walls()[w].normal);
    EXPECT_EQ(first.walls()[w].impulse, resumed.walls()[w].impulse);
    EXPECT_EQ(first.walls()[w].travel, resumed.walls()[w].travel);
  }
  EXPECT_GT(first.counters().wallContacts, 0u);
}

TEST(WallShapes, TheStepsBoundCountsAShellsContactsAndApproachesAsAPlanes) {
  // A sphere pressed into a cone at overlap h, and one approaching a cylinder across a gap at
  // speed u (relative to the turning wall's surface): the network's bound is the same number as
  // for the sphere against a plane at that overlap, or approaching it so.
  const double h = 2e-4, gap = 1e-4, u = 0.5;
  const Wall hopper = cone(Vec3::Zero(), Vec3::UnitZ(), 0.4, 0.1, 0.3);
  const double alpha = std::atan(0.5), z = 0.2, surface = 0.1 + z * 0.5;
  const Vec3 radial = Vec3::UnitX();
  const Vec3 pressed = z * Vec3::UnitZ() + (surface - (kR - h) / std::cos(alpha)) * radial;
  const Wall floor{"floor", Vec3::Zero(), Vec3::UnitZ()};
  auto bound = [](const Vec3& x, const Vec3& v, const Wall& wall) {
    Particles p;
    p.add(x, kR, 500.0, v);
    const Simulation sim(std::move(p), {wall}, config(0.3, Vec3::Zero()));
    return networkFrequencyBound(sim, 32, 1e-3);
  };
  const NetworkFrequency onCone = bound(pressed, Vec3::Zero(), hopper);
  const NetworkFrequency onPlane = bound(Vec3(0, 0, kR - h), Vec3::Zero(), floor);
  EXPECT_EQ(onCone.contacts, 1u);
  EXPECT_NEAR(onCone.omegaMax, onPlane.omegaMax, 1e-12 * onPlane.omegaMax);
  // The drum turns at 2 rad/s: its surface moves across the approach, not along it.
  Wall drum = cylinder(Vec3(0, -0.1, 0), Vec3::UnitY(), 0.2, 0.2);
  drum.angularVelocity = Vec3(0, 2, 0);
  const NetworkFrequency toDrum = bound(Vec3(0, 0, -0.2 + kR + gap), Vec3(0, 0, -u), drum);
  const NetworkFrequency toPlane = bound(Vec3(0, 0, kR + gap), Vec3(0, 0, -u), floor);
  EXPECT_EQ(toDrum.approaching, 1u);
  EXPECT_NEAR(toDrum.fastestApproach, u, 1e-12);
  EXPECT_NEAR(toDrum.omegaMax, toPlane.omegaMax, 1e-9 * toPlane.omegaMax);
}

TEST(WallShapes, ABadShapeIsRefusedByName) {
  Wall w = cylinder(Vec3::Zero(), Vec3::UnitZ(), 0.0, 0.2);
  EXPECT_THROW(stillSphere(Vec3(0, 0, 1), w), ConfigError);  // no length, equal radii
  w = rectangle(Vec3::Zero(), Vec3::UnitZ(), Vec3(1, 0, 0.1), 0.1, 0.1);
  EXPECT_THROW(stillSphere(Vec3(0, 0, 1), w), ConfigError);  // edge out of the plane
  Wall plane{"floor", Vec3::Zero(), Vec3::UnitZ()};
  plane.angularVelocity = Vec3(0, 0, 1);
  try {
    stillSphere(Vec3(0, 0, 1), plane);
    ADD_FAILURE() << "a turning infinite plane was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("wall floor"), std::string::npos) << e.what();
  }
}

namespace {

/// A shipped scene, run through its stages.
Simulation runShippedScene(const std::string& name) {
  const Scene scene =
      loadScene(std::filesystem::path(GRANULAR_SOURCE_DIR) / "assets/scenes" / name);
  Simulation sim = buildSimulation(scene);
  for (const StageSpec& stage : scene.stages) runStage(sim, stage, scene.output, StageObserver{});
  return sim;
}

/// The particles' weight [N].
double bedWeight(const Simulation& sim) {
  double weight = 0.0;
  for (double m : sim.particles().mass) weight += m * 9.81;
  return weight;
}

/// The walls' vertical reactions together against the particles' weight, as a fraction of it.
double weightCarried(const Simulation& sim) {
  double carried = 0.0;
  for (const Wall& w : sim.walls()) carried -= w.reaction.z();
  return carried / bedWeight(sim);
}

}  // namespace

TEST(WallShapes, TheShippedSiloAndHopperCarryTheirBedsAtRestOnTheirWalls) {
  // Settled (the stage ends on the kinetic energy), the bed's weight rests on the walls: the
  // silo's floor and cylinder, the hopper's cone, bin and gate, the meshed bin. No wall holds
  // the bed down or up by more than a hair: a side wall's friction takes the sign of the last
  // settling motion along it, and the silo's cylinder, which a poured bed hardly loads,
  // ends near zero, on either side: within 5 % of the weight, since over the last 0.03 s of
  // the stage its vertical reaction still swings between 1 % and 4.5 % of it as the bed
  // creeps (a sign error in a wall's friction puts tens of per cent there).
  for (const char* name : {"silo.toml", "hopper.toml", "mesh-bin.toml"}) {
    const Simulation sim = runShippedScene(name);
    EXPECT_NEAR(weightCarried(sim), 1.0, 0.03) << name;
    for (const Wall& w : sim.walls()) {
      EXPECT_LT(w.reaction.z(), 0.05 * bedWeight(sim)) << name << " " << w.name;
    }
  }
}

TEST(WallShapes, TheShippedDrumLiftsItsBedOnTheRisingSide) {
  // The drum turns at +2 rad/s about y: its bottom moves towards −x and drags the bed up the
  // −x side. No particle leaves the drum.
  const Simulation sim = runShippedScene("drum.toml");
  const Particles& p = sim.particles();
  double meanX = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    meanX += p.position[i].x() / double(p.size());
    EXPECT_LT(std::hypot(p.position[i].x(), p.position[i].z()) + p.radius[i], 0.15 + 1e-3) << i;
  }
  EXPECT_LT(meanX, -0.01);
}
