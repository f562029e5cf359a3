/// stop_signals.hpp.
#include "stop_signals.hpp"

#include <signal.h>

#include <atomic>

namespace granular::app {

namespace {

std::atomic<int> received{0};
static_assert(std::atomic<int>::is_always_lock_free, "the handler may only touch lock-free state");

void onStopSignal(int signal) {
  int none = 0;
  if (!received.compare_exchange_strong(none, signal) && none == signal) {
    // Asked twice: stop now, with the signal's own default action.
    ::signal(signal, SIG_DFL);
    ::raise(signal);
  }
}

}  // namespace

void catchStopSignals() {
  static const bool installed = [] {
    struct sigaction action {};
    action.sa_handler = onStopSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // the run's reads and writes go on undisturbed
    sigaction(SIGTERM, &action, nullptr);
    sigaction(SIGINT, &action, nullptr);
    return true;
  }();
  (void)installed;
}

int stopSignal() {
  return received.load(std::memory_order_relaxed);
}

std::string signalName(int signal) {
  switch (signal) {
    case SIGTERM:
      return "SIGTERM";
    case SIGINT:
      return "SIGINT";
    default:
      return "signal " + std::to_string(signal);
  }
}

void stopIfSignalled(const std::string& what) {
  if (const int signal = stopSignal()) {
    throw Interrupted(signal, "stopped by " + signalName(signal) + ": " + what);
  }
}

}  // namespace granular::app
