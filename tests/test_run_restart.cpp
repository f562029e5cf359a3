/// `granular run` killed and restarted: the real binary is killed with SIGKILL (no chance to
/// clean up) while it writes periodic checkpoints, restarted with --resume, killed again, and
/// resumed to the end; its outputs must equal, byte for byte, those of a run never interrupted.
/// And a NaN injected into the state stops the run at that step, naming the particle, with the
/// last good state in the checkpoint, from which the run resumes to the same end.
#include <gtest/gtest.h>

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "granular/checkpoint.hpp"
#include "granular_process.hpp"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

const fs::path kScene = fs::path(GRANULAR_SOURCE_DIR) / "tests/scenes/restart.toml";

std::string slurp(const fs::path& file) {
  return granular::testing::readFile(file);
}

/// `granular run` of `scene` (the restart scene unless given) into `out`, stderr beside it.
class Child : public granular::testing::GranularProcess {
 public:
  Child(const fs::path& out, const std::vector<std::string>& extra,
        std::vector<std::string> env = {}, const fs::path& scene = kScene)
      : GranularProcess(arguments(out, extra, scene), out.string() + ".stderr", std::move(env)) {}

 private:
  static std::vector<std::string> arguments(const fs::path& out,
                                            const std::vector<std::string>& extra,
                                            const fs::path& scene) {
    std::vector<std::string> args = {"run", scene.string(), "--out", out.string(), "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  }
};

/// Waits until `file` has been replaced `times` times since the call (its contents change), or
/// the run ends; true if it did.
bool waitForNewCheckpoints(Child& run, const fs::path& file, int times) {
  std::string seen = fs::exists(file) ? slurp(file) : std::string();
  for (int changes = 0; changes < times;) {
    if (!run.running()) return false;
    std::this_thread::sleep_for(5ms);
    if (!fs::exists(file)) continue;
    std::string now = slurp(file);
    if (now != seen) {
      seen = std::move(now);
      ++changes;
    }
  }
  return true;
}

/// Every output file a finished run leaves, compared by content; summary.txt is compared by its
/// state hash line (it also holds wall-clock times).
void expectSameOutputs(const fs::path& reference, const fs::path& resumed) {
  std::vector<std::string> names;
  for (const auto& entry : fs::recursive_directory_iterator(reference)) {
    const std::string name = fs::relative(entry.path(), reference).string();
    if (name.ends_with(".csv") || name.ends_with(".pvd") || name.ends_with(".vtp")) {
      names.push_back(name);
    }
  }
  // Time series, final state, snapshots of both stages; their ParaView files (3 per snapshot)
  // and the three collections, which a resumed run rebuilds from the files already written.
  ASSERT_GE(names.size(), 4u + 12u + 3u);
  for (const std::string& name : names) {
    ASSERT_TRUE(fs::exists(resumed / name)) << name;
    EXPECT_TRUE(slurp(reference / name) == slurp(resumed / name)) << name << " differs";
  }
  auto hashLine = [](const fs::path& dir) {
    std::istringstream in(slurp(dir / "summary.txt"));
    for (std::string line; std::getline(in, line);) {
      if (line.starts_with("state hash: ")) return line;
    }
    return std::string("(no state hash)");
  };
  EXPECT_EQ(hashLine(reference), hashLine(resumed));
}

fs::path freshDir(const char* name) {
  const fs::path dir = fs::temp_directory_path() / (std::string("granular_restart_") + name);
  fs::remove_all(dir);
  return dir;
}

}  // namespace

TEST(RunRestart, KilledTwiceAndResumedEndsBitForBitLikeAnUninterruptedRun) {
  const fs::path reference = freshDir("reference");
  Child whole(reference, {"--checkpoint-every", "0"});
  ASSERT_TRUE(whole.started());
  ASSERT_EQ(whole.wait(), 0) << whole.stderrText();

  const fs::path out = freshDir("killed");
  const fs::path checkpoint = out / "checkpoint.bin";
  // Checkpoint as often as the run offers (every 100 steps); kill after the first, then again
  // after two more, so that the second life itself starts from a checkpoint.
  const std::vector<std::string> often = {"--checkpoint-every", "1e-9", "--resume"};
  int kills = 0;
  for (int wanted : {1, 2}) {
    Child life(out, often);
    ASSERT_TRUE(life.started());
    if (!waitForNewCheckpoints(life, checkpoint, wanted)) {
      ADD_FAILURE() << "the run ended before it could be killed; make the scene longer\n"
                    << life.stderrText();
      return;
    }
    life.kill();
    ASSERT_EQ(life.wait(), -SIGKILL);
    ++kills;
    EXPECT_FALSE(fs::exists(out / "summary.txt")) << "killed after it had finished";
    // What a kill leaves behind is always a whole checkpoint, never a torn one.
    EXPECT_NO_THROW(granular::readCheckpoint(checkpoint)) << "after kill " << kills;
  }
  Child last(out, often);
  ASSERT_TRUE(last.started());
  ASSERT_EQ(last.wait(), 0) << last.stderrText();
  EXPECT_EQ(kills, 2);
  expectSameOutputs(reference, out);
}

TEST(RunRestart, AnAutomaticStepKilledAndResumedEndsBitForBit) {
  // time_step = "auto": the chosen step, its target and the steps since its last check travel
  // in the checkpoint (format 6), with the spectrum's calibration that Verlet's step comes
  // from once the network governs (format 8; this test fails when a resume drops it), and a
  // stage resumes at its stage time, so the resumed run chooses the same steps and lands on
  // the same sample times.
  const fs::path dir = freshDir("auto_scene");
  fs::create_directories(dir);
  const std::string text = slurp(kScene);
  const std::string::size_type at = text.find("time_step = 1.2e-4");
  ASSERT_NE(at, std::string::npos);
  const fs::path scene = dir / "restart-auto.toml";
  // Verlet with no accuracy floor to speak of: its step follows the network (gear5's stays at
  // its t_c/50 cap in this bed, Verlet's at t_c/10 by default).
  std::string automatic = text.substr(0, at) + "time_step = \"auto\"\ncontact_resolution = 2\n" +
                          text.substr(text.find('\n', at) + 1);
  const std::string::size_type gear = automatic.find("integrator = \"gear5\"");
  ASSERT_NE(gear, std::string::npos);
  automatic.replace(gear, std::string("integrator = \"gear5\"").size(), "integrator = \"verlet\"");
  std::ofstream(scene) << automatic;
  const fs::path reference = freshDir("auto_reference");
  Child whole(reference, {"--checkpoint-every", "0"}, {}, scene);
  ASSERT_TRUE(whole.started());
  ASSERT_EQ(whole.wait(), 0) << whole.stderrText();

  const fs::path out = freshDir("auto_killed");
  const fs::path checkpoint = out / "checkpoint.bin";
  const std::vector<std::string> often = {"--checkpoint-every", "1e-9", "--resume"};
  Child life(out, often, {}, scene);
  ASSERT_TRUE(life.started());
  if (!waitForNewCheckpoints(life, checkpoint, 3)) {
    ADD_FAILURE() << "the run ended before it could be killed\n" << life.stderrText();
    return;
  }
  life.kill();
  ASSERT_EQ(life.wait(), -SIGKILL);
  const granular::Simulation saved = granular::readCheckpoint(checkpoint);
  EXPECT_TRUE(saved.config().step.automatic);
  Child last(out, often, {}, scene);
  ASSERT_TRUE(last.started());
  ASSERT_EQ(last.wait(), 0) << last.stderrText();
  expectSameOutputs(reference, out);
}

TEST(RunRestart, InjectedNaNStopsAtItsStepAndTheLastGoodStateResumes) {
  const fs::path reference = freshDir("nan_reference");
  Child whole(reference, {"--checkpoint-every", "0"});
  ASSERT_TRUE(whole.started());
  ASSERT_EQ(whole.wait(), 0) << whole.stderrText();

  const fs::path out = freshDir("nan");
  const std::uint64_t badStep = 3456;  // inside the settling stage
  Child broken(out, {"--checkpoint-every", "1e-9"},
               {"GRANULAR_INJECT_NAN=" + std::to_string(badStep) + ":17"});
  ASSERT_TRUE(broken.started());
  EXPECT_EQ(broken.wait(), 3);
  const std::string message = broken.stderrText();
  // Detected within one step: the step after the injection, naming the particle.
  EXPECT_NE(message.find("step " + std::to_string(badStep + 1) + " "), std::string::npos)
      << message;
  // The particle is named with the first of its quantities that broke (the velocity's NaN
  // reaches the position in the same step).
  EXPECT_NE(message.find("particle 17: "), std::string::npos) << message;
  EXPECT_NE(message.find("is not finite"), std::string::npos) << message;
  EXPECT_NE(message.find("the last good state is"), std::string::npos) << message;
  EXPECT_TRUE(fs::exists(out / "failed_state.csv"));
  // The checkpoint holds a state from before the fault, whole and finite.
  const granular::Simulation good = granular::readCheckpoint(out / "checkpoint.bin");
  EXPECT_LE(good.stepCount(), badStep);
  EXPECT_GT(good.stepCount(), badStep - 200);  // checkpoints every 100 steps

  Child resumed(out, {"--checkpoint-every", "0", "--resume"});
  ASSERT_TRUE(resumed.started());
  ASSERT_EQ(resumed.wait(), 0) << resumed.stderrText();
  expectSameOutputs(reference, out);
}

// Issue 21, item 5: the checkpoint's fingerprint is the scene's values and the bytes of its
// particle files, not the bytes of the scene file.

TEST(RunRestart, ACommentEditedInTheSceneAfterAKillResumesBitForBit) {
  const fs::path reference = freshDir("comment_reference");
  Child whole(reference, {"--checkpoint-every", "0"});
  ASSERT_TRUE(whole.started());
  ASSERT_EQ(whole.wait(), 0) << whole.stderrText();

  const fs::path out = freshDir("comment");
  fs::create_directories(out);
  const fs::path scene = out.string() + ".toml";
  fs::copy_file(kScene, scene, fs::copy_options::overwrite_existing);
  Child life(out, {"--checkpoint-every", "1e-9"}, {}, scene);
  ASSERT_TRUE(life.started());
  if (!waitForNewCheckpoints(life, out / "checkpoint.bin", 1)) {
    ADD_FAILURE() << "the run ended before it could be killed\n" << life.stderrText();
    return;
  }
  life.kill();
  ASSERT_EQ(life.wait(), -SIGKILL);
  // A comment and blank lines added, and a number spelt otherwise: the same scene.
  const std::string text = slurp(scene);
  std::ofstream(scene, std::ios::trunc)
      << "# edited while the run was down\n\n"
      << text.substr(0, text.find("time_step = 1.2e-4")) << "time_step = 0.00012  # s\n"
      << text.substr(text.find('\n', text.find("time_step = 1.2e-4")) + 1);
  Child resumed(out, {"--checkpoint-every", "0", "--resume"}, {}, scene);
  ASSERT_TRUE(resumed.started());
  ASSERT_EQ(resumed.wait(), 0) << resumed.stderrText();
  expectSameOutputs(reference, out);
  fs::remove(scene);
}

TEST(RunRestart, AParticleFileEditedAfterACheckpointIsRefusedNamingIt) {
  // The case: 64 particles in a CSV, the run stopped, the file cut to 54 rows and a
  // particle moved.
  const fs::path dir = freshDir("csv_edit");
  fs::create_directories(dir);
  auto csv = [](int rows, double shift) {
    std::ostringstream text;
    text << "x,y,z,r\n";
    for (int k = 0; k < rows; ++k) {
      text << 0.1 + 0.1 * (k % 4) + (k == 0 ? shift : 0.0) << ',' << 0.1 + 0.1 * ((k / 4) % 4)
           << ',' << 0.1 + 0.1 * (k / 16) << ",0.03\n";
    }
    return text.str();
  };
  std::ofstream(dir / "particles.csv") << csv(64, 0.0);
  std::ofstream(dir / "scene.toml") << "[material]\nfriction = 0.3\nnormal_damping = 200.0\n"
                                       "[simulation]\ntime_step = 1.2e-4\n"
                                       "[box]\nmin = [0, 0, 0]\nmax = [0.6, 0.6, 2]\n"
                                       "[[particles]]\ntype = \"csv\"\nfile = \"particles.csv\"\n"
                                       "[[stages]]\nmax_time = 0.03\n";
  const fs::path out = dir / "out";
  Child first(out, {"--checkpoint-every", "1e-9"}, {}, dir / "scene.toml");
  ASSERT_TRUE(first.started());
  ASSERT_EQ(first.wait(), 0) << first.stderrText();
  ASSERT_TRUE(fs::exists(out / "checkpoint.bin"));

  std::ofstream(dir / "particles.csv", std::ios::trunc) << csv(54, 0.01);
  Child resumed(out, {"--resume"}, {}, dir / "scene.toml");
  ASSERT_TRUE(resumed.started());
  EXPECT_EQ(resumed.wait(), 2);
  const std::string message = resumed.stderrText();
  EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 1) << message;
  EXPECT_NE(message.find((out / "checkpoint.bin").string() +
                         ": the scene changed since this checkpoint was written: the particle "
                         "file " +
                         (dir / "particles.csv").string() + " (particles[0].file) changed"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("remove " + (out / "checkpoint.bin").string() +
                         " (or run without --resume) to start again"),
            std::string::npos)
      << message;
  fs::remove_all(dir);
}

// A batch scheduler's SIGTERM (and Ctrl-C's SIGINT) before its SIGKILL: the run finishes its
// step, writes a checkpoint even though periodic ones are off, says how to resume, exits with
// 128 + the signal; resumed, it ends bit for bit like a run never interrupted.
TEST(RunRestart, AParticleFileRewrittenWithTheSameValuesResumes) {
  // A spreadsheet's save of the same particles: CRLF line ends, the columns in another order,
  // 0.100 for 0.1, a comment. The values are the run's, so --resume continues it, and ends where
  // an uninterrupted run ends.
  const fs::path dir = freshDir("csv_same_values");
  fs::create_directories(dir);
  std::ostringstream plain, saved;
  plain << "x,y,z,r\n";
  saved << "# saved again\r\nr,z,x,y\r\n";
  for (int k = 0; k < 64; ++k) {
    const int x = 1 + k % 4, y = 1 + (k / 4) % 4, z = 1 + k / 16;
    plain << "0." << x << ",0." << y << ",0." << z << ",0.03\n";
    saved << "0.030,0." << z << "00,0." << x << "0,0." << y << "\r\n";
  }
  const std::string scene =
      "[material]\nfriction = 0.3\nnormal_damping = 200.0\n"
      "[simulation]\ntime_step = 1.2e-4\n"
      "[box]\nmin = [0, 0, 0]\nmax = [0.6, 0.6, 2]\n"
      "[[particles]]\ntype = \"csv\"\nfile = \"particles.csv\"\n"
      "[[stages]]\nname = \"first\"\nmax_time = 0.6\n"
      "[[stages]]\nname = \"second\"\nmax_time = 0.1\n"
      "[output]\ninterval = 0.002\n";
  std::ofstream(dir / "scene.toml") << scene;
  std::ofstream(dir / "particles.csv", std::ios::binary) << plain.str();
  const fs::path reference = dir / "reference";
  Child whole(reference, {"--checkpoint-every", "0"}, {}, dir / "scene.toml");
  ASSERT_TRUE(whole.started());
  ASSERT_EQ(whole.wait(), 0) << whole.stderrText();

  // Stopped mid-run by SIGTERM (which writes a checkpoint), the file saved again.
  const fs::path out = dir / "out";
  Child first(out, {"--checkpoint-every", "0"}, {}, dir / "scene.toml");
  ASSERT_TRUE(first.started());
  const fs::path series = out / "timeseries.csv";
  while (first.running() && (!fs::exists(series) || fs::file_size(series) < 4000)) {
    std::this_thread::sleep_for(2ms);
  }
  ASSERT_TRUE(first.running()) << "the run ended before the signal; make the scene longer";
  first.signal(SIGTERM);
  ASSERT_EQ(first.wait(), 128 + SIGTERM) << first.stderrText();
  std::ofstream(dir / "particles.csv", std::ios::binary | std::ios::trunc) << saved.str();
  Child resumed(out, {"--resume", "--checkpoint-every", "0"}, {}, dir / "scene.toml");
  ASSERT_TRUE(resumed.started());
  ASSERT_EQ(resumed.wait(), 0) << resumed.stderrText();
  EXPECT_EQ(slurp(out / "final_state.csv"), slurp(reference / "final_state.csv"));
  EXPECT_EQ(slurp(out / "timeseries.csv"), slurp(reference / "timeseries.csv"));
}

TEST(RunRestart, SigtermAndSigintWriteACheckpointSayHowToResumeAndExit128PlusTheSignal) {
  const fs::path reference = freshDir("signal_reference");
  Child whole(reference, {"--checkpoint-every", "0"});
  ASSERT_TRUE(whole.started());
  ASSERT_EQ(whole.wait(), 0) << whole.stderrText();

  const fs::path out = freshDir("signalled");
  const fs::path series = out / "timeseries.csv";
  std::uintmax_t seriesBytes = 0;
  for (int signal : {SIGTERM, SIGINT}) {
    Child life(out, {"--checkpoint-every", "0", "--resume"});
    ASSERT_TRUE(life.started());
    // Mid-stage: a few more rows of the time series than the last life left.
    while (life.running() && (!fs::exists(series) || fs::file_size(series) < seriesBytes + 4000)) {
      std::this_thread::sleep_for(2ms);
    }
    ASSERT_TRUE(life.running()) << "the run ended before the signal; make the scene longer";
    life.signal(signal);
    ASSERT_EQ(life.wait(), 128 + signal) << life.stderrText();
    const std::string message = life.stderrText();
    EXPECT_NE(message.find(signal == SIGTERM ? "SIGTERM" : "SIGINT"), std::string::npos) << message;
    EXPECT_NE(message.find("--resume"), std::string::npos) << message;
    EXPECT_NE(message.find((out / "checkpoint.bin").string()), std::string::npos) << message;
    EXPECT_NO_THROW(granular::readCheckpoint(out / "checkpoint.bin"));
    EXPECT_FALSE(fs::exists(out / "summary.txt"));
    seriesBytes = fs::file_size(series);
  }
  Child last(out, {"--checkpoint-every", "0", "--resume"});
  ASSERT_TRUE(last.started());
  ASSERT_EQ(last.wait(), 0) << last.stderrText();
  expectSameOutputs(reference, out);
}
