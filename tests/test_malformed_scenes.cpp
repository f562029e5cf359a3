/// Runs the real `granular run` on every scene in tests/scenes/malformed/ and checks that each is
/// refused the way a user needs: exit status 2 (not a crash, not an I/O error, not a run), exactly
/// one line on stderr, naming the scene file and containing every `# expect:` substring written
/// at the top of the file. The corpus is listed when the test binary starts, so a new file is
/// tested without touching this source.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "granular_process.hpp"

namespace {

namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(GRANULAR_SOURCE_DIR) / "tests" / "scenes" / "malformed";

std::vector<std::string> corpusFiles() {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(kCorpus, error)) {
    if (entry.is_regular_file() && entry.path().extension() == ".toml") {
      names.push_back(entry.path().filename().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

/// The `# what:` and `# expect:` lines at the top of a corpus file.
struct Expectation {
  std::string what;
  std::vector<std::string> substrings;
};

Expectation readExpectation(const fs::path& file) {
  Expectation e;
  std::ifstream in(file, std::ios::binary);
  std::string line;
  const std::string what = "# what:", expect = "# expect:";
  while (std::getline(in, line) && line.rfind("#", 0) == 0) {
    auto value = [&](const std::string& tag) {
      const std::string rest = line.substr(tag.size());
      return rest.substr(std::min(rest.find_first_not_of(' '), rest.size()));
    };
    if (line.rfind(what, 0) == 0) e.what = value(what);
    if (line.rfind(expect, 0) == 0) e.substrings.push_back(value(expect));
  }
  return e;
}

/// Outcome of one run of the binary.
struct RunResult {
  bool exited = false;  ///< false: killed by a signal (a crash) or by our timeout
  int status = -1;      ///< exit status when exited, else the signal number
  bool timedOut = false;
  std::string stderrText;
};

/// `granular run SCENE --out OUT -q` with stderr captured, killed after 60 s: a scene that is
/// wrongly accepted runs the simulation, and the bound keeps a run that would not end finite.
RunResult runGranular(const fs::path& scene, const fs::path& work) {
  granular::testing::GranularProcess run(
      {"run", scene.string(), "--out", (work / "out").string(), "-q"}, work / "stderr.txt");
  RunResult result;
  if (!run.started()) {
    result.stderrText = "posix_spawn failed: " + std::to_string(run.spawnError());
    return result;
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (run.running()) {
    if (std::chrono::steady_clock::now() > deadline) {
      run.kill();
      result.timedOut = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const int status = run.wait();
  result.exited = !result.timedOut && status >= 0;
  result.status = status >= 0 ? status : -status;
  result.stderrText = run.stderrText();
  return result;
}

class MalformedScene : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    work_ = fs::temp_directory_path() /
            ("granular_malformed_" + std::to_string(::getpid()) + "_" + sanitized(GetParam()));
    fs::remove_all(work_);
    fs::create_directories(work_);
  }
  void TearDown() override { fs::remove_all(work_); }

 public:
  /// gtest names allow only letters, digits and '_'.
  static std::string sanitized(const std::string& name) {
    std::string out = name.substr(0, name.rfind('.'));
    for (char& c : out) {
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    }
    return out;
  }

 protected:
  fs::path work_;
};

TEST(MalformedSceneCorpus, HasEnoughFiles) {
  EXPECT_GE(corpusFiles().size(), 50u) << "corpus folder: " << kCorpus;
}

TEST_P(MalformedScene, IsRefusedWithOneClearError) {
  const fs::path scene = kCorpus / GetParam();
  const Expectation expectation = readExpectation(scene);
  ASSERT_FALSE(expectation.what.empty()) << scene << ": no '# what:' line";
  ASSERT_FALSE(expectation.substrings.empty()) << scene << ": no '# expect:' line";

  const RunResult run = runGranular(scene, work_);
  const std::string context = "\n  file: " + scene.string() + "\n  what: " + expectation.what +
                              "\n  stderr: <<<" + run.stderrText + ">>>";
  ASSERT_FALSE(run.timedOut) << "still running after 60 s (the scene was accepted?)" << context;
  ASSERT_TRUE(run.exited) << "killed by signal " << run.status << context;
  EXPECT_EQ(run.status, 2) << "exit status" << context;

  // One clear error: a single non-empty line, so nothing else (a sanitizer report, "terminate
  // called", a progress line) was printed.
  const std::string& err = run.stderrText;
  EXPECT_TRUE(!err.empty() && err.back() == '\n' && std::count(err.begin(), err.end(), '\n') == 1 &&
              err.size() > 1)
      << "stderr is not exactly one line" << context;
  EXPECT_NE(err.find(scene.filename().string()), std::string::npos)
      << "the message does not name the scene file" << context;
  for (const std::string& part : expectation.substrings) {
    EXPECT_NE(err.find(part), std::string::npos) << "missing '" << part << "'" << context;
  }
}

INSTANTIATE_TEST_SUITE_P(Corpus, MalformedScene, ::testing::ValuesIn(corpusFiles()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return MalformedScene::sanitized(info.param);
                         });

}  // namespace
