#pragma once
/// granular's command line: every subcommand and option in one place, so `main` only parses and
/// dispatches and the tests can walk the same tree (help completeness, docs/guide.md's reference).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>

#include "calibrate_command.hpp"
#include "granular/communicator.hpp"
#include "paper_command.hpp"
#include "run_command.hpp"
#include "silo_command.hpp"

namespace granular::app {

class CommandLine {
 public:
  /// `ranks`: the processes of an MPI run (main, when mpirun started it), or null alone.
  explicit CommandLine(std::shared_ptr<const Communicator> ranks = nullptr);
  CommandLine(const CommandLine&) = delete;
  CommandLine& operator=(const CommandLine&) = delete;

  CLI::App& app() { return app_; }

  /// Parses and runs the chosen subcommand. Exit status: 0 done (or --help), 1 I/O error,
  /// 2 invalid scene, configuration or arguments, 3 the simulation's state broke.
  int run(int argc, char** argv);

 private:
  std::shared_ptr<const Communicator> ranks_;
  CLI::App app_{"granular: discrete-element simulation of spheres in a box"};
  RunOptions run_;
  PaperOptions paper_;
  CalibrateOptions calibrate_;
  SiloOptions silo_;
  std::filesystem::path figuresDir_;
  CLI::App* runCommand_ = nullptr;
  CLI::App* paperCommand_ = nullptr;
  CLI::App* calibrateCommand_ = nullptr;
  CLI::App* figuresCommand_ = nullptr;
  CLI::App* siloCommand_ = nullptr;
};

}  // namespace granular::app
