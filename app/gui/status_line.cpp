/// The status line's text (status_line.hpp).
#include "status_line.hpp"

#include <cstdio>

namespace granular::gui {

std::string statusLine(const Snapshot& snap, double framesPerSecond) {
  char line[256];
  std::snprintf(line, sizeof line,
                "t = %.4f s | stage %d | %s | %.0f steps/s | %zu contacts + %zu wall | energy "
                "balance %+.2e | %.0f frames/s",
                snap.time, snap.stage, snap.running ? "running" : "paused", snap.stepsPerSecond,
                snap.particleContacts, snap.wallContacts, snap.energyBalanceError, framesPerSecond);
  // A check that stopped the run is its message too: said once, by failedCheckStatus.
  const bool said = !snap.failedChecks.empty() && snap.message == snap.failedChecks.back();
  return std::string(line) + (snap.message.empty() || said ? "" : " | " + snap.message);
}

std::string failedCheckStatus(const Snapshot& snap) {
  if (snap.failedChecks.empty()) return {};
  const std::size_t earlier = snap.failedChecks.size() - 1;
  return "run check failed: " + snap.failedChecks.back() +
         (earlier > 0 ? " (and " + std::to_string(earlier) + " earlier)" : "");
}

}  // namespace granular::gui
