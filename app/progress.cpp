/// Progress lines (see progress.hpp).
#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace granular::app {

ProgressReporter::ProgressReporter(bool enabled, const Communicator* ranks)
    : enabled_(enabled),
      ranks_(ranks),
      terminal_(isatty(STDERR_FILENO) != 0),
      period_(terminal_ ? std::chrono::milliseconds(250) : std::chrono::seconds(5)),
      lastPrint_(Clock::now()) {}

void ProgressReporter::update(const Simulation& sim, const StageSpec& stage) {
  if (!enabled_) return;
  const Clock::time_point now = Clock::now();
  if (!started_) {
    // The rate is measured between prints: the first call only starts the measurement.
    started_ = true;
    lastPrint_ = now;
    lastSteps_ = sim.stepCount();
    return;
  }
  const double elapsed = std::chrono::duration<double>(now - lastPrint_).count();
  const bool due = !(now - lastPrint_ < period_ || elapsed <= 0.0);
  const bool root = !ranks_ || ranks_->rank() == 0;
  if (!(ranks_ ? ranks_->anyOverRanks(root && due) : due)) return;
  const double kinetic = sim.kineticEnergy();  // a sum over every rank's particles
  if (!root) return;
  const double rate = double(sim.stepCount() - lastSteps_) / elapsed;
  const StepCounters& c = sim.counters();
  char line[256];
  std::snprintf(line, sizeof line,
                "[%s] t = %.4f s  step %llu  %.0f steps/s  KE %.3e J  contacts %zu + %zu wall",
                stage.name.c_str(), sim.time(), (unsigned long long)sim.stepCount(), rate, kinetic,
                c.particleContacts, c.wallContacts);
  if (terminal_) {
    std::fprintf(stderr, "\r%s\x1b[K", line);  // back to column 0, clear the old tail
    lineOpen_ = true;
  } else {
    std::fprintf(stderr, "%s\n", line);
  }
  std::fflush(stderr);
  lastPrint_ = now;
  lastSteps_ = sim.stepCount();
}

void ProgressReporter::finish() {
  if (lineOpen_) {
    std::fprintf(stderr, "\r\x1b[K");
    std::fflush(stderr);
  }
  lineOpen_ = false;
  started_ = false;
}

}  // namespace granular::app
