#pragma once
/// Checkpoints: the complete state of a Simulation (particles, integrator derivatives, contact
/// history, walls, clocks, energy accounts), so that a run restarted from one continues bit for
/// bit as if it had never stopped.
///
/// File layout (little-endian, as written by this machine):
///   "GRANCKPT" | u32 format version | u64 scene fingerprint | u64 payload bytes | payload |
///   u64 FNV-1a checksum of the payload
/// The file is written to "<path>.tmp" and renamed over <path>, so a crash never leaves a
/// half-written checkpoint under the real name.
#include <cstdint>
#include <filesystem>
#include <stdexcept>

#include "granular/simulation.hpp"

namespace granular {

/// A checkpoint that cannot be used: missing, truncated, corrupted, of another format version or
/// of another scene. The message names the file and what is wrong.
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// 2: no inverse masses or Gear rotational positions (not needed to continue bit for bit).
inline constexpr std::uint32_t kCheckpointVersion = 2;

/// Writes `sim` atomically. `sceneFingerprint` identifies what the state belongs to (for
/// instance fingerprintFile() of the scene file); readCheckpoint can insist on it.
void writeCheckpoint(const Simulation& sim, const std::filesystem::path& file,
                     std::uint64_t sceneFingerprint);

/// Reads a checkpoint; with a non-zero `expectedFingerprint`, refuses one written for another
/// scene. Throws CheckpointError.
Simulation readCheckpoint(const std::filesystem::path& file, std::uint64_t expectedFingerprint = 0);

/// FNV-1a 64-bit hash of a file's bytes (throws CheckpointError if it cannot be read).
std::uint64_t fingerprintFile(const std::filesystem::path& file);

}  // namespace granular
