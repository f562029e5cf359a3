/// Files written so that failure is never taken for success (granular/output_file.hpp): a failed
/// write, flush or close is reported with the file and the OS's reason, the previous version of
/// the file is kept, no temporary is left behind, and an appended file ends after a whole record.
/// Failures are made two ways: injected (GRANULAR_INJECT_IO_ERROR) and real, on a small tmpfs
/// that fills up (skipped, with the reason, where this process may not mount one).
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/mount.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include "granular/error.hpp"
#include "granular/output_file.hpp"
#include "granular_process.hpp"

namespace {

namespace fs = std::filesystem;
using granular::AppendFile;
using granular::AtomicFile;
using granular::IoError;
using granular::testing::readFile;

fs::path freshFolder(const char* name) {
  const fs::path dir = fs::temp_directory_path() / (std::string("granular_output_file_") + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// Sets GRANULAR_INJECT_IO_ERROR for the scope.
class InjectedFault {
 public:
  explicit InjectedFault(const std::string& spec) {
    ::setenv("GRANULAR_INJECT_IO_ERROR", spec.c_str(), 1);
  }
  ~InjectedFault() { ::unsetenv("GRANULAR_INJECT_IO_ERROR"); }
};

/// The message of the IoError that `write` throws, or a failure.
template <class F>
std::string ioErrorOf(F write) {
  try {
    write();
  } catch (const IoError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no IoError";
  return {};
}

bool anyTemporary(const fs::path& dir) {
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.path().extension() == ".tmp") return true;
  }
  return false;
}

/// A tmpfs of `bytes` mounted on a fresh folder, unmounted at the end.
class SmallDisk {
 public:
  SmallDisk(const char* name, std::size_t bytes) : dir_(freshFolder(name)) {
    const std::string options = "size=" + std::to_string(bytes);
    if (::mount("tmpfs", dir_.c_str(), "tmpfs", 0, options.c_str()) != 0) {
      reason_ = std::string("cannot mount a tmpfs here (") + std::strerror(errno) +
                "): needs root or CAP_SYS_ADMIN";
    }
  }
  ~SmallDisk() {
    if (reason_.empty()) ::umount(dir_.c_str());
    fs::remove_all(dir_);
  }
  bool mounted() const { return reason_.empty(); }
  const std::string& reason() const { return reason_; }
  const fs::path& dir() const { return dir_; }

 private:
  fs::path dir_;
  std::string reason_;
};

}  // namespace

TEST(OutputFile, AFailedWriteKeepsThePreviousVersionAndLeavesNoTemporary) {
  const fs::path dir = freshFolder("injected");
  const fs::path file = dir / "result.csv";
  granular::writeFileAtomically(file, "good\n");
  for (const char* spec : {"write:ENOSPC:result.csv", "close:EIO:result.csv"}) {
    InjectedFault fault(spec);
    const std::string message =
        ioErrorOf([&] { granular::writeFileAtomically(file, "new contents\n"); });
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find(std::strerror(
                  std::string(spec).find("ENOSPC") != std::string::npos ? ENOSPC : EIO)),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("previous version is kept"), std::string::npos) << message;
    EXPECT_EQ(readFile(file), "good\n") << spec;
    EXPECT_FALSE(anyTemporary(dir)) << spec;
  }
  // A flush to the disk that fails is a failure of a durable file (a checkpoint).
  InjectedFault fault("fsync:EIO:result.csv");
  const std::string message =
      ioErrorOf([&] { granular::writeFileAtomically(file, "new\n", /*durable=*/true); });
  EXPECT_NE(message.find("cannot flush to the disk: " + std::string(std::strerror(EIO))),
            std::string::npos)
      << message;
  EXPECT_EQ(readFile(file), "good\n");
  EXPECT_FALSE(anyTemporary(dir));
}

TEST(OutputFile, AFolderWhereTheFileShouldBeIsNamedAndLeftAlone) {
  const fs::path dir = freshFolder("folder");
  const fs::path file = dir / "particles.pvd";
  fs::create_directory(file);
  fs::create_directory(file / "inside");
  EXPECT_NE(ioErrorOf([&] { AtomicFile f(file); }).find(file.string() + ": cannot write: a folder"),
            std::string::npos);
  EXPECT_NE(ioErrorOf([&] { AppendFile f(file); }).find("a folder of that name is in the way"),
            std::string::npos);
  EXPECT_TRUE(fs::is_directory(file / "inside"));
  EXPECT_FALSE(anyTemporary(dir));
}

TEST(OutputFile, UncommittedFilesAreRemoved) {
  const fs::path dir = freshFolder("uncommitted");
  {
    AtomicFile f(dir / "half.csv");
    f.stream() << "half of it";
  }  // an exception between the writes and commit() ends here
  EXPECT_FALSE(fs::exists(dir / "half.csv"));
  EXPECT_FALSE(anyTemporary(dir));
}

TEST(OutputFile, AFullDiskKeepsThePreviousVersionAndNamesTheReason) {
  SmallDisk disk("full", 64 * 1024);
  if (!disk.mounted()) GTEST_SKIP() << disk.reason();
  const fs::path file = disk.dir() / "particles.pvd";
  granular::writeFileAtomically(file, "previous\n");
  const std::string big(256 * 1024, 'x');  // four times the disk
  const std::string message = ioErrorOf([&] { granular::writeFileAtomically(file, big); });
  EXPECT_NE(message.find(file.string() + ": cannot write: " + std::strerror(ENOSPC)),
            std::string::npos)
      << message;
  EXPECT_EQ(readFile(file), "previous\n");
  EXPECT_FALSE(anyTemporary(disk.dir()));
}

TEST(OutputFile, AnAppendedFileEndsAfterItsLastWholeRecordWhenTheDiskFills) {
  SmallDisk disk("append", 64 * 1024);
  if (!disk.mounted()) GTEST_SKIP() << disk.reason();
  const fs::path file = disk.dir() / "timeseries.csv";
  AppendFile series(file);
  const std::string record = std::string(999, 'r') + "\n";  // does not divide the disk's pages
  std::uint64_t whole = 0;
  std::string message;
  try {
    for (int i = 0; i < 1000; ++i) {
      series.append(record);
      whole += record.size();
    }
  } catch (const IoError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find(std::strerror(ENOSPC)), std::string::npos) << message;
  EXPECT_GT(whole, 0u);
  EXPECT_EQ(fs::file_size(file), whole);
  EXPECT_EQ(series.bytes(), whole);
}

TEST(OutputFile, ResumingCutsTheFileBackAndRefusesOneTooShort) {
  const fs::path dir = freshFolder("resume");
  const fs::path file = dir / "timeseries.csv";
  {
    AppendFile series(file);
    series.append("header\n");
    series.append("row 1\n");
    series.append("row 2\n");
  }
  {
    AppendFile series(file, 13);  // header and row 1
    series.append("row 2'\n");
  }
  EXPECT_EQ(readFile(file), "header\nrow 1\nrow 2'\n");
  EXPECT_NE(
      ioErrorOf([&] { AppendFile f(file, 1000); }).find("the checkpoint expects at least 1000"),
      std::string::npos);
}
