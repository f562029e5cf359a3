#pragma once
/// Exceptions thrown by the core. The core never prints; callers decide how to report.
#include <stdexcept>
#include <string>

namespace granular {

/// A configuration the core refuses: bad parameter, unstable time step, particle outside the box.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A time step the engine refuses as unstable: above the stiffest contact's limit, or above the
/// step the contact network allows. A scene's builder names the key (simulation.time_step) and
/// where it is written.
class TimeStepError : public ConfigError {
 public:
  using ConfigError::ConfigError;
};

/// A scene file that cannot be read or does not validate. The message names the file, the key,
/// the value and the allowed range ("scene.toml:12:1: material.friction = -0.3: must be >= 0").
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file that cannot be opened, read, created or written in full: a folder or device where a
/// file should be, a full disk, a failed flush to the disk. The message names the file and the
/// operating system's reason ("out/timeseries.csv: cannot write: No space left on device").
/// Programs exit with status 1 for it.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A state that stopped being a number (NaN or infinity) during a step, detected at the end of
/// that step. The message names the step, the time and the first broken particle; the
/// Simulation is unusable afterwards (restart from the last checkpoint, which is never written
/// from a broken state).
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A NumericalError that one rank of a run split by space finds alone: the broken particle is
/// its own (its owner's finding; the other ranks cannot know of it).
class BrokenStateError : public NumericalError {
 public:
  using NumericalError::NumericalError;
};

}  // namespace granular
