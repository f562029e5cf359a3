/// Laying out and carrying the touching pairs' springs (pair_springs.hpp).
#include "pair_springs.hpp"

namespace granular {
namespace {

/// Copies one block's records into its array, with room for a few new contacts.
void fillBlock(std::vector<double>& block, const std::vector<double>& found, std::size_t slots) {
  block.reserve(found.size() + (found.size() / slots / 16 + 2) * slots);
  block.assign(found.begin(), found.end());
}

/// Pairs in ascending order with their keys (first << 32 | second), walking the list's rows.
class PairKeys {
 public:
  PairKeys(const std::vector<std::uint32_t>& rowStart, const std::vector<std::uint32_t>& second)
      : rowStart_(rowStart), second_(second) {}
  /// The key of pair k, k not below the last asked for.
  std::uint64_t at(std::size_t k) {
    while (rowStart_[row_ + 1] <= k) ++row_;
    return (std::uint64_t{row_} << 32) | second_[k];
  }

 private:
  const std::vector<std::uint32_t>& rowStart_;
  const std::vector<std::uint32_t>& second_;
  std::uint32_t row_ = 0;
};

/// Whether pair k of block b (k in the block) holds a spring.
bool holds(const std::vector<std::uint64_t>& held, const std::vector<std::uint32_t>& blockPair,
           const std::vector<std::uint32_t>& blockWord, std::size_t b, std::size_t k) {
  const auto [w, bit] = heldBit(blockPair, b, k);
  return (held[blockWord[b] + w] >> bit) & 1;
}

void setHeld(std::vector<std::uint64_t>& held, const std::vector<std::uint32_t>& blockPair,
             const std::vector<std::uint32_t>& blockWord, std::size_t b, std::size_t k) {
  const auto [w, bit] = heldBit(blockPair, b, k);
  held[blockWord[b] + w] |= std::uint64_t{1} << bit;
}

}  // namespace

std::vector<ContactHistory> perPairSprings(const NeighbourList& list) {
  if (list.springs.held.empty() || list.springs.block.empty()) return {};
  std::vector<ContactHistory> perPair(list.second.size());
  SpringReader reader(list);
  for (std::size_t k = 0; k < perPair.size(); ++k) perPair[k] = reader.at(k);
  return perPair;
}

void layOutPairSprings(NeighbourList& list, const std::vector<ContactHistory>& perPair,
                       unsigned optional) {
  PairSprings& springs = list.springs;
  springs = PairSprings{};
  springs.optional = optional;
  springs.slots = historyRecordSlots(optional);
  if (perPair.size() != list.second.size() || list.blockPair.back() != perPair.size()) {
    springs.held.assign(perPair.size(), 0);
    return;
  }
  const std::size_t blocks = list.blockPair.size() - 1;
  springs.held.assign(list.blockWord.back(), 0);
  springs.block.resize(blocks);
  std::vector<double> found;
  for (std::size_t b = 0; b < blocks; ++b) {
    found.clear();
    for (std::size_t k = list.blockPair[b]; k < list.blockPair[b + 1]; ++k) {
      if (!perPair[k].holdsSomething()) continue;
      setHeld(springs.held, list.blockPair, list.blockWord, b, k);
      found.resize(found.size() + springs.slots);
      compactRecord(perPair[k], optional, found.data() + found.size() - springs.slots);
    }
    fillBlock(springs.block[b], found, springs.slots);
  }
}

void relayOutPairSprings(NeighbourList& list, unsigned optional) {
  if (list.springs.block.empty()) {  // nothing held (frictionless, or no list yet)
    list.springs.optional = optional;
    list.springs.slots = historyRecordSlots(optional);
    return;
  }
  layOutPairSprings(list, perPairSprings(list), optional);
}

PairSprings carryPairSprings(NeighbourList& old, const std::vector<std::uint32_t>& rowStart,
                             const std::vector<std::uint32_t>& second,
                             const std::vector<std::uint32_t>& blockPair,
                             const std::vector<std::uint32_t>& blockWord) {
  PairSprings out;
  out.optional = old.springs.optional;
  out.slots = historyRecordSlots(out.optional);
  const std::size_t slots = out.slots;
  const std::size_t blocks = blockPair.size() - 1;
  out.held.assign(blockWord.back(), 0);
  out.block.resize(blocks);
  PairSprings& from = old.springs;
  const bool oldHolds = !from.block.empty() && !old.blockWord.empty() &&
                        from.held.size() == old.blockWord.back() &&
                        old.blockPair.back() == old.second.size();
  const std::size_t oldPairs = oldHolds ? old.second.size() : 0;
  PairKeys oldKeys(old.rowStart, old.second), newKeys(rowStart, second);
  // The old list's walk: pair a, its block, and the index of a's spring in that block.
  std::size_t a = 0, oldBlock = 0, index = 0;
  auto skipPassedBlocks = [&] {
    while (oldBlock + 1 < old.blockPair.size() && a >= old.blockPair[oldBlock + 1]) {
      std::vector<double>().swap(from.block[oldBlock]);  // passed: free it
      ++oldBlock;
      index = 0;
    }
  };
  auto oldHeld = [&] { return holds(from.held, old.blockPair, old.blockWord, oldBlock, a); };
  if (oldPairs > 0) skipPassedBlocks();
  std::vector<double> found;
  for (std::size_t b = 0; b < blocks; ++b) {
    found.clear();
    for (std::size_t k = blockPair[b]; k < blockPair[b + 1]; ++k) {
      const std::uint64_t key = newKeys.at(k);
      while (a < oldPairs && oldKeys.at(a) < key) {
        index += oldHeld() ? 1 : 0;
        ++a;
        skipPassedBlocks();
      }
      if (a < oldPairs && oldKeys.at(a) == key && oldHeld()) {
        setHeld(out.held, blockPair, blockWord, b, k);
        const double* record = from.block[oldBlock].data() + index * slots;
        found.insert(found.end(), record, record + slots);
      }
    }
    fillBlock(out.block[b], found, slots);
  }
  from = PairSprings{};
  return out;
}

}  // namespace granular
