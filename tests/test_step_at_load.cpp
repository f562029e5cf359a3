/// A fixed step judged when the scene is loaded, where the stiffest binary contact does not see
/// what limits it: rolling resistance at its documented limit (rolling_friction = 1). The loader
/// refuses the demo's Gear5 step with the step the network of a dense bed allows, and that step
/// then runs the bed through its settling and compaction without the run's own network check
/// ever finding it too large (which stopped the demo at step 374 when the loader let it pass).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "granular/error.hpp"
#include "granular/scene.hpp"
#include "granular/stage.hpp"
#include "temp_folder.hpp"

using namespace granular;

namespace {

class StepAtLoad : public granular::testing::TempFolderTest {
 protected:
  StepAtLoad() : TempFolderTest("granular_step_at_load") {}

  /// The demo (assets/scenes/demo.toml) with rolling resistance, shortened: 0.6 s of settling
  /// (the demo stopped at 0.064 s) and 0.05 s of compaction.
  std::string demoWithRolling(const std::string& integrator, const std::string& step,
                              double rollingDamping) const {
    std::ifstream in(std::string(GRANULAR_SOURCE_DIR) + "/assets/scenes/demo.toml");
    std::stringstream text;
    text << in.rdbuf();
    std::string scene = text.str();
    auto replace = [&](const std::string& from, const std::string& to) {
      const std::size_t at = scene.find(from);
      ASSERT_NE(at, std::string::npos) << from;
      scene.replace(at, from.size(), to);
    };
    replace("normal_law = \"hooke\"", "normal_law = \"hooke\"\nrolling_friction = 1.0\n" +
                                          ("rolling_damping = " + std::to_string(rollingDamping)));
    replace("integrator = \"gear5\"", "integrator = \"" + integrator + "\"");
    replace("time_step = 1.7e-4", "time_step = " + step);
    replace("max_time = 1.5", "max_time = 0.6");
    replace("max_time = 0.2", "max_time = 0.05");
    return scene;
  }

  /// The refusal's "use at most X s".
  static std::string allowedStep(const std::string& message) {
    const std::string lead = "use at most ";
    const std::size_t at = message.find(lead);
    if (at == std::string::npos) return "";
    const std::size_t begin = at + lead.size();
    return message.substr(begin, message.find(' ', begin) - begin);
  }

  /// Runs every stage; the run's network check stops it (NumericalError) at a step above the
  /// network's.
  static void runAll(const Scene& scene) {
    Simulation sim = buildSimulation(scene);
    for (const StageSpec& stage : scene.stages) runStage(sim, stage, scene.output, {});
    EXPECT_EQ(sim.counters().unstableChecks, 0u);
    EXPECT_GT(sim.counters().stepChecks, 10u);
  }
};

TEST_F(StepAtLoad, RollingFrictionAtItsLimitIsRefusedWithAStepThatRunsThrough) {
  for (const std::string integrator : {"gear5", "verlet"}) {
    SCOPED_TRACE(integrator);
    const std::string demoStep = integrator == "gear5" ? "1.7e-4" : "8e-4";  // t_c/51, t_c/11
    std::string message;
    try {
      loadScene(write("refused.toml", demoWithRolling(integrator, demoStep, 0.3)));
    } catch (const SceneError& e) {
      message = e.what();
    }
    ASSERT_NE(message.find("refused.toml:"), std::string::npos) << message;
    EXPECT_NE(message.find("simulation.time_step"), std::string::npos) << message;
    EXPECT_NE(message.find("rolling"), std::string::npos) << message;
    const std::string allowed = allowedStep(message);
    ASSERT_FALSE(allowed.empty()) << message;
    EXPECT_LT(std::stod(allowed), std::stod(demoStep));
    runAll(loadScene(write("allowed.toml", demoWithRolling(integrator, allowed, 0.3))));
  }
}

TEST_F(StepAtLoad, TheMostDampedRollingIsJudgedToo) {
  // η_r = 1, the largest: the rolling dashpots' rates at their highest.
  std::string message;
  try {
    loadScene(write("refused.toml", demoWithRolling("verlet", "2e-4", 1.0)));
  } catch (const SceneError& e) {
    message = e.what();
  }
  const std::string allowed = allowedStep(message);
  ASSERT_FALSE(allowed.empty()) << message;
  runAll(loadScene(write("allowed.toml", demoWithRolling("verlet", allowed, 1.0))));
}

}  // namespace
