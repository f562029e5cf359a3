#pragma once
/// Checkpoints: the complete state of a Simulation (particles, integrator derivatives, contact
/// history, walls, clocks, energy accounts), so that a run restarted from one continues bit for
/// bit as if it had never stopped.
///
/// File layout (little-endian, as written by this machine):
///   "GRANCKPT" | u32 format version | u64 scene fingerprint | u64 payload bytes | payload |
///   u64 FNV-1a checksum of the payload
/// where payload = the state's fields | u64 n | n bytes of the caller's data (appData).
/// The file is written to "<path>.tmp" and renamed over <path>, so a crash never leaves a
/// half-written checkpoint under the real name.
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>

#include "granular/simulation.hpp"

namespace granular {

/// A checkpoint that cannot be used: missing, truncated, corrupted, of another format version or
/// of another scene. The message names the file and what is wrong.
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// 2: no inverse masses or Gear rotational positions (not needed to continue bit for bit).
/// 3: the caller's data after the state (a run's stage progress).
/// 4: after that, Material::noPull (one flag byte). Versions 2 and 3 still read (no pull).
inline constexpr std::uint32_t kCheckpointVersion = 4;

/// Writes `sim` atomically. `sceneFingerprint` identifies what the state belongs to (for
/// instance fingerprintFile() of the scene file); readCheckpoint can insist on it. `appData`
/// is stored with the state under the same checksum, so the two can never disagree. A state
/// with a non-finite position, velocity or angular velocity is refused (CheckpointError), so a
/// good checkpoint is never replaced by a broken one.
void writeCheckpoint(const Simulation& sim, const std::filesystem::path& file,
                     std::uint64_t sceneFingerprint, const std::string& appData = {});

/// A checkpoint's state and the caller's data stored with it.
struct CheckpointContents {
  Simulation simulation;
  std::string appData;
};

/// Reads a checkpoint; with a non-zero `expectedFingerprint`, refuses one written for another
/// scene. The state is checked for consistency (array sizes, contact indices, finite values,
/// known enumerations) before it is used. Throws CheckpointError.
Simulation readCheckpoint(const std::filesystem::path& file, std::uint64_t expectedFingerprint = 0);
CheckpointContents readCheckpointWithData(const std::filesystem::path& file,
                                          std::uint64_t expectedFingerprint = 0);
/// The same from bytes in memory; `name` stands for the file in messages (used by the fuzzer).
CheckpointContents parseCheckpoint(std::span<const char> bytes, const std::string& name,
                                   std::uint64_t expectedFingerprint = 0);

/// FNV-1a 64-bit hash of a file's bytes (throws CheckpointError if it cannot be read).
std::uint64_t fingerprintFile(const std::filesystem::path& file);

}  // namespace granular
