/// A run started from a state granular saved (particles[i].type = "state", issue 33): a settled
/// bed's final_state.csv taken as it is, its overlaps with each other and with the walls
/// allowed and reported, its masses kept, every contact's history at zero. Settled once, the bed
/// is the start of other experiments: restarted unchanged it stays at rest; restarted with
/// friction switched on it runs from the same particles.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "csv_output.hpp"
#include "granular/error.hpp"
#include "granular/scene.hpp"
#include "granular/stage.hpp"
#include "granular_process.hpp"
#include "run_header.hpp"
#include "temp_folder.hpp"

using namespace granular;

namespace {

constexpr double kG = 9.81;  // [m/s²]

/// 60 frictionless spheres dropped into a 0.3 m × 0.3 m box (settle), or the same box with the
/// particles of `state`.
std::string scene(const std::string& particles, double friction, const std::string& stage) {
  return "[material]\nfriction = " + std::to_string(friction) +
         "\nnormal_damping = 200.0\n"
         "[simulation]\nintegrator = \"verlet\"\ntime_step = 2e-4\n"
         "[box]\nmin = [0, 0, 0]\nmax = [0.3, 0.3, 1]\n"
         "[[particles]]\n" +
         particles + "[[stages]]\n" + stage;
}

const std::string kGrid =
    "type = \"grid\"\norigin = [0, 0, 0]\ncell_size = 0.1\ncells = [3, 3, 7]\ncount = 60\n"
    "radius_min = 0.03\nradius_max = 0.035\nspeed_max = 0.2\n";

/// Σ m |g| (z − floor): the bed's potential energy above the floor [J].
double potentialEnergy(const Particles& p) {
  double sum = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) sum += p.mass[i] * kG * p.position[i].z();
  return sum;
}

class SavedState : public granular::testing::TempFolderTest {
 protected:
  SavedState() : TempFolderTest("granular_saved_state") {}

  /// The settled bed's final_state.csv, as `granular run` writes it.
  std::filesystem::path settledState() {
    const Scene settle = loadScene(
        write("settle.toml", scene(kGrid, 0.0,
                                   "name = \"settle\"\nmax_time = 4\nkinetic_energy_below = 1e-9\n"
                                   "sustain_time = 0.05\n")));
    Simulation sim = buildSimulation(settle);
    runStage(sim, settle.stages[0], settle.output, {});
    const std::filesystem::path state = dir_ / "final_state.csv";
    app::writeParticleState(state, sim.particles());
    settledPotential_ = potentialEnergy(sim.particles());
    return state;
  }

  /// The largest kinetic energy of a 0.5 s run of `restart`, sampled every output interval.
  static double largestKinetic(const Scene& restart) {
    Simulation sim = buildSimulation(restart);
    double largest = sim.kineticEnergy();
    StageObserver watch;
    watch.onSample = [&](const Simulation& s) { largest = std::max(largest, s.kineticEnergy()); };
    runStage(sim, restart.stages[0], restart.output, watch);
    return largest;
  }

  double settledPotential_ = 0.0;
};

TEST_F(SavedState, ASettledBedRestartedUnchangedStaysAtRest) {
  const std::filesystem::path state = settledState();
  const std::string hold = "name = \"hold\"\nmax_time = 0.5\n";
  const Scene restart = loadScene(
      write("restart.toml", scene("type = \"state\"\nfile = \"final_state.csv\"\n", 0.0, hold)));
  const Simulation start = buildSimulation(restart);
  // The state as it was: the settled bed presses into the floor and into itself.
  std::ostringstream header;
  app::printSavedStateStart(header, restart, start);
  const std::string text = header.str();
  EXPECT_NE(text.find("start       saved state " + state.string()), std::string::npos) << text;
  EXPECT_NE(text.find("wall contacts overlapping, the largest by "), std::string::npos) << text;
  EXPECT_NE(text.find("history (tangential springs) starts at zero"), std::string::npos) << text;
  EXPECT_EQ(text.find(" 0 particle and"), std::string::npos) << "no overlap in a settled bed?";
  EXPECT_LE(largestKinetic(restart), 1e-6 * settledPotential_);
}

TEST_F(SavedState, ARestartWithFrictionOnRunsFromTheSameParticles) {
  const std::filesystem::path state = settledState();
  const std::string hold = "name = \"hold\"\nmax_time = 0.5\n";
  const Scene restart = loadScene(
      write("restart.toml", scene("type = \"state\"\nfile = \"final_state.csv\"\n", 0.3, hold)));
  const Simulation start = buildSimulation(restart);
  // The particles, to the bit, with the masses of the file.
  const std::string rows = granular::testing::readFile(state);
  const std::filesystem::path again = dir_ / "again.csv";
  app::writeParticleState(again, start.particles());
  EXPECT_EQ(granular::testing::readFile(again), rows);
  EXPECT_LE(largestKinetic(restart), 1e-6 * settledPotential_);
}

TEST_F(SavedState, MassesThatDisagreeWithTheDensityAreRefusedNamingTheRow) {
  const std::filesystem::path state = settledState();
  const std::string hold = "name = \"hold\"\nmax_time = 0.1\n";
  std::string text = scene("type = \"state\"\nfile = \"final_state.csv\"\n", 0.0, hold);
  text.replace(text.find("normal_damping"), 0, "density = 400\n");
  try {
    buildSimulation(loadScene(write("restart.toml", text)));
    ADD_FAILURE() << "masses of density 500 accepted at density 400";
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(state.string() + ":2)"), std::string::npos) << message;
    EXPECT_NE(message.find("give a density of 500"), std::string::npos) << message;
    EXPECT_NE(message.find("set material.density"), std::string::npos) << message;
  }
}

TEST_F(SavedState, AStateFileAsAParticleFileIsRefusedSayingHowToStartFromIt) {
  settledState();
  const std::string hold = "name = \"hold\"\nmax_time = 0.1\n";
  try {
    loadScene(
        write("restart.toml", scene("type = \"csv\"\nfile = \"final_state.csv\"\n", 0.0, hold)));
    ADD_FAILURE() << "a state file read as particles";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("type = \"state\""), std::string::npos) << e.what();
  }
}

}  // namespace
