#pragma once
/// The real `granular` binary as a child process, for the tests that check what a user sees
/// (exit codes, stderr) and what a kill does: posix_spawn rather than popen, because popen goes
/// through a shell and captures only one stream, and a test must be able to SIGKILL the run.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern char** environ;

namespace granular::testing {

inline std::string readFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// `granular ARGS...` started at construction: stdout discarded, stderr into `stderrFile`, the
/// environment inherited plus `extraEnv` ("NAME=value").
class GranularProcess {
 public:
  GranularProcess(std::vector<std::string> args, std::filesystem::path stderrFile,
                  std::vector<std::string> extraEnv = {})
      : stderrFile_(std::move(stderrFile)) {
    std::string program = GRANULAR_EXECUTABLE;
    std::vector<char*> argv{program.data()};
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    for (char** e = environ; *e; ++e) extraEnv.emplace_back(*e);
    std::vector<char*> envp;
    for (std::string& e : extraEnv) envp.push_back(e.data());
    envp.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, stderrFile_.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    spawnError_ = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
  }
  bool started() const { return spawnError_ == 0; }
  int spawnError() const { return spawnError_; }
  /// True while it runs; once it has ended, its wait status is kept for `status()`.
  bool running() {
    if (ended_) return false;
    if (waitpid(pid_, &wstatus_, WNOHANG) == 0) return true;
    ended_ = true;
    return false;
  }
  /// Waits for the end; the exit status, or minus the signal that ended it.
  int wait() {
    if (!ended_) waitpid(pid_, &wstatus_, 0);
    ended_ = true;
    return WIFEXITED(wstatus_) ? WEXITSTATUS(wstatus_) : -WTERMSIG(wstatus_);
  }
  void kill() { ::kill(pid_, SIGKILL); }
  /// Sends `sig` (SIGTERM, SIGINT: what a batch scheduler or Ctrl-C sends).
  void signal(int sig) { ::kill(pid_, sig); }
  std::string stderrText() const { return readFile(stderrFile_); }

 private:
  std::filesystem::path stderrFile_;
  pid_t pid_ = -1;
  int spawnError_ = 0;
  int wstatus_ = 0;
  bool ended_ = false;
};

}  // namespace granular::testing
