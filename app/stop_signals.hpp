#pragma once
/// SIGTERM and SIGINT as a request to stop cleanly, the way batch schedulers use them: SIGTERM
/// comes some seconds before SIGKILL. The handler only records the signal; the command finishes
/// the step it is in, writes what lets it continue (a checkpoint for `granular run`), says how
/// to resume and exits with 128 + the signal's number. A second signal of the same kind while
/// stopping ends the process at once, as if no handler were installed.
#include <stdexcept>
#include <string>

namespace granular::app {

/// Installs the handlers (once per process; later calls do nothing).
void catchStopSignals();

/// The signal received since catchStopSignals(), or 0.
int stopSignal();

/// "SIGTERM", "SIGINT".
std::string signalName(int signal);

/// Thrown by a command that stops on a signal; withErrorMapping prints the message and returns
/// 128 + the signal's number.
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& message)
      : std::runtime_error(message), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

/// Throws Interrupted if a stop signal has arrived; `what` says what is lost or kept.
void stopIfSignalled(const std::string& what);

}  // namespace granular::app
