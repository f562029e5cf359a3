/// What a user sees when the real `granular` cannot write its outputs: exit status 1 (an I/O
/// error, not 2 for an invalid scene, and never 0), one line on stderr naming the file and the
/// operating system's reason, no `*.tmp` left behind, and nothing half-written left under a real
/// name (the time series ends after a whole row; every .pvd lists files that exist). Failures
/// are injected (GRANULAR_INJECT_IO_ERROR) or real: a small tmpfs that fills up, a folder where
/// an output file should be.
#include <gtest/gtest.h>
#include <sys/mount.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "granular_process.hpp"

namespace {

namespace fs = std::filesystem;
using granular::testing::GranularProcess;
using granular::testing::readFile;

const fs::path kDemo = fs::path(GRANULAR_SOURCE_DIR) / "assets/scenes/demo.toml";

fs::path freshFolder(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("granular_write_failure_" + name);
  fs::remove_all(dir);
  return dir;
}

struct Outcome {
  int status = 0;
  std::string stderrText;
};

Outcome run(const std::vector<std::string>& args, const fs::path& stderrFile,
            std::vector<std::string> env = {}) {
  env.push_back("OMP_NUM_THREADS=1");
  GranularProcess p(args, stderrFile, env);
  EXPECT_TRUE(p.started());
  Outcome o;
  o.status = p.wait();
  o.stderrText = p.stderrText();
  return o;
}

std::size_t lines(const std::string& text) {
  std::size_t n = 0;
  for (char c : text) n += c == '\n';
  return n;
}

std::vector<fs::path> temporaries(const fs::path& dir) {
  std::vector<fs::path> found;
  if (!fs::exists(dir)) return found;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.path().extension() == ".tmp") found.push_back(entry.path());
  }
  return found;
}

/// Every row of a CSV file has the header's number of fields, and the file ends with a newline
/// (or is empty: its header could not be written).
void expectWholeRows(const fs::path& csv) {
  const std::string text = readFile(csv);
  if (text.empty()) return;
  EXPECT_EQ(text.back(), '\n') << csv << " ends mid-row";
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  const auto fields = [](const std::string& l) { return std::count(l.begin(), l.end(), ',') + 1; };
  const auto expected = fields(line);
  for (int row = 2; std::getline(in, line); ++row) {
    EXPECT_EQ(fields(line), expected) << csv << " row " << row;
  }
}

/// The files a .pvd collection lists (its file="..." attributes) all exist.
void expectCollectionsPointAtFiles(const fs::path& dir) {
  const std::string attribute = "file=\"";
  for (const char* name : {"particles.pvd", "contacts.pvd", "walls.pvd"}) {
    if (!fs::exists(dir / name)) continue;
    const std::string text = readFile(dir / name);
    for (std::size_t at = text.find(attribute); at != std::string::npos;
         at = text.find(attribute, at + 1)) {
      const std::size_t begin = at + attribute.size();
      const std::string listed = text.substr(begin, text.find('"', begin) - begin);
      EXPECT_TRUE(fs::exists(dir / listed)) << name << " lists " << listed;
    }
  }
}

}  // namespace

TEST(WriteFailures, AnOutputPathOccupiedByAFolderStopsTheRunNamingIt) {
  const fs::path out = freshFolder("occupied");
  // The first ParaView file of the run: the settle stage's snapshot at 0.1 s, taken at the first
  // step at or after it (demo.toml: time_step = 1.7e-4 s), and named by that step.
  const auto step = std::uint64_t(std::ceil(0.1 / 1.7e-4));
  const fs::path occupied =
      out / "paraview" / ("settle_" + std::to_string(step) + "_particles.vtp");
  fs::create_directories(occupied);
  const Outcome o =
      run({"run", kDemo.string(), "--out", out.string(), "-q"}, out.string() + ".err");
  EXPECT_EQ(o.status, 1) << o.stderrText;
  EXPECT_EQ(lines(o.stderrText), 1u) << o.stderrText;  // no VTK log burying it
  EXPECT_NE(o.stderrText.find(occupied.string() + ": cannot write: a folder"), std::string::npos)
      << o.stderrText;
  EXPECT_TRUE(temporaries(out).empty());
  expectCollectionsPointAtFiles(out);
}

TEST(WriteFailures, ACheckpointThatCannotBeWrittenOrFlushedIsAnIoError) {
  for (const std::string spec : {"write:ENOSPC:checkpoint.bin", "fsync:EIO:checkpoint.bin"}) {
    const fs::path out = freshFolder("checkpoint");
    const Outcome o = run({"run", kDemo.string(), "--out", out.string(), "-q"},
                          out.string() + ".err", {"GRANULAR_INJECT_IO_ERROR=" + spec});
    EXPECT_EQ(o.status, 1) << spec << ": " << o.stderrText;
    EXPECT_EQ(lines(o.stderrText), 1u) << o.stderrText;
    const std::string reason =
        std::strerror(spec.find("ENOSPC") != std::string::npos ? ENOSPC : EIO);
    EXPECT_NE(o.stderrText.find((out / "checkpoint.bin").string()), std::string::npos)
        << o.stderrText;
    EXPECT_NE(o.stderrText.find(reason), std::string::npos) << o.stderrText;
    EXPECT_FALSE(fs::exists(out / "checkpoint.bin"));
    EXPECT_TRUE(temporaries(out).empty()) << spec;
  }
}

TEST(WriteFailures, EveryWriterReportsAnInjectedFullDisk) {
  // One writer of each kind: the time series (appended rows), a particle CSV, a ParaView file
  // and its collection, the summary.
  for (const std::string name : {"timeseries.csv", "snapshot_", "final_state.csv", "_particles.vtp",
                                 "particles.pvd", "summary.txt"}) {
    const fs::path out = freshFolder("injected");
    const Outcome o = run({"run", kDemo.string(), "--out", out.string(), "-q"},
                          out.string() + ".err", {"GRANULAR_INJECT_IO_ERROR=write:ENOSPC:" + name});
    EXPECT_EQ(o.status, 1) << name << ": " << o.stderrText;
    EXPECT_EQ(lines(o.stderrText), 1u) << o.stderrText;
    EXPECT_NE(o.stderrText.find(name), std::string::npos) << o.stderrText;
    EXPECT_NE(o.stderrText.find(std::strerror(ENOSPC)), std::string::npos) << o.stderrText;
    EXPECT_TRUE(temporaries(out).empty()) << name;
    if (fs::exists(out / "timeseries.csv")) expectWholeRows(out / "timeseries.csv");
    expectCollectionsPointAtFiles(out);
  }
}

TEST(WriteFailures, ARealFullDiskEndsTheRunWithWholeFilesOnly) {
  const fs::path disk = freshFolder("tmpfs");
  fs::create_directories(disk);
  // The demo writes about 0.5 MB: this disk fills part-way through.
  if (::mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=300k") != 0) {
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno)
                 << "): needs root or CAP_SYS_ADMIN";
  }
  const fs::path out = disk / "run";
  const Outcome o =
      run({"run", kDemo.string(), "--out", out.string(), "-q"}, disk.string() + ".err");
  EXPECT_EQ(o.status, 1) << o.stderrText;
  EXPECT_EQ(lines(o.stderrText), 1u) << o.stderrText;
  EXPECT_NE(o.stderrText.find(std::strerror(ENOSPC)), std::string::npos) << o.stderrText;
  EXPECT_TRUE(temporaries(out).empty());
  expectWholeRows(out / "timeseries.csv");
  expectCollectionsPointAtFiles(out);
  ::umount(disk.c_str());
}

TEST(WriteFailures, CalibrateRefusesAReportFolderBeforeSettlingAnything) {
  const fs::path dir = freshFolder("report");
  fs::create_directories(dir);
  const Outcome o =
      run({"calibrate-box", kDemo.string(), "--sides", "0.5", "--report", dir.string(), "-q"},
          dir.string() + ".err");
  EXPECT_EQ(o.status, 1) << o.stderrText;
  EXPECT_NE(o.stderrText.find("--report is a folder"), std::string::npos) << o.stderrText;
  EXPECT_FALSE(fs::exists(dir.string() + ".tmp"));
  EXPECT_TRUE(temporaries(dir).empty());
}
