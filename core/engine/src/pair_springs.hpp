#pragma once
/// Finding, laying out and carrying the springs of the touching pairs (PairSprings in
/// simulation_state.hpp): springs are stored only for pairs that touched (or were within a
/// reaching term's reach) at the last force pass, each particle block's in its own array in
/// ascending pair order, and a bit per pair says which pairs hold one.
#include <bit>
#include <cstdint>
#include <vector>

#include "contact_law.hpp"
#include "simulation_state.hpp"

namespace granular {

/// The spring of a pair that holds none: no stretch, no stiffness.
inline const ContactHistory kNoSpring{};
/// The same as a stored record (every record is at most this long).
inline constexpr double kNoRecord[kHistorySlots] = {};

/// Doubles in a stored record for a scene with the optional terms `optional` (PairSprings).
inline std::size_t historyRecordSlots(unsigned optional) {
  std::size_t n = 0;
  for (bool included : kHistorySlotsByMask[optional]) n += included ? 1 : 0;
  return n;
}
/// A stored record as the contact's history (zero in the slots it does not hold).
inline ContactHistory expandRecord(const double* record, unsigned optional) {
  ContactHistory h;
  std::size_t at = 0;
  for (std::size_t k = 0; k < kHistorySlots; ++k) {
    if (kHistorySlotsByMask[optional][k]) h.slot[k] = record[at++];
  }
  return h;
}
/// The record of a contact's history (the slots of the terms `optional` includes).
inline void compactRecord(const ContactHistory& h, unsigned optional, double* record) {
  std::size_t at = 0;
  for (std::size_t k = 0; k < kHistorySlots; ++k) {
    if (kHistorySlotsByMask[optional][k]) record[at++] = h.slot[k];
  }
}

/// The bits below bit `bit` of a word.
inline std::uint64_t bitsBelow(std::uint64_t word, std::size_t bit) {
  return word & ((std::uint64_t{1} << bit) - 1);
}

/// Where pair k of block b keeps its held bit: word `inBlock` of the block's words in
/// PairSprings::held (from `blockWord`), bit `bit`.
struct HeldBit {
  std::size_t inBlock, bit;
};
inline HeldBit heldBit(const std::vector<std::uint32_t>& blockPair, std::size_t b, std::size_t k) {
  const std::size_t offset = k - blockPair[b];
  return {offset / 64, offset % 64};
}

/// Pair k's spring for k ascending over the calls (kNoSpring if it holds none): walks the
/// blocks, counting the holding pairs before k in k's block. The list must hold springs
/// (friction) laid out for its blocks.
class SpringReader {
 public:
  explicit SpringReader(const NeighbourList& list) : list_(list) {}
  ContactHistory at(std::size_t k) {
    const std::vector<std::uint32_t>& blockPair = list_.blockPair;
    if (k >= blockPair[block_ + 1]) {
      do ++block_;
      while (k >= blockPair[block_ + 1]);
      words_ = 0;
      before_ = 0;
    }
    const auto [w, bit] = heldBit(blockPair, block_, k);
    const std::uint64_t* held = list_.springs.held.data() + list_.blockWord[block_];
    for (; words_ < w; ++words_) before_ += static_cast<std::size_t>(std::popcount(held[words_]));
    if (((held[w] >> bit) & 1) == 0) return kNoSpring;
    const PairSprings& springs = list_.springs;
    const std::size_t index =
        before_ + static_cast<std::size_t>(std::popcount(bitsBelow(held[w], bit)));
    return expandRecord(springs.block[block_].data() + index * springs.slots, springs.optional);
  }

 private:
  const NeighbourList& list_;
  std::size_t block_ = 0;   ///< the block of the last pair asked for
  std::size_t words_ = 0;   ///< words of that block counted
  std::size_t before_ = 0;  ///< holding pairs in them
};

/// One spring per candidate pair (kNoSpring for those holding none): the checkpoint's layout.
/// Empty if the list holds no springs.
std::vector<ContactHistory> perPairSprings(const NeighbourList& list);

/// Lays out one spring per candidate pair (as perPairSprings gives them) into list.springs for
/// the list's blocks, as records of the slots the optional terms `optional` include; a pair
/// holds its spring if any of its numbers is nonzero. If the count
/// does not match the list's pairs (none at all: the frictionless path), `held` gets one word
/// per given spring and no block (the state checks report a mismatch on a frictional path).
void layOutPairSprings(NeighbourList& list, const std::vector<ContactHistory>& perPair,
                       unsigned optional);

/// Lays the list's springs out again as records for the optional terms `optional` (a scene whose
/// material switched one on or off): the slots of a term switched off are dropped, those of one
/// switched on start at zero.
void relayOutPairSprings(NeighbourList& list, unsigned optional);

/// The springs of the pairs of `old` that are also in the new list (rowStart, second, sorted,
/// with its blocks blockPair and blockWord), laid out for the new list, block by block on up to
/// `threads` threads (the same for any count). Frees old's block arrays as it passes them, so
/// that the old and the new springs are not held whole at once.
PairSprings carryPairSprings(NeighbourList& old, const std::vector<std::uint32_t>& rowStart,
                             const std::vector<std::uint32_t>& second,
                             const std::vector<std::uint32_t>& blockPair,
                             const std::vector<std::uint32_t>& blockWord, int threads = 1);

/// One block's springs rewritten in place by blockPairs, as records of S doubles: the stored
/// record of the pair holding the `read`-th one is at source + (read - sourceOffset) S; the
/// advanced records of the pairs that touch now are written to the array's front, `written` of
/// them so far.
template <std::size_t S>
struct SpringCursor {
  std::vector<double>* array = nullptr;
  const double* source = nullptr;
  std::size_t sourceOffset = 0, read = 0, written = 0, stored = 0;  // in records
  bool setAside = false;

  void start(std::vector<double>& springs) {
    array = &springs;
    source = springs.data();
    stored = springs.size() / S;
  }
  /// The record of the `index`-th held spring (index >= read).
  const double* at(std::size_t index) const { return source + (index - sourceOffset) * S; }
  /// Room for m new records after those written, once the records up to `read` are loaded.
  double* write(std::size_t m, std::vector<double>& aside) {
    if (!setAside && written + m > read && read < stored) {
      aside.assign(array->begin() + static_cast<std::ptrdiff_t>(read * S),
                   array->begin() + static_cast<std::ptrdiff_t>(stored * S));
      source = aside.data();
      sourceOffset = read;
      setAside = true;
    }
    if ((written + m) * S > array->size()) {
      // An eighth more, not double: the springs are the largest array of a frictional bed, and
      // between two rebuilds (which lay every array out afresh) a block gains a few contacts.
      if ((written + m) * S > array->capacity()) array->reserve(((written + m) * 9 / 8 + 4) * S);
      array->resize((written + m) * S);
      if (!setAside) source = array->data();  // what is left to read kept its place
    }
    double* out = array->data() + written * S;
    written += m;
    return out;
  }
  void finish() { array->resize(written * S); }
};

}  // namespace granular
