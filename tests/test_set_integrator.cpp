/// Simulation::setIntegrator: a switch keeps the state, the clock and the tangential springs,
/// and the run then goes on exactly as a run of the new integrator from that state would.
#include <gtest/gtest.h>

#include <filesystem>
#include <vector>

#include "granular/checkpoint.hpp"
#include "physics_fixtures.hpp"

using namespace granular;
using granular::testing::fallingGrid;

namespace {

SimulationConfig frictional(Integrator integrator) {
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.timeStep = 1.5e-4;
  cfg.integrator = integrator;
  return cfg;
}

}  // namespace

TEST(SetIntegrator, GearSwitchedAtTheStartStepsLikeVelocityVerlet) {
  // Freshly built, a Gear and a Verlet simulation of one scene hold the same state (Gear's
  // higher derivatives start at zero): switched at step 0, the Gear one must follow the Verlet
  // one bit for bit, which it can only do if it really integrates with Verlet.
  Simulation gear = fallingGrid(4, 4, 3, frictional(Integrator::Gear5), 0.3);
  Simulation verlet = fallingGrid(4, 4, 3, frictional(Integrator::VelocityVerlet), 0.3);
  Simulation switched = fallingGrid(4, 4, 3, frictional(Integrator::Gear5), 0.3);
  switched.setIntegrator(Integrator::VelocityVerlet);
  EXPECT_EQ(switched.config().integrator, Integrator::VelocityVerlet);
  switched.run(1500);
  verlet.run(1500);
  gear.run(1500);
  EXPECT_EQ(switched.stateHash(), verlet.stateHash());
  EXPECT_NE(switched.stateHash(), gear.stateHash());
}

TEST(SetIntegrator, ARestoredMidRunStateKeepsItsSpringsAcrossTheSwitch) {
  Simulation gear = fallingGrid(4, 4, 3, frictional(Integrator::Gear5), 0.3);
  gear.run(1500);  // landed: contacts with tangential springs
  ASSERT_GT(gear.energy().of("elastic_tangential_J"), 0.0);
  const auto file = std::filesystem::temp_directory_path() / "granular_test_set_integrator.ckpt";
  writeCheckpoint(gear, file, 0);
  Simulation switched = readCheckpoint(file);
  std::filesystem::remove(file);
  switched.setIntegrator(Integrator::VelocityVerlet);
  EXPECT_EQ(switched.stateHash(), gear.stateHash());
  EXPECT_EQ(switched.time(), gear.time());
  EXPECT_EQ(switched.stepCount(), gear.stepCount());
  EXPECT_EQ(switched.energy().of("elastic_tangential_J"), gear.energy().of("elastic_tangential_J"));
  std::vector<ContactView> before, after;
  gear.forEachContact([&](const ContactView& c) { before.push_back(c); });
  switched.forEachContact([&](const ContactView& c) { after.push_back(c); });
  ASSERT_EQ(before.size(), after.size());
  for (std::size_t k = 0; k < before.size(); ++k) {
    EXPECT_EQ(before[k].force, after[k].force) << "contact " << k;
  }
  // And it moves on under the new scheme: one step already differs from Gear's.
  gear.step();
  switched.step();
  EXPECT_NE(switched.stateHash(), gear.stateHash());
}

TEST(SetIntegrator, VerletToGearStartsLikeANewGearRun) {
  // Back to Gear at step 0: the same as a Gear run from the start (zero higher derivatives).
  Simulation gear = fallingGrid(3, 3, 2, frictional(Integrator::Gear5), 0.3);
  Simulation switched = fallingGrid(3, 3, 2, frictional(Integrator::VelocityVerlet), 0.3);
  switched.setIntegrator(Integrator::Gear5);
  gear.run(600);
  switched.run(600);
  EXPECT_EQ(switched.stateHash(), gear.stateHash());
}
