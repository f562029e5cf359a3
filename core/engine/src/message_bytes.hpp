#pragma once
/// Arrays of plain records as the bytes of a message between the processes of a split run
/// (Communicator::exchange): a count, then the records' bytes.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace granular {

/// Appends the count and the values' bytes. (Sized, then copied: GCC 12 misreads an insert of
/// the bytes here as an overflow, -Wstringop-overflow.)
template <class T>
void putArray(std::vector<std::byte>& out, const std::vector<T>& values) {
  const std::uint64_t count = values.size();
  const std::size_t at = out.size();
  const std::size_t bytes = values.size() * sizeof(T);
  // (A bound GCC 12 can see: without it, it takes the new size for one that may wrap.)
  if (bytes > std::size_t{1} << 48) throw std::length_error("split run: a message over 256 TiB");
  out.resize(at + sizeof count + bytes);
  std::memcpy(out.data() + at, &count, sizeof count);
  if (count > 0) {  // (an empty array's data() may be null, which memcpy may not be given)
    std::memcpy(out.data() + at + sizeof count, values.data(), values.size() * sizeof(T));
  }
}

/// Reads what putArray wrote at `at` onto the end of `appendTo`, and moves `at` past it.
template <class T>
void getArray(const std::vector<std::byte>& in, std::size_t& at, std::vector<T>& appendTo) {
  std::uint64_t count = 0;
  if (at + sizeof count > in.size()) throw std::logic_error("split run: a short message");
  std::memcpy(&count, in.data() + at, sizeof count);
  at += sizeof count;
  if (count > (in.size() - at) / sizeof(T)) throw std::logic_error("split run: a short message");
  const std::size_t before = appendTo.size();
  appendTo.resize(before + count);
  if (count > 0) {  // (an empty array's data() may be null, which memcpy may not be given)
    std::memcpy(static_cast<void*>(appendTo.data() + before), in.data() + at, count * sizeof(T));
  }
  at += count * sizeof(T);
}

}  // namespace granular
