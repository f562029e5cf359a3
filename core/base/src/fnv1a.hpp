#pragma once
/// FNV-1a, 64 bits (private to the core): the checksum of checkpoints and the fingerprint of
/// the files and values a run is computed from. Not cryptographic: it tells an edit from the
/// original, it does not resist a forger.
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace granular {

inline constexpr std::uint64_t kFnv1aOffset = 1469598103934665603ULL;

/// Continues the hash `h` over `size` bytes at `data` (start with kFnv1aOffset).
inline std::uint64_t fnv1a(const char* data, std::size_t size, std::uint64_t h = kFnv1aOffset) {
  for (std::size_t i = 0; i < size; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= 1099511628211ULL;
  }
  return h;
}

inline std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h = kFnv1aOffset) {
  return fnv1a(bytes.data(), bytes.size(), h);
}

}  // namespace granular
