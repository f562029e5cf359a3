/// Messages of the real `granular` for mistakes on its command line and in what it is given to
/// read: each names what is wrong in the user's words (the command, the option and its value,
/// the file) and exits with the documented status, never a misleading one.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "granular_process.hpp"

namespace {

namespace fs = std::filesystem;

const fs::path kDemo = fs::path(GRANULAR_SOURCE_DIR) / "assets/scenes/demo.toml";

struct Outcome {
  int status = 0;
  std::string stderrText;
};

Outcome run(const std::vector<std::string>& args) {
  // One file per test process: ctest runs these tests side by side.
  const fs::path err =
      fs::temp_directory_path() / ("granular_user_messages_" + std::to_string(::getpid()) + ".err");
  granular::testing::GranularProcess p(args, err, {"OMP_NUM_THREADS=1"});
  EXPECT_TRUE(p.started());
  Outcome o;
  o.status = p.wait();
  o.stderrText = p.stderrText();
  return o;
}

void expectRefusal(const std::vector<std::string>& args, int status,
                   const std::vector<std::string>& phrases,
                   const std::vector<std::string>& absent = {}) {
  const Outcome o = run(args);
  std::string command;
  for (const std::string& a : args) command += a + " ";
  EXPECT_EQ(o.status, status) << command << "\n" << o.stderrText;
  for (const std::string& phrase : phrases) {
    EXPECT_NE(o.stderrText.find(phrase), std::string::npos)
        << command << ": no '" << phrase << "' in\n"
        << o.stderrText;
  }
  for (const std::string& phrase : absent) {
    EXPECT_EQ(o.stderrText.find(phrase), std::string::npos)
        << command << ": '" << phrase << "' in\n"
        << o.stderrText;
  }
}

}  // namespace

TEST(UserMessages, AMistypedCommandIsNamedWithTheNearestOne) {
  expectRefusal({"rnu", kDemo.string()}, 2, {"unknown command 'rnu'", "did you mean 'run'?"},
                {"A subcommand is required"});
  expectRefusal({"figure", "x"}, 2, {"did you mean 'figures'?"});
  expectRefusal({"simulate"}, 2, {"unknown command 'simulate'", "run, paper"}, {"did you mean"});
}

TEST(UserMessages, NumbersOutOfRangeAreRefusedWithoutA309DigitBound) {
  for (const std::string value : {"-1", "nan", "inf", "1e400", "ten"}) {
    expectRefusal({"run", kDemo.string(), "--checkpoint-every", value}, 2,
                  {"--checkpoint-every", "'" + value + "' is not a finite number >= 0 seconds"},
                  {"179769313486231570"});
  }
  expectRefusal({"calibrate-box", kDemo.string(), "--sides", "nan"}, 2,
                {"--sides", "'nan' is not a finite number > 0 m"}, {"below one grid cell"});
  expectRefusal({"calibrate-box", kDemo.string(), "--sides", "0.5", "--target-height", "-1"}, 2,
                {"--target-height", "'-1' is not a finite number > 0 m"}, {"-nan"});
}

TEST(UserMessages, AnEmptyOutputFolderIsRefusedRatherThanReplacedByTheDefault) {
  expectRefusal({"run", kDemo.string(), "--out", ""}, 2, {"--out", "an empty path"});
  expectRefusal({"paper", "--out", ""}, 2, {"--out", "an empty path"});
}

TEST(UserMessages, AFolderOrDeviceGivenAsTheSceneIsNamedAsSuch) {
  expectRefusal({"run", kDemo.parent_path().string()}, 2, {"it is a folder (give the .toml file)"});
  expectRefusal({"run", "/dev/null"}, 2, {"/dev/null", "not a regular file"});
  expectRefusal({"run", "/no/such/scene.toml"}, 2, {"/no/such/scene.toml", "no such file"});
}
