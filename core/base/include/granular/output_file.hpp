#pragma once
/// Files read and written so that a failure is never taken for success: every write, the flush
/// to the disk and the close are checked; a new version of a file is written to "<file>.tmp" and
/// renamed over the file only once it is whole, so a failed write keeps the previous version; a
/// temporary left by an error is removed. Failures throw IoError naming the file and the
/// operating system's reason ("No space left on device").
///
/// Test hook: GRANULAR_INJECT_IO_ERROR="OP:ERRNO:TEXT" makes the operation OP (write, fsync or
/// close) fail with ERRNO (ENOSPC, EIO, EDQUOT, EROFS, EACCES or a number) on every file
/// written here whose path contains TEXT, so that tests reproduce a full disk or a failing
/// device without having one.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace granular {

/// A new version of `target`: written through stream() into "<target>.tmp", renamed over
/// `target` by commit(). Destroyed without a successful commit(), it removes the temporary and
/// leaves `target` as it was.
class AtomicFile {
 public:
  /// IoError at once if `target` cannot be a file (a folder of that name is in the way) or the
  /// temporary cannot be created. `durable`: commit() also waits until the bytes and the rename
  /// are on the disk (fsync), so that a power cut leaves the old or the new file whole.
  explicit AtomicFile(std::filesystem::path target, bool durable = false);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// Buffered; a failed write is remembered and reported by commit().
  std::ostream& stream();
  /// Flushes, checks every write, (durable: fsync), closes and renames into place. IoError
  /// otherwise, with the temporary removed and `target` untouched.
  void commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// `bytes` as the new version of `file` (AtomicFile).
void writeFileAtomically(const std::filesystem::path& file, std::string_view bytes,
                         bool durable = false);

/// A file grown by whole records, such as a time series: each append() is one write of the whole
/// record, and a record that fails part-way is cut off again, so the file always ends after its
/// last whole record.
class AppendFile {
 public:
  /// Creates `file`, or empties an existing one.
  explicit AppendFile(std::filesystem::path file);
  /// Continues `file` after its first `keepBytes` bytes, cutting off the rest (a resumed run).
  /// IoError if the file is shorter or cannot be opened. With `expectedHash`, the kept bytes
  /// must hash to it (contentHash() when they were written) or nothing is cut and ConfigError
  /// says the file was changed: a resumed run continues only what it wrote itself.
  AppendFile(std::filesystem::path file, std::uint64_t keepBytes,
             std::optional<std::uint64_t> expectedHash = std::nullopt);
  ~AppendFile();
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;

  void append(std::string_view record);
  /// Waits until everything appended is on the disk (fdatasync).
  void sync();
  /// Bytes in the file [B].
  std::uint64_t bytes() const { return bytes_; }
  /// FNV-1a of every byte in the file (kept and appended).
  std::uint64_t contentHash() const { return hash_; }

 private:
  std::filesystem::path file_;
  int fd_ = -1;
  std::uint64_t bytes_ = 0;
  std::uint64_t hash_;
};

/// A regular file opened for reading. IoError naming the file and `what` it should be
/// ("checkpoint", "scene file") for a missing or unreadable file, a folder or a device.
class InputFile {
 public:
  InputFile(const std::filesystem::path& file, const char* what);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  /// Size when opened [B].
  std::uint64_t size() const { return size_; }
  /// `bytes` bytes from `offset` (IoError where a read fails or the file ends first).
  std::string read(std::uint64_t offset, std::uint64_t bytes);
  /// The whole file; IoError if it holds more than `maxBytes` or a read fails.
  std::string readAll(std::uint64_t maxBytes);

 private:
  std::filesystem::path file_;
  std::string what_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

/// Memory this process can still allocate [B]: the kernel's MemAvailable, or the room left
/// under the control group's limit where that is lower; 0 where neither can be read.
std::uint64_t availableMemoryBytes();

}  // namespace granular
