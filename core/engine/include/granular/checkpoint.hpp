#pragma once
/// Checkpoints: the complete state of a Simulation (particles, integrator derivatives, contact
/// history, walls, clocks, energy accounts), so that a run restarted from one continues bit for
/// bit as if it had never stopped.
///
/// File layout (little-endian, as written by this machine):
///   "GRANCKPT" | u32 format version | u64 scene fingerprint | u64 payload bytes | payload |
///   u64 FNV-1a checksum of the payload
/// where payload = the fingerprint's parts (u64 count, then per part its key as u64 length and
/// bytes, and its u64 hash) | the state's fields | u64 n | n bytes of the caller's data (appData).
/// The file is written to "<path>.tmp", flushed to the disk and renamed over <path>, so a crash
/// never leaves a half-written checkpoint under the real name; a failed write (full disk, failed
/// flush) throws IoError, removes the temporary and keeps the previous checkpoint.
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

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
/// 4: the fingerprint's parts before the state, so that a refusal can name what changed; and
///    Material::noPull (one flag byte) at the end of the payload (versions 2 and 3: true).
/// 5: every material parameter the contact model declares (granular/contact_model.hpp) as
///    (key, value) pairs after that flag: a parameter the file lacks keeps its default, one this
///    build does not declare is refused by name; and each contact's history as the terms'
///    slots (ContactHistory), with the list of (term, slot count) before the pairs, so that a
///    file is read into this build's layout by term (older files: the tangential spring's 4);
///    and every energy account (its value now, since the start, at the start) by column after
///    the material, so that a term's accounts travel without a field of their own.
/// 6: the step control (StepControl: automatic, safety, contact resolution, check interval,
///    on_unstable), the step asked for or chosen, and the steps since the step was last
///    checked, after the accounts: an automatic run resumes bit for bit (older files: fixed).
/// 7: the step counters (checks, unstable checks, the worst ratio, the smallest and largest
///    step) and the last check (StepCheck), after the step control: a resumed run's summary
///    counts from the start (older files: from the resume).
/// 8: whether the last check's frequency was estimated (StepCheck::estimated) and the
///    spectrum's calibration (NetworkCalibration), after the last check: an automatic run that
///    takes its step from the estimate resumes bit for bit (older files: none, made again at
///    the next check).
/// 9: the growing modes met (StepCounters::rollbacks and keptGrowths, and the calibration's
///    NetworkCalibration::rollbacks), after the calibration: a run whose estimate a growing
///    mode raised resumes bit for bit (older files: none met).
/// 10: the fewest steps between checks at rebuilds of an automatic step (its gap, lengthened
///    while the step holds still), after the growing modes: an automatic run resumes bit for
///    bit (older files: the least).
/// Versions 2 to 5 still read; checked against a SceneFingerprint they are refused, since their
/// one number cannot say whether the scene's particle files are the same.
inline constexpr std::uint32_t kCheckpointVersion = 10;

/// One input of a run and the hash of its content: a part of the scene ("material",
/// "stages[1]") or a file the scene reads ("particles[0]": the CSV's bytes).
struct FingerprintPart {
  std::string key;         ///< stable name, independent of where the files are
  std::uint64_t hash = 0;  ///< FNV-1a of the part's canonical bytes
  std::string label;       ///< how a message names it ("the particle file a.csv"); not stored
};

/// What a state was computed from, part by part (fingerprintScene, scene_fingerprint.hpp).
struct SceneFingerprint {
  std::vector<FingerprintPart> parts;
  /// One number for all the parts (keys and hashes, in order): the checkpoint header's.
  std::uint64_t combined() const;
};

/// Writes `sim` atomically. `sceneFingerprint` identifies what the state belongs to (for
/// instance fingerprintScene() of the scene); readCheckpoint can insist on it. `appData`
/// is stored with the state under the same checksum, so the two can never disagree. A state
/// with a non-finite position, velocity or angular velocity is refused (CheckpointError), so a
/// good checkpoint is never replaced by a broken one.
void writeCheckpoint(const Simulation& sim, const std::filesystem::path& file,
                     const SceneFingerprint& sceneFingerprint, const std::string& appData = {});
/// The same with a bare number for the header (no parts stored): for callers that identify the
/// state some other way, or not at all (0).
void writeCheckpoint(const Simulation& sim, const std::filesystem::path& file,
                     std::uint64_t sceneFingerprint, const std::string& appData = {});

/// A checkpoint's state and the caller's data stored with it.
struct CheckpointContents {
  Simulation simulation;
  std::string appData;
};

/// Reads a checkpoint; with a non-zero `expectedFingerprint`, refuses one whose header holds
/// another number. The state is checked for consistency (array sizes, contact indices, finite
/// values, known enumerations) before it is used. Throws CheckpointError for a file that is not
/// a usable checkpoint, IoError for one that cannot be read (missing, a folder or device, a read
/// error, larger than the memory available); the file is never read beyond what its header
/// announces.
Simulation readCheckpoint(const std::filesystem::path& file, std::uint64_t expectedFingerprint = 0);
CheckpointContents readCheckpointWithData(const std::filesystem::path& file,
                                          std::uint64_t expectedFingerprint = 0);
/// The same, refusing a checkpoint written for another scene with a message that names each
/// part that differs ("the particle file a.csv changed since the checkpoint was written").
Simulation readCheckpoint(const std::filesystem::path& file, const SceneFingerprint& expected);
CheckpointContents readCheckpointWithData(const std::filesystem::path& file,
                                          const SceneFingerprint& expected);
/// The same from bytes in memory; `name` stands for the file in messages (used by the fuzzer).
CheckpointContents parseCheckpoint(std::span<const char> bytes, const std::string& name,
                                   std::uint64_t expectedFingerprint = 0);
CheckpointContents parseCheckpoint(std::span<const char> bytes, const std::string& name,
                                   const SceneFingerprint& expected);

/// FNV-1a 64-bit hash of a file's bytes (throws IoError if it cannot be read).
std::uint64_t fingerprintFile(const std::filesystem::path& file);

}  // namespace granular
