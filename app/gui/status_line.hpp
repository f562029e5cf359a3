#pragma once
/// The window's status line, as text: the run's state, and a failed run check apart so that the
/// window can show it in a colour of its own.
#include <string>

#include "sim_runner.hpp"

namespace granular::gui {

/// "t = 0.1234 s | stage 1 | running | 5000 steps/s | 900 contacts + 120 wall | energy balance
/// +1.00e-05 | 60 frames/s", then " | " and the last message if there is one (unless it is the
/// failed check that stopped the run, which failedCheckStatus says).
std::string statusLine(const Snapshot& snap, double framesPerSecond);

/// "run check failed: <the latest failed check>" (and how many more failed before it); empty
/// while every run check has passed.
std::string failedCheckStatus(const Snapshot& snap);

}  // namespace granular::gui
