/// The checks a run makes of itself at its samples (run_checks.hpp): the energy balance and
/// particles outside the box, in the core and as `granular run` reports them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "calibrate_command.hpp"
#include "granular/contact_theory.hpp"
#include "granular/engine_studies.hpp"
#include "granular/run_checks.hpp"
#include "granular/wall_mesh.hpp"
#include "granular_process.hpp"
#include "mesh_fixtures.hpp"
#include "physics_fixtures.hpp"
#include "run_progress.hpp"

using namespace granular;
using granular::testing::fallingGrid;

namespace {

namespace fs = std::filesystem;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// A fresh folder under the build tree for one test.
fs::path workFolder(const std::string& name) {
  const fs::path dir = fs::path(GRANULAR_BINARY_DIR) / "run-checks-test" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace

TEST(EnergyRunChecks, FreeFallKeepsItsBalanceAndLeavesTheOpenFloorWhenTheClosedFormSays) {
  // One sphere falls from rest in a box with no walls. Gravity alone: the ledger's total
  // (K − work of gravity) stays at its start to round-off, so even a drift limit of 1e-12 is
  // never passed. The sphere is wholly below the open floor (z = 0) once z < −R, at
  // t* = sqrt(2 (z0 + R)/g): reported at the first sample at or after t*, never before.
  const double z0 = 0.2, r = 0.03, g = 9.81, interval = 0.01;
  SimulationConfig cfg;
  cfg.timeStep = 1e-4;
  cfg.gravity = Vec3(0, 0, -g);
  Particles p;
  p.add(Vec3(0.5, 0.5, z0), r, cfg.material.density);
  Simulation sim(std::move(p), {}, cfg);
  BoxSpec box;
  box.walls.fill(false);
  RunCheckSpec spec;
  spec.energyDriftLimit = 1e-12;
  RunChecks checks(spec, box, sim.energy().total());
  const double tStar = std::sqrt(2.0 * (z0 + r) / g);
  double reportedAt = -1;
  for (int k = 0; k <= 40; ++k) {
    if (k > 0) sim.run(100);  // one sample every 100 steps: 0.01 s
    for (const std::string& found : checks.atSample(sim, "fall")) {
      ASSERT_LT(reportedAt, 0.0) << "reported twice: " << found;
      EXPECT_TRUE(contains(found, "particle 0 is outside the box")) << found;
      EXPECT_TRUE(contains(found, "the open face bottom")) << found;
      EXPECT_TRUE(contains(found, "(stage fall)")) << found;
      reportedAt = sim.time();
    }
  }
  EXPECT_GE(reportedAt, tStar);
  EXPECT_LT(reportedAt, tStar + interval);
}

TEST(EnergyRunChecks, ASphereFallingThroughAGapInAMeshFloorIsReportedAndOneBesideItIsNot) {
  // A meshed floor at z = 0 (4 × 4 squares of 0.25 m) lacks the two triangles of one square:
  // a sphere of radius 0.03 m above the gap falls through it and out of the box's open floor;
  // a sphere above the whole floor lands and stays. Only the first is reported, as a way out
  // past the scene's walls.
  const double r = 0.03;
  SimulationConfig cfg;
  cfg.gravity = Vec3(0, 0, -9.81);
  cfg.timeStep = stiffestContact(cfg.material, r, 1.0).duration / 50.0;
  TriangleMesh floor = granular::testing::flatGrid(4, 1.0);
  const std::size_t gap = 2 * (4 * 1 + 1);  // the square (1, 1): [0.25, 0.5]²
  floor.triangle.erase(floor.triangle.begin() + long(gap), floor.triangle.begin() + long(gap) + 2);
  Wall w;
  w.name = "floor";
  w.shape = WallShape::Mesh;
  w.mesh = poseMesh(std::make_shared<const TriangleMesh>(std::move(floor)), Vec3::Zero(),
                    Vec3::UnitZ(), Vec3::UnitX());
  Particles p;
  p.add(Vec3(0.375, 0.375, 0.1), r, cfg.material.density);  // above the gap
  p.add(Vec3(0.625, 0.625, 0.1), r, cfg.material.density);  // above the floor
  Simulation sim(std::move(p), {w}, cfg);
  BoxSpec box;
  box.walls.fill(false);
  RunChecks checks(RunCheckSpec{}, box, sim.energy().total());
  std::vector<std::string> found;
  const auto sample = std::max<long>(1, std::lround(0.01 / cfg.timeStep));
  for (int k = 0; k < 40 && found.empty(); ++k) {
    sim.run(sample);
    found = checks.atSample(sim, "fill");
  }
  ASSERT_EQ(found.size(), 1u) << "the sphere above the gap was never reported";
  EXPECT_TRUE(contains(found[0], "particle 0 is outside the box")) << found[0];
  EXPECT_TRUE(contains(found[0], "a gap between them or in a mesh")) << found[0];
  EXPECT_GT(sim.particles().position[1].z(), 0.5 * r) << "the other sphere stays on the floor";
}

TEST(EnergyRunChecks, BedAboveTheDampingLimitIsReportedOnceAndStoppedUnderStop) {
  // 150 frictional spheres settle under Gear5 at the paper's step. At the largest γt accepted
  // the balance closes (tests/test_tangential_damping.cpp) and no sample reports anything; at 8×
  // it the bed's dashpots are unstable and energy grows without work: reported once, at a
  // sample, naming the time and step; under Stop the run ends there with the same message.
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.timeStep = 1.7e-4;
  cfg.threads = 1;
  const double limit = maxTangentialDamping(cfg.timeStep, cfg.integrator);
  BoxSpec box;
  box.max = Vec3(0.5, 0.5, 1.0);
  for (double factor : {1.0, 8.0}) {
    for (CheckAction action : {CheckAction::Warn, CheckAction::Stop}) {
      Simulation sim = fallingGrid(5, 5, 6, cfg, 0.3);
      studies::disableStepLimit(sim, true);
      Material m = cfg.material;
      m.tangentialDamping = factor * limit;
      sim.setMaterial(m);
      RunCheckSpec spec;
      spec.onFailedCheck = action;
      RunChecks checks(spec, box, sim.energy().total());
      std::vector<std::string> found;
      std::string stopped;
      try {
        while (sim.time() < 1.0) {
          sim.run(59);  // about 0.01 s
          for (std::string& f : checks.atSample(sim, "settle")) found.push_back(std::move(f));
        }
      } catch (const RunCheckError& e) {
        stopped = e.what();
      }
      if (factor == 1.0) {
        EXPECT_TRUE(found.empty() && stopped.empty()) << (found.empty() ? stopped : found[0]);
        continue;
      }
      const std::string& message = action == CheckAction::Warn ? found.at(0) : stopped;
      EXPECT_EQ(found.size(), action == CheckAction::Warn ? 1u : 0u);
      EXPECT_TRUE(contains(message, "energy balance drifted by +")) << message;
      EXPECT_TRUE(contains(message, "% of the work done, limit 5 %) at t = ")) << message;
      EXPECT_TRUE(contains(message, "the time step or a damping coefficient")) << message;
      if (action == CheckAction::Stop) {
        EXPECT_LT(sim.time(), 1.0);
      }
    }
  }
}

TEST(EnergyRunChecks, WorkDoneCountsEveryFlowOnce) {
  EnergyBalance e;
  e.gravityWork = 4.0;
  e.wallWork = -1.0;
  e.contact = {{"elastic_normal_J", EnergyKind::Stored, 16.0},  // held, not a flow
               {"dissipated_normal_J", EnergyKind::Dissipated, 2.0},
               {"dissipated_tangential_J", EnergyKind::Dissipated, 0.25},
               {"dissipated_friction_J", EnergyKind::Slip, -0.125},  // a remainder, either sign
               {"tangential_stiffness_work_J", EnergyKind::Supplied, 0.5}};
  EXPECT_EQ(RunChecks::workDone(e, 3.0), 3.0 + 4.0 + 1.0 + 0.5 + 2.0 + 0.25 + 0.125);
}

TEST(EnergyRunChecks, TheReferenceTravelsWithTheCheckpointsProgress) {
  app::RunProgress p;
  p.energyReference = 0.1 + 0.2;  // not a short decimal: it must come back to the bit
  const app::RunProgress back = app::decodeRunProgress(app::encodeRunProgress(p), "f");
  ASSERT_TRUE(back.energyReference.has_value());
  EXPECT_EQ(*back.energyReference, 0.1 + 0.2);
  p.energyReference.reset();  // written before it was kept: the run measures from its resume
  EXPECT_FALSE(app::decodeRunProgress(app::encodeRunProgress(p), "f").energyReference);
}

namespace {

/// 8 spheres in a 0.5 m box, at up to `speed` m/s, falling for 0.3 s, then pressed for 0.05 s by
/// a top wall placed on them and moving at `topVelocity`; `output` is added to [output].
fs::path writeScene(const fs::path& dir, double speed, const std::string& topVelocity,
                    const std::string& output) {
  const fs::path file = dir / "scene.toml";
  // Spheres at 1000 m/s and a lid at 10⁶ m/s also cross the contact network's step:
  // on_unstable = "warn" lets the run go on to the checks this test is about.
  std::ofstream(file) << "[material]\nfriction = 0.3\n"
                         "[simulation]\ntime_step = 1.7e-4\non_unstable = \"warn\"\n"
                         "[box]\nmin = [0, 0, 0]\nmax = [0.5, 0.5, 1]\n"
                         "[[particles]]\ntype = \"grid\"\norigin = [0, 0, 0]\ncell_size = 0.1\n"
                         "cells = [2, 2, 2]\nradius_min = 0.03\nradius_max = 0.035\n"
                         "speed_max = "
                      << speed
                      << "\n"
                         "[[stages]]\nname = \"fall\"\nmax_time = 0.3\n"
                         "[[stages]]\nname = \"press\"\nmax_time = 0.05\n"
                         "place_top_wall_on_surface = true\n"
                         "[stages.wall_velocity]\ntop = "
                      << topVelocity << "\n[output]\ninterval = 0.01\n"
                      << output;
  return file;
}

struct Outcome {
  int status;
  std::string stderrText, summary;
};

Outcome runScene(const fs::path& dir, const fs::path& scene) {
  granular::testing::GranularProcess run(
      {"run", scene.string(), "--out", (dir / "out").string(), "-q", "--force"},
      dir / "stderr.txt");
  EXPECT_TRUE(run.started());
  const int status = run.wait();
  return {status, run.stderrText(), granular::testing::readFile(dir / "out" / "summary.txt")};
}

}  // namespace

TEST(EnergyRunChecks, RunCommandWarnsOnStderrAndInTheSummaryOrStopsWithExitThree) {
  // A sane scene: nothing to report. Spheres at up to 1000 m/s cross a 6 cm sphere in 0.2
  // steps and tunnel through each other and the walls: energy appears from nowhere and
  // spheres leave the box. A lid driven down at 10⁶ m/s passes through every sphere in one step.
  const fs::path dir = workFolder("command");
  Outcome sane = runScene(dir, writeScene(dir, 0.3, "[0, 0, -0.01]", ""));
  EXPECT_EQ(sane.status, 0) << sane.stderrText;
  EXPECT_EQ(sane.stderrText, "");
  EXPECT_FALSE(contains(sane.summary, "warning")) << sane.summary;
  // The step control's reviews and what they cost, on the time step's line.
  EXPECT_TRUE(contains(sane.summary, " checks against the contact network")) << sane.summary;
  EXPECT_TRUE(contains(sane.summary, " s of the wall-clock\n")) << sane.summary;

  Outcome fast = runScene(dir, writeScene(dir, 1000.0, "[0, 0, -0.01]", ""));
  EXPECT_EQ(fast.status, 0) << fast.stderrText;
  for (const char* part : {"warning: energy balance drifted by +", "(stage fall)",
                           "warning: particle ", " is outside the box at t = "}) {
    EXPECT_TRUE(contains(fast.stderrText, part)) << part << " in\n" << fast.stderrText;
    EXPECT_TRUE(contains(fast.summary, part)) << part << " in\n" << fast.summary;
  }

  Outcome stopped =
      runScene(dir, writeScene(dir, 1000.0, "[0, 0, -0.01]", "on_failed_check = \"stop\"\n"));
  EXPECT_EQ(stopped.status, 3) << stopped.stderrText;
  EXPECT_TRUE(contains(stopped.stderrText, "error: energy balance drifted by +"))
      << stopped.stderrText;

  Outcome lid = runScene(dir, writeScene(dir, 0.3, "[0, 0, -1e6]", "on_failed_check = \"stop\"\n"));
  EXPECT_EQ(lid.status, 3) << lid.stderrText;
  EXPECT_TRUE(contains(lid.stderrText, "(stage press)")) << lid.stderrText;
  EXPECT_TRUE(contains(lid.stderrText, "is outside the box")) << lid.stderrText;
}

// `granular calibrate-box` checks each settling as `granular run` does: a drift limit no
// integrator meets (10⁻¹²) is a warning on stderr naming the box and a line of the report
// under "Run checks"; under on_failed_check = "stop" the command ends with exit 3, naming the
// box, and writes no report.
TEST(EnergyRunChecks, CalibrateBoxWarnsOnStderrAndInItsReportOrStopsWithExitThree) {
  const fs::path dir = workFolder("calibrate");
  std::string scene = granular::testing::readFile(fs::path(GRANULAR_SOURCE_DIR) /
                                                  "tests/scenes/reduced-compaction.toml");
  const std::string output = "[output]\ninterval = 0.01\n";
  ASSERT_TRUE(contains(scene, output));
  scene.replace(scene.find(output), output.size(), output + "energy_drift_limit = 1e-12\n");
  for (const char* action : {"warn", "stop"}) {
    SCOPED_TRACE(action);
    const fs::path file = dir / (std::string(action) + ".toml");
    std::ofstream(file) << scene << "on_failed_check = \"" << action << "\"\n";
    app::CalibrateOptions options;
    options.scene = file;
    options.sides = {0.3};
    options.targetHeight = 1.0;
    options.report = dir / (std::string(action) + ".md");
    options.quiet = true;
    ::testing::internal::CaptureStdout();
    ::testing::internal::CaptureStderr();
    const int status = app::calibrateCommand(options);
    ::testing::internal::GetCapturedStdout();
    const std::string message = ::testing::internal::GetCapturedStderr();
    if (std::string(action) == "stop") {
      EXPECT_EQ(status, 3) << message;
      EXPECT_TRUE(contains(message, "error: box side 0.3 m: energy balance drifted by "))
          << message;
      EXPECT_FALSE(fs::exists(options.report));
      continue;
    }
    ASSERT_EQ(status, 0) << message;
    EXPECT_TRUE(contains(message, "warning: box side 0.3 m: energy balance drifted by "))
        << message;
    const std::string report = granular::testing::readFile(options.report);
    EXPECT_TRUE(contains(report, "Run checks (energy balance, particles in the box): **failed**"))
        << report;
    EXPECT_TRUE(contains(report, "\n- box side 0.3 m: energy balance drifted by ")) << report;
  }
}

TEST(EnergyRunChecks, ASphereThroughTheFloorAtAHundredMetresASecondBlamesTheContactNotTheStep) {
  // The paper's material: a head-on impact on a wall overlaps a sphere of 3 cm by its radius
  // at about 12 m/s (Hooke's peak v/ω, damped a little). At 100 m/s the sphere passes through
  // the floor at 2 µs and at 20 µs alike (it moves 0.2 mm and 2 mm a step, under a tenth of its
  // radius): the contact, not the step, is at fault, and the message says so.
  const double r = 0.03;
  Material material;
  const double mass = material.density * 4.0 / 3.0 * M_PI * r * r * r;
  const double held = speedForPeakOverlap(material, r, mass, r);
  EXPECT_NEAR(peakImpactOverlap(material, r, mass, held), r, 1e-12 * r);
  EXPECT_GT(held, 5.0);
  EXPECT_LT(held, 20.0);
  for (const double dt : {2e-6, 2e-5}) {
    SCOPED_TRACE(dt);
    SimulationConfig cfg;
    cfg.timeStep = dt;
    cfg.gravity = Vec3::Zero();
    Particles p;
    p.add(Vec3(0.5, 0.5, 0.05), r, material.density, Vec3(0, 0, -100));
    Wall floor;
    floor.name = "bottom";
    floor.point = Vec3(0.5, 0.5, 0.0);
    Simulation sim(std::move(p), {floor}, cfg);
    BoxSpec box;
    RunChecks checks(RunCheckSpec{}, box, sim.energy().total());
    std::string found;
    for (int k = 0; k < 200 && found.empty(); ++k) {
      sim.advanceTo(sim.time() + 1e-4);
      for (const std::string& warning : checks.atSample(sim, "impact")) {
        if (contains(warning, "outside the box")) found = warning;
      }
    }
    ASSERT_FALSE(found.empty()) << "the sphere did not pass through";
    EXPECT_TRUE(contains(found, "wholly beyond the wall bottom")) << found;
    EXPECT_TRUE(contains(found, "whatever the time step")) << found;
    EXPECT_TRUE(contains(found, "too soft for the speed or the load")) << found;
    EXPECT_TRUE(contains(found,
                         "holds a head-on impact of a sphere of this radius on a wall up "
                         "to " +
                             std::to_string(held).substr(0, 4)))
        << found;
    EXPECT_FALSE(contains(found, "too fast for the time step")) << found;
  }
}

TEST(EnergyRunChecks, AFixedStepRunWarnsWhenItsContactsApproachFasterThanDeclared) {
  // Hertz at a fixed step of 1 ms, judged at impact_speed = 0.1 m/s (its limit there, t_c/10,
  // is 2 ms), two spheres 4 mm apart closing at 10 m/s, where the limit is 0.82 ms: the check
  // measures the speed, and the run says so once. Declared right, no word of it.
  const fs::path dir = workFolder("approach");
  std::ofstream(dir / "pair.csv") << "x,y,z,r,vx,vy,vz\n0.468,0.5,0.5,0.03,5,0,0\n"
                                     "0.532,0.5,0.5,0.03,-5,0,0\n";
  const std::string scene =
      "[material]\nnormal_law = \"hertz\"\n[simulation]\nintegrator = \"verlet\"\n"
      "time_step = 1e-3\nimpact_speed = 0.1\ngravity = [0, 0, 0]\n"
      "[box]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
      "[[particles]]\ntype = \"csv\"\nfile = \"pair.csv\"\n"
      "[[stages]]\nmax_time = 0.03\n[output]\ninterval = 0.001\n";
  std::ofstream(dir / "scene.toml") << scene;
  Outcome declared = runScene(dir, dir / "scene.toml");
  EXPECT_EQ(declared.status, 0) << declared.stderrText;
  for (const char* part :
       {"warning: contacts approach at up to 10 m/s, above simulation.impact_speed = 0.1 m/s",
        "s is above its limit there", "or use time_step = \"auto\""}) {
    EXPECT_TRUE(contains(declared.stderrText, part)) << part << " in\n" << declared.stderrText;
    EXPECT_TRUE(contains(declared.summary, part)) << part << " in\n" << declared.summary;
  }
  std::ofstream(dir / "scene.toml", std::ios::trunc)
      << std::string(scene).replace(scene.find("impact_speed = 0.1"), 18, "impact_speed = 11");
  Outcome right = runScene(dir, dir / "scene.toml");
  EXPECT_EQ(right.status, 0) << right.stderrText;
  EXPECT_FALSE(contains(right.stderrText, "contacts approach")) << right.stderrText;
}
