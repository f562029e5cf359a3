/// Laying out and carrying the touching pairs' springs (pair_springs.hpp).
#include "pair_springs.hpp"

#include <algorithm>
#include <bit>

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
  /// Starting at row `row` (that of the first pair asked for, or one before it).
  PairKeys(const std::vector<std::uint32_t>& rowStart, const std::vector<std::uint32_t>& second,
           std::uint32_t row = 0)
      : rowStart_(rowStart), second_(second), row_(row) {}
  /// The key of pair k, k not below the last asked for.
  std::uint64_t at(std::size_t k) {
    while (rowStart_[row_ + 1] <= k) ++row_;
    return (std::uint64_t{row_} << 32) | second_[k];
  }

 private:
  const std::vector<std::uint32_t>& rowStart_;
  const std::vector<std::uint32_t>& second_;
  std::uint32_t row_;
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

namespace {

/// The row of pair k of a list (rowStart ascending, k below its last entry).
std::uint32_t rowOf(const std::vector<std::uint32_t>& rowStart, std::size_t k) {
  return static_cast<std::uint32_t>(
      std::upper_bound(rowStart.begin(), rowStart.end(), std::uint32_t(k)) - rowStart.begin() - 1);
}

/// The first pair of a list whose key is not below (i, j).
std::size_t firstPairFrom(const std::vector<std::uint32_t>& rowStart,
                          const std::vector<std::uint32_t>& second, std::uint32_t i,
                          std::uint32_t j) {
  if (std::size_t(i) + 1 >= rowStart.size()) return second.size();
  return std::size_t(
      std::lower_bound(second.begin() + rowStart[i], second.begin() + rowStart[i + 1], j) -
      second.begin());
}

/// How many pairs of block b before pair k hold a spring.
std::size_t heldBefore(const std::vector<std::uint64_t>& held,
                       const std::vector<std::uint32_t>& blockPair,
                       const std::vector<std::uint32_t>& blockWord, std::size_t b, std::size_t k) {
  const auto [w, bit] = heldBit(blockPair, b, k);
  std::size_t count = 0;
  for (std::size_t v = 0; v < w; ++v) count += std::popcount(held[blockWord[b] + v]);
  if (bit > 0) count += std::popcount(held[blockWord[b] + w] & ((std::uint64_t{1} << bit) - 1));
  return count;
}

}  // namespace

PairSprings carryPairSprings(NeighbourList& old, const std::vector<std::uint32_t>& rowStart,
                             const std::vector<std::uint32_t>& second,
                             const std::vector<std::uint32_t>& blockPair,
                             const std::vector<std::uint32_t>& blockWord, int threads) {
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
  const std::size_t oldBlocks = oldHolds ? old.blockPair.size() - 1 : 0;
  /// Where the new list's pair k falls in the old list: the first old pair not below it.
  auto oldFrom = [&](std::size_t k) -> std::size_t {
    if (k >= second.size()) return oldPairs;
    return std::min(oldPairs,
                    firstPairFrom(old.rowStart, old.second, rowOf(rowStart, k), second[k]));
  };
  // Block b's springs: a walk of the new block's pairs beside the old list's from where the
  // block's first pair falls in it. Blocks are independent, so threads take them in rounds;
  // after each round the old blocks wholly passed are freed, so that the old and the new
  // springs are not held whole at once.
  auto carryBlock = [&](std::size_t b, std::vector<double>& found) {
    found.clear();
    if (oldPairs > 0 && blockPair[b] < blockPair[b + 1]) {
      std::size_t a = oldFrom(blockPair[b]);
      std::size_t oldBlock = std::size_t(std::upper_bound(old.blockPair.begin(),
                                                          old.blockPair.end(), std::uint32_t(a)) -
                                         old.blockPair.begin()) -
                             1;
      std::size_t index =
          a < oldPairs ? heldBefore(from.held, old.blockPair, old.blockWord, oldBlock, a) : 0;
      PairKeys oldKeys(old.rowStart, old.second, a < oldPairs ? rowOf(old.rowStart, a) : 0);
      PairKeys newKeys(rowStart, second, rowOf(rowStart, blockPair[b]));
      auto oldHeld = [&] { return holds(from.held, old.blockPair, old.blockWord, oldBlock, a); };
      for (std::size_t k = blockPair[b]; k < blockPair[b + 1] && a < oldPairs; ++k) {
        const std::uint64_t key = newKeys.at(k);
        while (a < oldPairs && oldKeys.at(a) < key) {
          index += oldHeld() ? 1 : 0;
          ++a;
          while (a < oldPairs && a >= old.blockPair[oldBlock + 1]) {
            ++oldBlock;
            index = 0;
          }
        }
        if (a < oldPairs && oldKeys.at(a) == key && oldHeld()) {
          setHeld(out.held, blockPair, blockWord, b, k);
          const double* record = from.block[oldBlock].data() + index * slots;
          found.insert(found.end(), record, record + slots);
        }
      }
    }
    fillBlock(out.block[b], found, slots);
  };
  const int teams = std::max(threads, 1);
  const std::size_t round = std::size_t(teams) * 16;
  std::size_t freed = 0;  // old blocks before this one are freed
  for (std::size_t first = 0; first < blocks; first += round) {
    const std::size_t last = std::min(blocks, first + round);
#pragma omp parallel num_threads(teams) if (teams > 1 && last - first > 1)
    {
      std::vector<double> found;
#pragma omp for schedule(dynamic)
      for (std::size_t b = first; b < last; ++b) carryBlock(b, found);
    }
    // The old blocks wholly before the next round's first pair are passed.
    const std::size_t reached = last < blocks ? oldFrom(blockPair[last]) : oldPairs;
    while (freed < oldBlocks && old.blockPair[freed + 1] <= reached) {
      std::vector<double>().swap(from.block[freed]);
      ++freed;
    }
  }
  from = PairSprings{};
  return out;
}

}  // namespace granular
