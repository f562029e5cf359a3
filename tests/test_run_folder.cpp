/// A run's output folder holds one run (issue 33): a fresh run into a folder that holds an
/// earlier run is refused, or with --force starts clean; the ParaView collections list this
/// run's frames only, timed in seconds since the run began even at an automatic step; a resumed
/// run continues only the time series rows it wrote itself; a complete run killed before its
/// final files writes them when resumed.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "granular_process.hpp"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using granular::testing::GranularProcess;
using granular::testing::readFile;

/// 27 spheres falling onto the floor, two stages (the second on its own clock), snapshots.
std::string scene(const std::string& step, const std::string& snapshots) {
  return "[material]\nfriction = 0.3\nnormal_damping = 200.0\n"
         "[simulation]\nintegrator = \"verlet\"\ntime_step = " +
         step +
         "\n"
         "[box]\nmin = [0, 0, 0]\nmax = [0.3, 0.3, 1]\n"
         "[[particles]]\ntype = \"grid\"\norigin = [0, 0, 0]\ncell_size = 0.1\n"
         "cells = [3, 3, 3]\nradius_min = 0.03\nradius_max = 0.035\nspeed_max = 0.2\n"
         "[[stages]]\nname = \"settle\"\nmax_time = 0.3\n"
         "[[stages]]\nname = \"hold\"\nmax_time = 0.1\nreset_clock = true\n"
         "[output]\ninterval = 0.002\nsnapshots = [" +
         snapshots + "]\n";
}

class RunFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("granular_run_folder_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path writeScene(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  /// `granular run SCENE --out OUT -q EXTRA...` to its end: exit status and stderr.
  std::pair<int, std::string> run(const fs::path& scenePath, const std::vector<std::string>& extra,
                                  const std::string& tag) const {
    std::vector<std::string> args = {"run", scenePath.string(), "--out", out().string(), "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    GranularProcess p(args, dir_ / (tag + ".stderr"));
    EXPECT_TRUE(p.started());
    const int status = p.wait();
    return {status, p.stderrText()};
  }
  /// The same, stopped by SIGTERM once the time series has `bytes` bytes (it checkpoints).
  void runUntil(const fs::path& scenePath, std::uintmax_t bytes) const {
    GranularProcess p(
        {"run", scenePath.string(), "--out", out().string(), "-q", "--checkpoint-every", "0"},
        dir_ / "stopped.stderr");
    ASSERT_TRUE(p.started());
    const fs::path series = out() / "timeseries.csv";
    while (p.running() && (!fs::exists(series) || fs::file_size(series) < bytes)) {
      std::this_thread::sleep_for(1ms);
    }
    ASSERT_TRUE(p.running()) << "ended before the signal; make the scene longer";
    p.signal(SIGTERM);
    ASSERT_EQ(p.wait(), 128 + SIGTERM) << p.stderrText();
  }
  fs::path out() const { return dir_ / "out"; }

  /// The (timestep, file) pairs of a .pvd collection, in order (scanned by hand: GCC 12's
  /// <regex> trips -Wmaybe-uninitialized in the sanitizer build).
  static std::vector<std::pair<double, std::string>> frames(const fs::path& pvd) {
    const std::string text = readFile(pvd);
    std::vector<std::pair<double, std::string>> found;
    auto quoted = [&](std::size_t from, const std::string& name) {
      const std::size_t start = text.find(name + "=\"", from);
      if (start == std::string::npos) return std::string();
      const std::size_t begin = start + name.size() + 2;
      return text.substr(begin, text.find('"', begin) - begin);
    };
    for (std::size_t at = text.find("<DataSet"); at != std::string::npos;
         at = text.find("<DataSet", at + 1)) {
      found.emplace_back(std::stod(quoted(at, "timestep")), quoted(at, "file"));
    }
    return found;
  }

  fs::path dir_;
};

TEST_F(RunFolder, AFreshRunIntoAnEarlierRunsFolderIsRefusedNamingTheWaysOn) {
  const fs::path first = writeScene("first.toml", scene("2e-4", "0.05"));
  ASSERT_EQ(run(first, {}, "first").first, 0);
  const std::string series = readFile(out() / "timeseries.csv");
  const auto [status, message] = run(first, {}, "again");
  EXPECT_EQ(status, 2) << message;
  EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 1) << message;
  for (const std::string& part : std::vector<std::string>{
           out().string() + " holds an earlier run (", "--resume", "--force", "another --out"}) {
    EXPECT_NE(message.find(part), std::string::npos) << part << " in " << message;
  }
  EXPECT_EQ(readFile(out() / "timeseries.csv"), series) << "the refusal touched the earlier run";
  // --resume and --force together make no sense.
  EXPECT_NE(run(first, {"--resume", "--force"}, "both").first, 0);
}

TEST_F(RunFolder, ForceStartsCleanAndTheCollectionsListOnlyTheNewRunsFrames) {
  ASSERT_EQ(run(writeScene("first.toml", scene("2e-4", "0.05, 0.15")), {}, "first").first, 0);
  std::ofstream(out() / "notes.txt") << "mine\n";
  const auto earlier = frames(out() / "particles.pvd");
  ASSERT_EQ(earlier.size(), 3u);  // settle at 0.05 and 0.15 s, hold (0.1 s long) at 0.05 s
  // Another step: the snapshots fall at other steps, so their files have other names.
  const auto [status, message] =
      run(writeScene("second.toml", scene("1.5e-4", "0.05")), {"--force"}, "second");
  ASSERT_EQ(status, 0) << message;
  const auto now = frames(out() / "particles.pvd");
  ASSERT_EQ(now.size(), 2u);
  for (const auto& [time, file] : now) {
    EXPECT_TRUE(fs::exists(out() / file)) << file;
    for (const auto& [oldTime, oldFile] : earlier) EXPECT_NE(file, oldFile);
  }
  for (const auto& [oldTime, oldFile] : earlier) {
    EXPECT_FALSE(fs::exists(out() / oldFile)) << oldFile << " of the earlier run is still there";
  }
  // Every snapshot CSV left is one of the new run's: "<stage>_<step>" of one of its frames.
  for (const auto& entry : fs::directory_iterator(out())) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with("snapshot_") && !name.starts_with("contacts_")) continue;
    bool ours = false;
    for (const auto& [time, file] : now) {
      const std::string frame = fs::path(file).filename().string();  // settle_334_particles.vtp
      const std::string stem = frame.substr(0, frame.rfind('_'));    // settle_334
      ours = ours || name.ends_with("_" + stem + ".csv");
    }
    EXPECT_TRUE(ours) << name << " is not a snapshot of the new run";
  }
  EXPECT_EQ(readFile(out() / "notes.txt"), "mine\n") << "a file not the run's was removed";
}

TEST_F(RunFolder, AResumedRunListsOnlyTheFramesOfItsOwnRun) {
  const fs::path path = writeScene("scene.toml", scene("2e-4", "0.02, 0.05"));
  GranularProcess reference({"run", path.string(), "--out", (dir_ / "reference").string(), "-q",
                             "--checkpoint-every", "0"},
                            dir_ / "reference.stderr");
  ASSERT_EQ(reference.wait(), 0) << reference.stderrText();
  runUntil(path, 12000);  // past the first stage's snapshots: 0.05 s is row 26
  // A frame of another run, left in the folder by hand, as `settle_589` was in the report.
  const auto referenceFrames = frames(dir_ / "reference" / "particles.pvd");
  ASSERT_FALSE(referenceFrames.empty());
  fs::copy_file(dir_ / "reference" / referenceFrames.front().second,
                out() / "paraview" / "settle_589_particles.vtp");
  const auto [status, message] = run(path, {"--resume"}, "resumed");
  ASSERT_EQ(status, 0) << message;
  for (const char* kind : {"particles.pvd", "contacts.pvd", "walls.pvd"}) {
    EXPECT_EQ(readFile(out() / kind), readFile(dir_ / "reference" / kind)) << kind;
  }
  for (const auto& [time, file] : frames(out() / "particles.pvd")) {
    EXPECT_EQ(file.find("settle_589"), std::string::npos);
  }
}

TEST_F(RunFolder, AnAutomaticStepsFramesAreTimedInSecondsSinceTheRunBegan) {
  const fs::path path = writeScene("auto.toml", scene("\"auto\"", "0.02, 0.05"));
  const auto [status, message] = run(path, {}, "auto");
  ASSERT_EQ(status, 0) << message;
  // settle: 0.02 and 0.05 s; hold, on its own clock after settle's 0.3 s: 0.32 and 0.35 s.
  const auto found = frames(out() / "particles.pvd");
  ASSERT_EQ(found.size(), 4u);
  const double expected[] = {0.02, 0.05, 0.32, 0.35};
  for (std::size_t k = 0; k < found.size(); ++k) {
    EXPECT_NEAR(found[k].first, expected[k], 1e-9) << found[k].second;
  }
}

TEST_F(RunFolder, AResumeRefusesATimeSeriesEditedBeforeItsCheckpoint) {
  const fs::path path = writeScene("scene.toml", scene("2e-4", "0.05"));
  runUntil(path, 8000);
  const fs::path series = out() / "timeseries.csv";
  std::string text = readFile(series);
  const std::size_t row = text.find("\nsettle,0.002,");
  ASSERT_NE(row, std::string::npos) << text.substr(0, 400);
  text[text.find(',', row + 14) + 1] = '9';  // the step column of the second row, edited by hand
  std::ofstream(series, std::ios::binary | std::ios::trunc) << text;
  const auto [status, message] = run(path, {"--resume"}, "resumed");
  EXPECT_EQ(status, 2) << message;
  EXPECT_NE(message.find(series.string() + ": its first "), std::string::npos) << message;
  EXPECT_NE(message.find("were changed since"), std::string::npos) << message;
  EXPECT_EQ(readFile(series), text) << "the refused resume cut the file";
}

TEST_F(RunFolder, ACompleteRunKilledBeforeItsFinalFilesWritesThemWhenResumed) {
  const fs::path path = writeScene("scene.toml", scene("2e-4", "0.05"));
  ASSERT_EQ(run(path, {}, "whole").first, 0);
  const std::string finalState = readFile(out() / "final_state.csv");
  // What a kill between the last checkpoint and the final files leaves.
  fs::remove(out() / "final_state.csv");
  fs::remove(out() / "summary.txt");
  const auto [status, message] = run(path, {"--resume"}, "resumed");
  ASSERT_EQ(status, 0) << message;
  EXPECT_EQ(readFile(out() / "final_state.csv"), finalState);
  EXPECT_TRUE(fs::exists(out() / "summary.txt"));
}

}  // namespace
