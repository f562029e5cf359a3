/// Checked file writing and bounded reading (output_file.hpp). Sections: 1. injected faults;
/// 2. descriptor helpers; 3. AtomicFile; 4. AppendFile; 5. InputFile; 6. available memory.
#include "granular/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <streambuf>
#include <string>
#include <utility>

#include "fnv1a.hpp"
#include "granular/error.hpp"

namespace granular {

namespace {

// 1. Injected faults ------------------------------------------------------------------------------

enum class Operation { Write, Fsync, Close };

/// GRANULAR_INJECT_IO_ERROR = "OP:ERRNO:TEXT" (output_file.hpp) as it applies to one file.
struct InjectedFault {
  Operation operation = Operation::Write;
  int error = 0;
};

int errnoNamed(const std::string& name) {
  static const std::array<std::pair<const char*, int>, 6> kNames = {{{"ENOSPC", ENOSPC},
                                                                     {"EIO", EIO},
                                                                     {"EDQUOT", EDQUOT},
                                                                     {"EROFS", EROFS},
                                                                     {"EACCES", EACCES},
                                                                     {"EFBIG", EFBIG}}};
  for (const auto& [text, value] : kNames) {
    if (name == text) return value;
  }
  char* end = nullptr;
  const long value = std::strtol(name.c_str(), &end, 10);
  return (end && *end == '\0' && value > 0 && value < 4096) ? int(value) : 0;
}

std::optional<InjectedFault> injectedFault(const std::filesystem::path& file) {
  const char* text = std::getenv("GRANULAR_INJECT_IO_ERROR");
  if (!text || !*text) return std::nullopt;
  const std::string spec = text;
  const std::size_t a = spec.find(':');
  const std::size_t b = a == std::string::npos ? a : spec.find(':', a + 1);
  if (b == std::string::npos) {
    throw ConfigError("GRANULAR_INJECT_IO_ERROR = '" + spec + "': expected OP:ERRNO:TEXT");
  }
  const std::string op = spec.substr(0, a), name = spec.substr(a + 1, b - a - 1);
  InjectedFault fault;
  if (op == "write") {
    fault.operation = Operation::Write;
  } else if (op == "fsync") {
    fault.operation = Operation::Fsync;
  } else if (op == "close") {
    fault.operation = Operation::Close;
  } else {
    throw ConfigError("GRANULAR_INJECT_IO_ERROR = '" + spec +
                      "': OP must be write, fsync or close");
  }
  fault.error = errnoNamed(name);
  if (fault.error == 0) {
    throw ConfigError("GRANULAR_INJECT_IO_ERROR = '" + spec + "': unknown ERRNO '" + name + "'");
  }
  if (file.string().find(spec.substr(b + 1)) == std::string::npos) return std::nullopt;
  return fault;
}

// 2. Descriptor helpers ---------------------------------------------------------------------------

/// The injected error for `operation`, or 0.
int injected(const std::optional<InjectedFault>& fault, Operation operation) {
  return fault && fault->operation == operation ? fault->error : 0;
}

/// Writes all of `data`; 0 or the errno of the failure.
int writeAll(int fd, const char* data, std::size_t size,
             const std::optional<InjectedFault>& fault) {
  if (const int e = injected(fault, Operation::Write); e != 0 && size > 0) return e;
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return errno;
    if (n == 0) return EIO;
    data += n;
    size -= std::size_t(n);
  }
  return 0;
}

int syncFile(int fd, const std::optional<InjectedFault>& fault) {
  if (const int e = injected(fault, Operation::Fsync)) return e;
  return ::fsync(fd) == 0 ? 0 : errno;
}

int closeFile(int fd, const std::optional<InjectedFault>& fault) {
  const int result = ::close(fd) == 0 ? 0 : errno;
  if (const int e = injected(fault, Operation::Close)) return e;
  return result;
}

/// Best effort: a folder that cannot be opened or synced (some file systems) leaves a rename as
/// durable as the file system makes it.
void syncFolder(const std::filesystem::path& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

std::string reason(int error) {
  return std::strerror(error);
}

/// A folder where a file should be: the OS's own words ("Is a directory") come only at the
/// rename, after all the writing.
void refuseFolder(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) {
    throw IoError(file.string() + ": cannot write: a folder of that name is in the way");
  }
}

/// A stream buffer over a file descriptor that remembers the first failed write.
class DescriptorBuffer : public std::streambuf {
 public:
  DescriptorBuffer(int fd, std::optional<InjectedFault> fault)
      : fd_(fd), fault_(std::move(fault)), buffer_(1 << 16) {
    setp(buffer_.data(), buffer_.data() + buffer_.size());
  }
  /// 0, or the errno of the first failed write.
  int error() const { return error_; }
  bool drain() {
    if (error_ != 0) return false;
    const std::size_t n = std::size_t(pptr() - pbase());
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    if (n > 0) error_ = writeAll(fd_, buffer_.data(), n, fault_);
    return error_ == 0;
  }

 protected:
  int_type overflow(int_type ch) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  std::streamsize xsputn(const char* data, std::streamsize n) override {
    if (n <= epptr() - pptr()) {
      std::memcpy(pptr(), data, std::size_t(n));
      pbump(int(n));
      return n;
    }
    if (!drain()) return 0;
    error_ = writeAll(fd_, data, std::size_t(n), fault_);
    return error_ == 0 ? n : 0;
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  int fd_;
  std::optional<InjectedFault> fault_;
  std::vector<char> buffer_;
  int error_ = 0;
};

}  // namespace

// 3. AtomicFile -----------------------------------------------------------------------------------

struct AtomicFile::Impl {
  std::filesystem::path target, temporary;
  bool durable = false;
  std::optional<InjectedFault> fault;
  int fd = -1;
  std::unique_ptr<DescriptorBuffer> buffer;
  std::unique_ptr<std::ostream> stream;
  bool committed = false;

  [[noreturn]] void fail(const std::string& what, int error) {
    discard();
    std::error_code ec;
    const bool kept = std::filesystem::exists(target, ec);
    throw IoError(target.string() + ": " + what + ": " + reason(error) +
                  (kept ? " (the previous version is kept)" : ""));
  }
  void discard() {
    if (fd >= 0) ::close(fd);
    fd = -1;
    std::error_code ec;
    std::filesystem::remove(temporary, ec);
  }
};

AtomicFile::AtomicFile(std::filesystem::path target, bool durable) : impl_(new Impl) {
  Impl& f = *impl_;
  refuseFolder(target);
  f.target = std::move(target);
  f.temporary = f.target;
  f.temporary += ".tmp";
  f.durable = durable;
  f.fault = injectedFault(f.target);
  f.fd = ::open(f.temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (f.fd < 0) {
    const int error = errno;
    throw IoError(f.target.string() + ": cannot create " + f.temporary.filename().string() + ": " +
                  reason(error));
  }
  f.buffer = std::make_unique<DescriptorBuffer>(f.fd, f.fault);
  f.stream = std::make_unique<std::ostream>(f.buffer.get());
}

AtomicFile::~AtomicFile() {
  if (!impl_->committed) impl_->discard();
}

std::ostream& AtomicFile::stream() {
  return *impl_->stream;
}

void AtomicFile::commit() {
  Impl& f = *impl_;
  if (!f.buffer->drain()) f.fail("cannot write", f.buffer->error());
  if (f.durable) {
    if (const int e = syncFile(f.fd, f.fault)) f.fail("cannot flush to the disk", e);
  }
  const int fd = std::exchange(f.fd, -1);
  if (const int e = closeFile(fd, f.fault)) f.fail("cannot write", e);
  std::error_code ec;
  std::filesystem::rename(f.temporary, f.target, ec);
  if (ec) f.fail("cannot rename into place", ec.value());
  f.committed = true;
  if (f.durable) {
    syncFolder(f.target.has_parent_path() ? f.target.parent_path() : std::filesystem::path("."));
  }
}

void writeFileAtomically(const std::filesystem::path& file, std::string_view bytes, bool durable) {
  AtomicFile out(file, durable);
  out.stream().write(bytes.data(), std::streamsize(bytes.size()));
  out.commit();
}

// 4. AppendFile -----------------------------------------------------------------------------------

AppendFile::AppendFile(std::filesystem::path file) : file_(std::move(file)), hash_(kFnv1aOffset) {
  refuseFolder(file_);
  fd_ = ::open(file_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw IoError(file_.string() + ": cannot create: " + reason(errno));
}

AppendFile::AppendFile(std::filesystem::path file, std::uint64_t keepBytes,
                       std::optional<std::uint64_t> expectedHash)
    : file_(std::move(file)), hash_(kFnv1aOffset) {
  refuseFolder(file_);
  {
    // The kept bytes, read before anything is cut: a file changed where it is kept is refused
    // as it is.
    InputFile in(file_, "file to continue");
    if (in.size() >= keepBytes) {
      constexpr std::uint64_t kBlock = 1 << 20;
      for (std::uint64_t at = 0; at < keepBytes; at += kBlock) {
        const std::string block = in.read(at, std::min(kBlock, keepBytes - at));
        hash_ = fnv1a(block.data(), block.size(), hash_);
      }
      if (expectedHash && hash_ != *expectedHash) {
        throw ConfigError(file_.string() + ": its first " + std::to_string(keepBytes) +
                          " bytes, written before the checkpoint, were changed since (edited "
                          "by hand?); a resumed run continues only what it wrote itself: "
                          "restore the file, or start the run again");
      }
    }
  }
  fd_ = ::open(file_.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd_ < 0) throw IoError(file_.string() + ": cannot open to continue it: " + reason(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || std::uint64_t(st.st_size) < keepBytes) {
    const std::string size = std::to_string(std::uint64_t(st.st_size));
    ::close(fd_);
    fd_ = -1;
    throw IoError(file_.string() + ": cannot continue it: it has " + size +
                  " bytes, the checkpoint expects at least " + std::to_string(keepBytes));
  }
  if (::ftruncate(fd_, off_t(keepBytes)) != 0 || ::lseek(fd_, off_t(keepBytes), SEEK_SET) < 0) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    throw IoError(file_.string() + ": cannot cut it back to " + std::to_string(keepBytes) +
                  " bytes: " + reason(error));
  }
  bytes_ = keepBytes;
}

AppendFile::~AppendFile() {
  if (fd_ >= 0) ::close(fd_);
}

void AppendFile::append(std::string_view record) {
  if (const int e = writeAll(fd_, record.data(), record.size(), injectedFault(file_))) {
    // A record cut short by a full disk is taken back: the file ends after a whole record.
    if (::ftruncate(fd_, off_t(bytes_)) == 0) ::lseek(fd_, off_t(bytes_), SEEK_SET);
    throw IoError(file_.string() + ": cannot write: " + reason(e));
  }
  bytes_ += record.size();
  hash_ = fnv1a(record.data(), record.size(), hash_);
}

void AppendFile::sync() {
  if (const int e = syncFile(fd_, injectedFault(file_))) {
    throw IoError(file_.string() + ": cannot flush to the disk: " + reason(e));
  }
}

// 5. InputFile ------------------------------------------------------------------------------------

InputFile::InputFile(const std::filesystem::path& file, const char* what)
    : file_(file), what_(what) {
  fd_ = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw IoError(file.string() + ": cannot open " + what_ + ": " + reason(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    const int error = errno;
    ::close(fd_);
    throw IoError(file.string() + ": cannot read " + what_ + ": " + reason(error));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd_);
    throw IoError(file.string() + ": cannot read " + what_ + ": " +
                  (S_ISDIR(st.st_mode) ? "it is a folder" : "not a regular file (a device?)"));
  }
  size_ = std::uint64_t(st.st_size);
}

InputFile::~InputFile() {
  if (fd_ >= 0) ::close(fd_);
}

std::string InputFile::read(std::uint64_t offset, std::uint64_t bytes) {
  std::string data(static_cast<std::size_t>(bytes), '\0');
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::pread(fd_, data.data() + done, data.size() - done, off_t(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw IoError(file_.string() + ": cannot read " + what_ + ": " + reason(errno));
    if (n == 0) throw IoError(file_.string() + ": " + what_ + " shrank while being read");
    done += std::size_t(n);
  }
  return data;
}

std::string InputFile::readAll(std::uint64_t maxBytes) {
  if (size_ > maxBytes) {
    throw IoError(file_.string() + ": cannot read " + what_ + ": " + std::to_string(size_) +
                  " bytes, more than the " + std::to_string(maxBytes) + " it may have");
  }
  return read(0, size_);
}

// 6. Available memory -----------------------------------------------------------------------------

namespace {

std::optional<std::uint64_t> meminfoAvailable() {
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  std::uint64_t value = 0;
  while (in >> key >> value) {
    std::getline(in, unit);
    if (key == "MemAvailable:") return value * 1024;  // the kernel states kB
  }
  return std::nullopt;
}

/// Room left under a cgroup v2 limit ("max" or unreadable: none).
std::optional<std::uint64_t> cgroupRoom() {
  std::ifstream limitFile("/sys/fs/cgroup/memory.max"), usageFile("/sys/fs/cgroup/memory.current");
  std::string limitText;
  std::uint64_t usage = 0;
  if (!(limitFile >> limitText) || limitText == "max" || !(usageFile >> usage)) return std::nullopt;
  std::istringstream parse(limitText);
  std::uint64_t limit = 0;
  if (!(parse >> limit)) return std::nullopt;
  return limit > usage ? limit - usage : 0;
}

}  // namespace

std::uint64_t availableMemoryBytes() {
  const std::optional<std::uint64_t> system = meminfoAvailable(), group = cgroupRoom();
  if (system && group) return std::min(*system, *group);
  return system.value_or(group.value_or(0));
}

}  // namespace granular
