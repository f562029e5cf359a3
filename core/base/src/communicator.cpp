/// What every Communicator does through its exchange (granular/communicator.hpp).
#include "granular/communicator.hpp"

#include <cstring>

namespace granular {

std::string Communicator::firstOverRanks(const std::string& mine) const {
  std::vector<std::byte> bytes(mine.size());
  if (!mine.empty()) std::memcpy(bytes.data(), mine.data(), mine.size());
  const std::vector<std::vector<std::byte>> all =
      exchange(std::vector<std::vector<std::byte>>(static_cast<std::size_t>(size()), bytes));
  for (const std::vector<std::byte>& text : all) {
    if (!text.empty()) return std::string(reinterpret_cast<const char*>(text.data()), text.size());
  }
  return {};
}

}  // namespace granular
