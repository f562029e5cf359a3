/// libFuzzer target for the checkpoint reader (parseCheckpoint: the field parser and
/// validateRestoredState), and for the engine stepping whatever state the reader accepts.
///
/// The input is the payload: it is wrapped in a valid frame ("GRANCKPT", version, fingerprint,
/// payload size, payload, FNV-1a of the payload) so that the fuzzer does not spend its time on
/// the checksum, which a random mutation never gets right. A state the reader accepts is stepped
/// a few times; the reader promises that no accepted state makes the engine misbehave.
///
/// Allowed outcomes: CheckpointError (refused), ConfigError (refused by the engine),
/// NumericalError (a state that is valid but blows up). Anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "granular/checkpoint.hpp"
#include "granular/error.hpp"

namespace {

std::uint64_t fnv1a(const std::uint8_t* data, std::size_t size) {
  std::uint64_t h = 1469598103934665603ULL;
  for (std::size_t i = 0; i < size; ++i) {
    h ^= data[i];
    h *= 1099511628211ULL;
  }
  return h;
}

template <class T>
void put(std::vector<char>& out, T value) {
  const char* p = reinterpret_cast<const char*>(&value);
  out.insert(out.end(), p, p + sizeof value);
}

constexpr int kSteps = 3;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<char> file = {'G', 'R', 'A', 'N', 'C', 'K', 'P', 'T'};
  file.reserve(file.size() + 28 + size);
  put(file, granular::kCheckpointVersion);
  put(file, std::uint64_t{0x66757a7a});  // any fingerprint: none is expected below
  put(file, static_cast<std::uint64_t>(size));
  if (size > 0) file.insert(file.end(), data, data + size);
  put(file, fnv1a(data, size));
  try {
    granular::CheckpointContents contents = granular::parseCheckpoint(file, "fuzz-input");
    // One thread: the fuzzer runs many tiny states, where starting a team costs more than the
    // step; the threaded code is covered by the TSan suite.
    contents.simulation.setThreads(1);
    contents.simulation.run(kSteps);
  } catch (const granular::CheckpointError&) {
  } catch (const granular::ConfigError&) {
  } catch (const granular::NumericalError&) {
  }
  return 0;
}
