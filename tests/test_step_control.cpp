/// The step control (StepControl, docs/physics.md §2.16): Gear's order across step changes, a
/// step that lands on the times asked for, a fixed step that a stiffening contact crosses
/// (on_unstable stop and warn), and time_step = "auto" on a bed that falls, collides and
/// settles: the balance closes as at a fixed step and the chosen steps stay within the network's;
/// the checks of a still automatic step further apart, back to the least where it moves, and the
/// gap across a checkpoint.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "granular/checkpoint.hpp"
#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "granular/impact_probe.hpp"
#include "granular/network_step.hpp"
#include "network_matrices.hpp"
#include "physics_fixtures.hpp"
#include "temp_folder.hpp"

using namespace granular;
using granular::testing::largestEigenvalue;
using granular::testing::networkMatrix;

namespace {

constexpr double kR = 0.03;  // [m]

/// A sphere resting on a Hooke floor spring (no damping, no friction) pressed in by half its
/// equilibrium overlap more: it oscillates about the equilibrium with h(t) = h_eq + A cos ωt,
/// ω = √(k/m), never leaving the floor (a smooth linear oscillator).
struct Oscillator {
  Simulation sim;
  double omega, equilibrium, amplitude;
};

Oscillator floorOscillator(double dt) {
  SimulationConfig cfg;
  cfg.material.normalDamping = 0.0;
  cfg.integrator = Integrator::Gear5;
  cfg.threads = 1;
  cfg.timeStep = dt;
  const double m = granular::testing::sphereMass(kR, cfg.material.density);
  const double k = cfg.material.normalCoefficient() * kR;  // Hooke on a wall: κ R
  const double equilibrium = m * 9.81 / k, amplitude = 0.5 * equilibrium;
  Particles p;
  p.add(Vec3(0.5, 0.5, kR - equilibrium - amplitude), kR, cfg.material.density);
  Oscillator o{Simulation(std::move(p), {Wall{"floor", Vec3::Zero(), Vec3::UnitZ()}}, cfg),
               std::sqrt(k / m), equilibrium, amplitude};
  return o;
}

/// |h(T) − exact| after two periods, at steps dt, or alternating dt and 0.6 dt every 7 steps.
double oscillatorError(double dt, bool changing) {
  Oscillator o = floorOscillator(dt);
  const double end = 2.0 * 2.0 * std::numbers::pi / o.omega;
  for (long k = 0; o.sim.time() < end - 1e-12; ++k) {
    if (changing && k % 7 == 0) o.sim.setTimeStep((k / 7) % 2 == 0 ? dt : 0.6 * dt);
    if (o.sim.time() + o.sim.config().timeStep > end) o.sim.setTimeStep(end - o.sim.time());
    o.sim.step();
  }
  const double h = kR - o.sim.particles().position[0].z();
  return std::abs(h - (o.equilibrium + o.amplitude * std::cos(o.omega * o.sim.time())));
}

/// The paper's frictional Hooke material, velocity Verlet at time_step = "auto", one thread.
SimulationConfig paperMaterialAtAuto() {
  SimulationConfig cfg;
  cfg.material.youngModulus = 0.3e6;
  cfg.material.shearModulus = 0.11e6;
  cfg.material.normalDamping = 60.0;
  cfg.material.tangentialDamping = 10.0;
  cfg.material.friction = 0.3;
  cfg.integrator = Integrator::VelocityVerlet;
  cfg.threads = 1;
  cfg.step.automatic = true;
  return cfg;
}

}  // namespace

TEST(StepControl, GearKeepsItsOrderAcrossStepChanges) {
  // Gear's derivatives are stored unscaled (x''' etc., not x''' Δt³/3!): a new step scales them
  // into the corrector's variables afresh, which is the Nordsieck rescaling by (Δt'/Δt)^k. The
  // error after two periods falls by 2^p per halving of Δt; with the step changing every 7 steps
  // the order is the constant step's.
  const double period = 2.0 * std::numbers::pi / floorOscillator(1e-5).omega;
  const double coarse = period / 120, fine = period / 240;  // t_c/60, t_c/120
  const double constantOrder =
      std::log2(oscillatorError(coarse, false) / oscillatorError(fine, false));
  const double changingOrder =
      std::log2(oscillatorError(coarse, true) / oscillatorError(fine, true));
  std::printf("Gear5 order: constant step %.2f, changing step %.2f\n", constantOrder,
              changingOrder);
  // Gear5 with c0 = 3/20 (the corrector for velocity-dependent forces) converges at about
  // fourth order on this oscillator (3.7 measured); the changing step keeps it.
  EXPECT_GT(constantOrder, 3.5);
  EXPECT_GT(changingOrder, constantOrder - 0.2);
  EXPECT_LT(oscillatorError(fine, true), 1e-6 * floorOscillator(fine).amplitude);
}

TEST(StepControl, AdvanceToLandsOnTheTimeAskedFor) {
  for (bool automatic : {false, true}) {
    SimulationConfig cfg;
    cfg.material.friction = 0.3;
    cfg.timeStep = stiffestContact(cfg.material, kR, 1.0).duration / 60;
    cfg.step.automatic = automatic;
    Simulation sim = granular::testing::fallingGrid(3, 3, 3, cfg, 0.3);
    for (double t : {0.0123, 0.05, 0.0500001, 0.3}) {
      sim.advanceTo(t);
      EXPECT_EQ(sim.time(), t) << automatic;
    }
    // The shortened steps are never longer than the step asked for or chosen, and only the
    // stretches that reach a time are shortened (at most a few steps per time).
    EXPECT_LE(sim.counters().largestStep,
              automatic ? stiffestContact(cfg.material, kR, 1.0).duration / 10 : cfg.timeStep);
    EXPECT_GT(sim.counters().smallestStep, 0.0);
    EXPECT_THROW(sim.advanceTo(0.2), ConfigError);  // before the clock
  }
}

namespace {

/// An undamped Hertz sphere falling onto the floor from 0.1 m, at a fixed Gear5 step the
/// scene's stated impact speed allows (0.05 m/s: a long, soft contact) but its real impact
/// (1.4 m/s, much stiffer at its peak overlap) does not.
Simulation hertzDrop(OnUnstable onUnstable) {
  SimulationConfig cfg;
  cfg.material.normalLaw = NormalLaw::Hertz;
  cfg.material.normalDamping = 0.0;
  cfg.integrator = Integrator::Gear5;
  cfg.impactSpeed = 0.05;
  cfg.threads = 1;
  cfg.timeStep = 0.99 * maxStableStep(stiffestContact(cfg.material, kR, 0.05), Integrator::Gear5);
  cfg.step.onUnstable = onUnstable;
  Particles p;
  p.add(Vec3(0.5, 0.5, kR + 0.1), kR, cfg.material.density);
  return Simulation(std::move(p), {Wall{"floor", Vec3::Zero(), Vec3::UnitZ()}}, cfg);
}

}  // namespace

TEST(StepControl, AFixedStepThatTheNetworkOutgrowsStopsTheRunOrWarns) {
  // Accepted at the start: no contact, the stiffest binary contact at the stated speed.
  Simulation stopped = hertzDrop(OnUnstable::Stop);
  try {
    stopped.advanceTo(0.2);
    ADD_FAILURE() << "the run went through an impact its step cannot hold";
  } catch (const NumericalError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("above the step the contact network allows"), std::string::npos) << what;
    EXPECT_NE(what.find("on_unstable = \"stop\""), std::string::npos) << what;
    // Stopped before the sphere touched: the coming contact was counted.
    EXPECT_GT(stopped.particles().position[0].z(), kR);
  }
  Simulation warned = hertzDrop(OnUnstable::Warn);
  warned.advanceTo(0.2);
  EXPECT_GT(warned.counters().unstableChecks, 0u);
  EXPECT_GT(warned.counters().worstStepRatio, 1.0);
  // The same drop at time_step = "auto" goes through, shorter steps near the floor.
  Simulation automatic = hertzDrop(OnUnstable::Stop);
  StepControl control;
  control.automatic = true;
  automatic.setStepControl(control);
  automatic.advanceTo(0.2);
  EXPECT_GT(automatic.particles().velocity[0].z(), 0.0);  // bounced (at 0.14 s), rising
  EXPECT_LT(automatic.counters().smallestStep, 0.9 * automatic.counters().largestStep);
}

TEST(StepControl, AutomaticStepOnAFallingDampedBedClosesItsBalanceAndStaysInsideTheNetwork) {
  // 48 frictional spheres (Hertz, γn = 200 1/s, rolling resistance) fall, collide and settle
  // for 1.5 s at time_step = "auto" (Verlet and Gear): the energy balance closes to 1e-3 of the
  // work of gravity (the dissipative runs of test_energy.cpp close to that at t_c/50), and at
  // every 0.05 s the step in use lies inside the integrator's interval at the corner of the
  // exact linearised network then (its ω_max and fastest damping rate, the dense spectrum), the
  // least damped contact's ratio from the bound.
  for (Integrator integrator : {Integrator::VelocityVerlet, Integrator::Gear5}) {
    SimulationConfig cfg;
    cfg.material.normalLaw = NormalLaw::Hertz;
    cfg.material.normalDamping = 200.0;
    cfg.material.friction = 0.3;
    cfg.material.rollingFriction = 0.05;
    cfg.integrator = integrator;
    cfg.impactSpeed = 3.0;
    cfg.threads = 1;
    cfg.step.automatic = true;
    Simulation sim = granular::testing::fallingGrid(4, 3, 4, cfg, 0.3);
    const double start = sim.energy().total();
    double gained = 0, lost = 0, work = 0;
    for (int k = 1; k <= 150; ++k) {
      sim.advanceTo(0.01 * k);
      if (k % 5 == 0) {
        const double omega = std::sqrt(largestEigenvalue(networkMatrix(sim, false)));
        const double rate = largestEigenvalue(networkMatrix(sim, true));
        const double zeta = std::max(rate / (2.0 * omega), 0.0);
        const double least = std::min(networkStableStep(sim).smallestZeta, zeta);
        const double allowed = stableOmegaDtOver(integrator, least, zeta) / omega;
        EXPECT_LE(sim.config().timeStep, allowed * (1 + 1e-9)) << sim.time();
      }
      const EnergyBalance e = sim.energy();
      gained = std::max(gained, e.total() - start);
      lost = std::max(lost, start - e.total());
      work = std::max(work, std::abs(e.gravityWork));
    }
    std::printf(
        "%s: steps %llu, dt %.3g .. %.3g s; balance: gained %.2e, lost %.2e of the "
        "work of gravity\n",
        integrator == Integrator::Gear5 ? "gear5" : "verlet",
        static_cast<unsigned long long>(sim.stepCount()), sim.counters().smallestStep,
        sim.counters().largestStep, gained / work, lost / work);
    // The balance drifts by truncation (the ledger's trapezoid over contacts that open and
    // close inside a step: second order, 2 % of the work at t_c/10, 3·10⁻⁴ at t_c/80 in this
    // bed); an unstable step would grow it without bound. At "auto" it drifts no more than a
    // fixed run at the longest step auto took while impacts went on, the accuracy floor (the
    // still bed's longer steps, above the floor, add nothing that shows).
    SimulationConfig fixed = cfg;
    fixed.step.automatic = false;
    const double floor = std::min(sim.contactScale().duration / cfg.step.contactResolution,
                                  maxStableStep(sim.contactScale(), integrator));  // Gear5's t_c/50
    fixed.timeStep = std::min(sim.counters().largestStep, floor);
    fixed.step.onUnstable = OnUnstable::Warn;  // the settled bed's network allows less
    Simulation reference = granular::testing::fallingGrid(4, 3, 4, fixed, 0.3);
    double referenceGained = 0;
    for (int k = 1; k <= 150; ++k) {
      reference.advanceTo(0.01 * k);
      referenceGained = std::max(referenceGained, reference.energy().total() - start);
    }
    std::printf("  fixed at %.3g s: gained %.2e\n", fixed.timeStep, referenceGained / work);
    EXPECT_LT(gained, 1.2 * referenceGained + 1e-4 * work);
    EXPECT_LT(lost, 1e-3 * work);
    EXPECT_GT(sim.counters().particleContacts, 40u);  // settled: a bed, not a gas
  }
}

TEST(StepControl, TheAccuracyFloorFollowsTheApproachSpeedsTheRunHas) {
  // A Hertz contact is shorter at a higher speed (t_c ∝ v^(-1/5)). Declared at 0.1 m/s, a
  // 10 m/s impact would be resolved in 10 · (0.1/10)^(1/5) ≈ 4 steps of the floor the
  // declaration sets. The checks measure the
  // closing speeds of the contacts about to form, and the floor follows the faster: the impact
  // is resolved in its 10 steps and ends as one run at a fine step does.
  auto impact = [](double declared, double resolution) {
    const double r = 0.03, gap = 2e-3, speed = 10.0;
    SimulationConfig cfg;
    cfg.material.normalLaw = NormalLaw::Hertz;
    cfg.gravity = Vec3::Zero();
    cfg.integrator = Integrator::VelocityVerlet;
    cfg.timeStep = 1e-6;  // the first step; the control chooses from the start on
    cfg.step.automatic = true;
    cfg.step.contactResolution = resolution;
    cfg.impactSpeed = declared;
    cfg.threads = 1;
    Particles p;
    p.add(Vec3(-r - 0.5 * gap, 0, 0), r, cfg.material.density, Vec3(0.5 * speed, 0, 0));
    p.add(Vec3(r + 0.5 * gap, 0, 0), r, cfg.material.density, Vec3(-0.5 * speed, 0, 0));
    Simulation sim(std::move(p), {}, cfg);
    return measurePairImpact(sim, speed, 1.0);
  };
  const ImpactMeasurement reference = impact(10.0, 400.0);
  const ImpactMeasurement declaredRight = impact(10.0, 10.0);
  const ImpactMeasurement declaredSlow = impact(0.1, 10.0);
  ASSERT_TRUE(reference.separated && declaredRight.separated && declaredSlow.separated);
  // Resolved as if the speed had been declared: the contact in 10 steps, within 2.5 % of the
  // fine run (the restitution 2 %: Verlet's dashpot acts at the half-step velocity, first
  // order; docs/physics.md §2.6).
  EXPECT_NEAR(declaredSlow.restitution, declaredRight.restitution,
              1e-3 * declaredRight.restitution);
  EXPECT_NEAR(declaredSlow.overlapDuration, declaredRight.overlapDuration,
              1e-3 * declaredRight.overlapDuration);
  EXPECT_NEAR(declaredSlow.restitution, reference.restitution, 2e-2 * reference.restitution);
  EXPECT_NEAR(declaredSlow.overlapDuration, reference.overlapDuration,
              2.5e-2 * reference.overlapDuration);
}

TEST(StepControl, AHertzPairClosingFastFromAfarIsMetBelowTheDeclaredFloor) {
  // Two Hertz spheres close at 10 m/s from 0.3 m apart in a scene that declares 0.1 m/s: with
  // no contact the floor the declaration sets holds the step, and its checks come as seldom as
  // a fixed step's. The scans at the rebuilds between see the pair enter the list and bring the
  // floor down before it touches: t_c ∝ u^(-1/5), so at 10 m/s the floor is 0.4 × the declared
  // one, and every step in contact is under half of it.
  const double r = 0.03, speed = 10.0;
  SimulationConfig cfg;
  cfg.material.normalLaw = NormalLaw::Hertz;
  cfg.gravity = Vec3::Zero();
  cfg.integrator = Integrator::VelocityVerlet;
  cfg.timeStep = 1e-6;  // the first step; the control chooses from the start on
  cfg.step.automatic = true;
  cfg.impactSpeed = 0.1;
  cfg.threads = 1;
  Particles p;
  p.add(Vec3(-r - 0.15, 0, 0), r, cfg.material.density, Vec3(0.5 * speed, 0, 0));
  p.add(Vec3(r + 0.15, 0, 0), r, cfg.material.density, Vec3(-0.5 * speed, 0, 0));
  Simulation sim(std::move(p), {}, cfg);
  const double declared = sim.contactScale().duration / cfg.step.contactResolution;
  ASSERT_EQ(sim.config().timeStep, declared);
  int inContact = 0;
  for (int k = 0; k < 400 && inContact >= 0; ++k) {
    sim.step();
    const Particles& q = sim.particles();
    if ((q.position[1] - q.position[0]).norm() >= 2.0 * r) {
      if (inContact > 0) inContact = -1;  // separated
      continue;
    }
    ++inContact;
    EXPECT_LT(sim.config().timeStep, 0.5 * declared) << sim.time();
  }
  EXPECT_EQ(inContact, -1);
}

TEST(StepControl, TheAccuracyFloorIsForImpactsNotForTheNetworksSlowMotion) {
  // A frictional Hooke bed (the paper's material) settles at time_step = "auto": while spheres
  // fall onto it, the step is at most the floor for impacts (t_c/10; Gear5's binary limit
  // t_c/50); once the bed is still, the kinetic energy of its contacts' relative motion is far
  // under 1 % of what their springs store and the step is the network's (safety × its stable
  // step), above the floor. A sphere then thrown at it at 2 m/s brings the floor back before
  // it touches: every step it spends in contact is at most the floor.
  for (Integrator integrator : {Integrator::VelocityVerlet, Integrator::Gear5}) {
    SCOPED_TRACE(integrator == Integrator::Gear5 ? "gear5" : "verlet");
    SimulationConfig cfg = paperMaterialAtAuto();
    cfg.integrator = integrator;
    Simulation sim = granular::testing::fallingGrid(4, 4, 4, cfg, 0.3);
    const double floor = std::min(sim.contactScale().duration / cfg.step.contactResolution,
                                  maxStableStep(sim.contactScale(), integrator));
    while (sim.time() < 1.5) {
      sim.step();
      if (sim.kineticEnergy() > 1e-3) {
        EXPECT_LE(sim.config().timeStep, floor * (1 + 1e-12)) << sim.time();
      }
    }
    sim.advanceTo(3.0);
    ASSERT_LT(sim.kineticEnergy(), 1e-4);  // still
    const StepCheck& still = sim.stepCheck();
    EXPECT_GT(still.accuracyStep, 10.0 * floor);
    EXPECT_GT(sim.config().timeStep, 1.3 * floor);
    EXPECT_NEAR(sim.config().timeStep, sim.config().step.safety * still.networkStep,
                1e-12 * still.networkStep);

    double top = 0;
    for (std::size_t i = 0; i < sim.particles().size(); ++i) {
      top = std::max(top, sim.particles().position[i].z() + sim.particles().radius[i]);
    }
    const double r = 0.032;
    sim.exchangeParticles([&](const Particles&) {
      ParticleExchange x;
      x.insert.add(Vec3(0.2, 0.2, top + r + 0.02), r, cfg.material.density, Vec3(0, 0, -2.0));
      return x;
    });
    const std::size_t thrown = sim.particles().size() - 1;
    int stepsInContact = 0;
    for (int k = 0; k < 400; ++k) {
      sim.step();
      const Particles& p = sim.particles();
      bool touching = p.position[thrown].z() < r;  // the floor
      for (std::size_t i = 0; i < thrown; ++i) {
        touching |= (p.position[i] - p.position[thrown]).norm() < p.radius[i] + r;
      }
      if (!touching) continue;
      ++stepsInContact;
      EXPECT_LE(sim.config().timeStep, floor * (1 + 1e-12)) << sim.time();
    }
    EXPECT_GT(stepsInContact, 10);
  }
}

class StillStep : public granular::testing::TempFolderTest {
 protected:
  StillStep() : TempFolderTest("granular_still_step") {}
};

TEST_F(StillStep, ItsChecksComeFurtherApartUntilTheStepMovesAndAResumedRunKeepsTheirGap) {
  // A frictional Hooke bed (the paper's material) settled at time_step = "auto", then carried
  // along x at 0.2 m/s as one body with its box: the neighbour list is rebuilt every few steps
  // while the contact network, and so the step (the network's, the floor stretched), holds
  // still. A check comes at a rebuild at least 25 steps after the last, then twice as far apart
  // at each check that leaves the step within 1 %, up to recheckSteps (100). Three times the
  // normal damping then moves the step by a quarter with no motion (its check is the setter's,
  // the floor stays stretched): the next check comes at a rebuild 25 steps on again, and the
  // gaps double from there. A checkpoint written while the checks are 100 steps apart resumes
  // with that gap, bit for bit.
  const SimulationConfig cfg = paperMaterialAtAuto();
  Simulation settled = granular::testing::fallingGrid(4, 4, 4, cfg, 0.3);
  settled.advanceTo(3.0);
  ASSERT_LT(settled.kineticEnergy(), 1e-4);  // still
  Particles p = settled.particles();
  const Vec3 carried(0.2, 0.0, 0.0);
  for (Vec3& v : p.velocity) v = carried;
  std::vector<Wall> walls = settled.walls();
  Simulation sim(std::move(p), std::move(walls), cfg);
  for (std::size_t w = 0; w < sim.walls().size(); ++w) sim.setWallVelocity(w, carried);
  const double floor = sim.contactScale().duration / cfg.step.contactResolution;
  sim.advanceTo(2.0);  // the springs the copy dropped stretched again: the bed still

  // The steps between consecutive checks over `steps` steps (the first counted from the start).
  auto gapsOf = [](Simulation& sim, int steps) {
    std::vector<int> gaps;
    std::uint64_t checks = sim.counters().stepChecks;
    int since = 0;
    for (int k = 0; k < steps; ++k) {
      sim.step();
      ++since;
      if (sim.counters().stepChecks == checks) continue;
      checks = sim.counters().stepChecks;
      gaps.push_back(since);
      since = 0;
    }
    return gaps;
  };
  const std::uint64_t rebuilds = sim.counters().rebuilds;
  std::vector<int> gaps = gapsOf(sim, 700);
  EXPECT_GT(sim.counters().rebuilds - rebuilds, 700u / 12u);  // a rebuild every few steps
  EXPECT_GT(sim.config().timeStep, 1.3 * floor);              // stretched
  ASSERT_GE(gaps.size(), 5u);
  for (std::size_t k = 1; k < gaps.size(); ++k) EXPECT_EQ(gaps[k], 100) << k;

  const std::filesystem::path file = dir_ / "still.ckpt";
  writeCheckpoint(sim, file, 0);
  Simulation resumed = readCheckpoint(file);
  gaps = gapsOf(sim, 250);
  EXPECT_EQ(gapsOf(resumed, 250), gaps);
  EXPECT_EQ(resumed.stateHash(), sim.stateHash());

  Material damped = sim.config().material;
  damped.normalDamping *= 3.0;
  const double before = sim.config().timeStep;
  sim.setMaterial(damped);
  EXPECT_LT(sim.config().timeStep, 0.98 * before);
  gaps = gapsOf(sim, 400);
  EXPECT_GT(sim.config().timeStep, 1.3 * floor);
  ASSERT_GE(gaps.size(), 3u);
  EXPECT_LT(gaps[0], 50);  // 25 and the steps to the next rebuild
  EXPECT_GE(gaps[1], 50);
  EXPECT_LT(gaps[1], 100);
  for (std::size_t k = 2; k < gaps.size(); ++k) EXPECT_EQ(gaps[k], 100) << k;
}

TEST(StepControl, AnAutomaticStepItsFloorSetsIsCheckedAsSeldomAsAFixedOne) {
  // The paper's material falls and settles at time_step = "auto": while the spheres strike,
  // the floor t_c/10 sets the step, the network allowing 1.25 × more, and the neighbour list is
  // rebuilt every few steps, yet the checks come at least 25 steps apart, as a fixed step's:
  // the floor holds the step still (Hooke's does not depend on the approach), and a contact
  // that forms between two checks stiffens the network by less than the margin. The checks
  // change nothing else: the bed falls as a fixed run at the floor does, to the bit.
  const SimulationConfig cfg = paperMaterialAtAuto();
  Simulation sim = granular::testing::fallingGrid(4, 4, 4, cfg, 0.3);
  const double floor = sim.contactScale().duration / cfg.step.contactResolution;
  std::uint64_t checks = sim.counters().stepChecks, rebuilds = sim.counters().rebuilds;
  int since = 0, atFloor = 0, steps = 0;
  while (sim.time() < 0.5) {
    sim.step();
    ++steps;
    ++since;
    ASSERT_EQ(sim.config().timeStep, floor) << sim.time();
    if (sim.counters().stepChecks == checks) continue;
    checks = sim.counters().stepChecks;
    ASSERT_EQ(sim.stepCheck().chosenStep, sim.stepCheck().accuracyStep);  // the floor's
    if (atFloor++ > 0) {
      EXPECT_GE(since, 25) << sim.time();
    }
    since = 0;
  }
  EXPECT_GT(sim.counters().rebuilds - rebuilds, std::uint64_t(steps) / 10);  // rebuilt often
  EXPECT_GE(atFloor, 3);
  SimulationConfig fixed = cfg;
  fixed.step.automatic = false;
  fixed.timeStep = floor;
  Simulation reference = granular::testing::fallingGrid(4, 4, 4, fixed, 0.3);
  while (reference.stepCount() < sim.stepCount()) reference.step();
  for (std::size_t i = 0; i < sim.particles().size(); ++i) {
    ASSERT_EQ(reference.particles().position[i], sim.particles().position[i]) << i;
    ASSERT_EQ(reference.particles().velocity[i], sim.particles().velocity[i]) << i;
  }
}
