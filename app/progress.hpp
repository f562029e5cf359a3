#pragma once
/// Progress lines on stderr for long runs: on a terminal one line updated in place a few times a
/// second; otherwise (a log file, CI) a plain line every few seconds, so short runs print none.
#include <chrono>
#include <cstdint>

#include "granular/communicator.hpp"
#include "granular/stage.hpp"

namespace granular::app {

class ProgressReporter {
 public:
  /// `enabled` false silences it (--quiet). Under mpirun (`ranks`) every rank calls it alike:
  /// rank 0's clock decides when a line is due, every rank takes part in the kinetic energy it
  /// shows, and rank 0 prints it.
  explicit ProgressReporter(bool enabled, const Communicator* ranks = nullptr);
  ~ProgressReporter() { finish(); }
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  /// Called every few hundred steps; prints only when the refresh period has passed.
  void update(const Simulation& sim, const StageSpec& stage);
  /// Ends the line being updated in place, so that the next output starts on a fresh line.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;

  bool enabled_;
  const Communicator* ranks_;
  bool terminal_;
  Clock::duration period_;
  Clock::time_point lastPrint_;
  std::uint64_t lastSteps_ = 0;
  bool started_ = false;
  bool lineOpen_ = false;
};

}  // namespace granular::app
