#pragma once
/// How the force pass sums its contacts' energy powers, contact counts and walls' reactions
/// (private to the engine; force_pass.cpp uses it): in double block by block (BlockSums, the same
/// bits for any thread count), or exactly (ExactSums with ParticleEnergies: the same bits however
/// the particles are split, among threads or processes; SimulationConfig::exactSums), and the
/// parts' sums finished into the state's powers and the walls' reactions.
#include <array>
#include <cstddef>
#include <cstdint>

#include "contact_law.hpp"
#include "simulation_state.hpp"

namespace granular {

/// The energy slots a build's pass sums: those of the terms it includes, but Slip accounts (a
/// residual, not summed).
template <bool kFriction, unsigned kOptional>
struct SummedSlots {
  static constexpr bool summed(std::size_t slot) {
    return kEnergySlotTable[slot].kind != EnergyKind::Slip &&
           kIncludedEnergySlots<kFriction, kOptional>[slot];
  }
  static constexpr std::size_t count = [] {
    std::size_t n = 0;
    for (std::size_t slot = 0; slot < kEnergySlots; ++slot) n += summed(slot) ? 1 : 0;
    return n;
  }();
  static constexpr std::array<std::size_t, count> slots = [] {
    std::array<std::size_t, count> list{};
    std::size_t n = 0;
    for (std::size_t slot = 0; slot < kEnergySlots; ++slot) {
      if (summed(slot)) list[n++] = slot;
    }
    return list;
  }();
};

/// Whether the chunk's entry e is a contact: in a build whose terms act beyond touch the chunk
/// also holds the bodies across a gap within their reach, which are not counted as contacts.
template <bool kFriction, unsigned kOptional>
bool touches(const ContactChunk& c, std::size_t e) {
  if constexpr (kReaches<kFriction, kOptional>) {
    return granular::touches(c.overlap[e]);
  } else {
    return true;
  }
}
/// How many of the chunk's first m entries are contacts (touches).
template <bool kFriction, unsigned kOptional>
std::size_t contactsIn(const ContactChunk& c, std::size_t m) {
  if constexpr (kReaches<kFriction, kOptional>) {
    std::size_t n = 0;
    for (std::size_t e = 0; e < m; ++e) n += touches<kFriction, kOptional>(c, e) ? 1 : 0;
    return n;
  } else {
    return m;
  }
}

/// Adds the powers of the chunk's m contacts to `powers` in contact order (so the sums are the
/// same for any thread count and any vector width).
template <bool kFriction, unsigned kOptional>
void addChunkPowers(const ContactChunk& c, std::size_t m, ContactPowers& powers) {
  // In locals: the rows might alias the totals for all the compiler knows, which would store
  // and reload every total at every contact.
  using Slots = SummedSlots<kFriction, kOptional>;
  double total[Slots::count];
  for (std::size_t k = 0; k < Slots::count; ++k) total[k] = powers.energy[Slots::slots[k]];
  for (std::size_t e = 0; e < m; ++e) {
    for (std::size_t k = 0; k < Slots::count; ++k) total[k] += c.energyRows[Slots::slots[k]][e];
  }
  for (std::size_t k = 0; k < Slots::count; ++k) powers.energy[Slots::slots[k]] = total[k];
  if constexpr (kFriction) powers.tangentialEvaluations += m;
}

/// The energies of one particle's pairs, summed in its contact order (ascending second
/// particle) across the chunks that hold them, and added exactly once it has none left: the
/// subtotal is the same bits whatever the chunks, blocks or threads (ExactPowers).
template <bool kFriction, unsigned kOptional>
class ParticleEnergies {
 public:
  /// The chunk's m pair contacts (by ascending first particle, continuing the last chunk's).
  /// Branch-free over the contacts: each slot's running sum restarts after a particle's last
  /// contact, and only those ends are added exactly, in a loop of their own.
  /// `owned`: which particles this process accounts for (null: all); the others' subtotals are
  /// dropped (their owners add them).
  void add(const ContactChunk& c, std::size_t m, ExactPowers& powers, const std::uint8_t* owned) {
    if (m == 0) return;
    if (open_ && c.first[0] != particle_) close(powers, owned);
    bool ends[kChunk];         // contact e is its particle's last (the chunk's last: not yet)
    std::uint32_t at[kChunk];  // the ends' contacts, in order
    std::size_t count = 0;
    for (std::size_t e = 0; e + 1 < m; ++e) {
      ends[e] = c.first[e + 1] != c.first[e];
      at[count] = static_cast<std::uint32_t>(e);
      count += ends[e] && (owned == nullptr || owned[c.first[e]]) ? 1 : 0;
    }
    ends[m - 1] = false;
    double total[kSummed][kChunk];
    double sum[kSummed];  // in locals, as addChunkPowers
    for (std::size_t k = 0; k < kSummed; ++k) sum[k] = sum_[k];
    for (std::size_t e = 0; e < m; ++e) {
      for (std::size_t k = 0; k < kSummed; ++k) {
        sum[k] += c.energyRows[kSlots[k]][e];
        total[k][e] = sum[k];
        sum[k] = ends[e] ? 0.0 : sum[k];
      }
    }
    for (std::size_t k = 0; k < kSummed; ++k) sum_[k] = sum[k];
    if (held_ + count > kHeld) flush(powers);
    for (std::size_t k = 0; k < kSummed; ++k) {
      for (std::size_t q = 0; q < count; ++q) subtotal_[k][held_ + q] = total[k][at[q]];
    }
    held_ += count;
    particle_ = c.first[m - 1];
    open_ = true;
  }
  /// The last particle's subtotal, at the end of a block (a particle's pairs never straddle
  /// two blocks).
  void close(ExactPowers& powers, const std::uint8_t* owned) {
    if (!open_) return;
    if (owned == nullptr || owned[particle_]) {
      if (held_ == kHeld) flush(powers);
      for (std::size_t k = 0; k < kSummed; ++k) subtotal_[k][held_] = sum_[k];
      ++held_;
    }
    for (double& sum : sum_) sum = 0.0;
    open_ = false;
  }
  /// A wall contact's energies (entry e of the chunk), held as one more subtotal.
  void holdWallContact(const ContactChunk& c, std::size_t e, ExactPowers& powers) {
    if (held_ == kHeld) flush(powers);
    for (std::size_t k = 0; k < kSummed; ++k) subtotal_[k][held_] = c.energyRows[kSlots[k]][e];
    ++held_;
  }
  /// Adds the subtotals held so far exactly, a slot's in one batch (ExactSum::addAll: far
  /// cheaper than one by one). At the end of a part, and whenever the holding is full.
  void flush(ExactPowers& powers) {
    for (std::size_t k = 0; k < kSummed; ++k) powers.energy[kSlots[k]].addAll(subtotal_[k], held_);
    held_ = 0;
  }

 private:
  static constexpr std::size_t kHeld = 512;  // subtotals held per slot before a flush (≥ kChunk)
  static constexpr std::size_t kSummed = SummedSlots<kFriction, kOptional>::count;
  static constexpr const std::array<std::size_t, kSummed>& kSlots =
      SummedSlots<kFriction, kOptional>::slots;

  std::uint32_t particle_ = 0;
  bool open_ = false;
  double sum_[kSummed] = {};
  std::size_t held_ = 0;
  double subtotal_[kSummed][kHeld];  ///< the closed particles' subtotals, not yet added
};

/// How a pass sums its powers and wall reactions (SimulationConfig::exactSums).
///
/// BlockSums: in double, contact by contact within a particle block, then block by block: the
/// same bits for any thread count (the blocks follow the lists, not the threads), the cheapest.
template <bool kFriction, unsigned kOptional>
struct BlockSums {
  ContactPowers powers;  // local to the block: kept in registers
  Vec3* reaction;        // the block's push on each wall [N]

  void pairs(const ContactChunk& c, std::size_t m) {
    addChunkPowers<kFriction, kOptional>(c, m, powers);
    powers.particleContacts += contactsIn<kFriction, kOptional>(c, m);
  }
  void wallContacts(const ContactChunk& c, std::size_t m, const std::uint32_t*) {
    addChunkPowers<kFriction, kOptional>(c, m, powers);
    powers.wallContacts += contactsIn<kFriction, kOptional>(c, m);
  }
  void wall(std::size_t w, const Vec3& force, double power, std::uint32_t) {
    powers.wallPower += power;
    reaction[w] -= force;
  }
};

/// ExactSums: each particle's pair energies in its contact order, each wall contact alone, all
/// added exactly (ExactPowers): the same bits however the particles are split, among threads,
/// blocks or processes. With ownership (`owned`, Simulation::setOwnership) only the contacts
/// this process accounts for: pairs whose first particle it owns, its particles' wall contacts.
template <bool kFriction, unsigned kOptional>
struct ExactSums {
  ExactSums(ExactPowers& sums, const std::uint8_t* ownedBy) : powers(sums), owned(ownedBy) {}
  ExactPowers& powers;
  const std::uint8_t* owned;                        // null: every particle
  ParticleEnergies<kFriction, kOptional> energies;  // a particle's pairs stay in one block

  void pairs(const ContactChunk& c, std::size_t m) {
    energies.add(c, m, powers, owned);
    std::size_t counted = m, contacts = contactsIn<kFriction, kOptional>(c, m);
    if (owned != nullptr) {
      counted = contacts = 0;
      for (std::size_t e = 0; e < m; ++e) {
        counted += owned[c.first[e]];
        contacts += owned[c.first[e]] && touches<kFriction, kOptional>(c, e) ? 1 : 0;
      }
    }
    powers.particleContacts += contacts;
    if constexpr (kFriction) powers.tangentialEvaluations += counted;
  }
  void wallContacts(const ContactChunk& c, std::size_t m, const std::uint32_t* who) {
    std::size_t counted = 0, contacts = 0;
    for (std::size_t e = 0; e < m; ++e) {
      if (owned != nullptr && !owned[who[e]]) continue;
      ++counted;
      contacts += touches<kFriction, kOptional>(c, e) ? 1 : 0;
      energies.holdWallContact(c, e, powers);
    }
    powers.wallContacts += contacts;
    if constexpr (kFriction) powers.tangentialEvaluations += counted;
  }
  void wall(std::size_t w, const Vec3& force, double power, std::uint32_t particle) {
    if (owned != nullptr && !owned[particle]) return;
    if (held == kHeld) flushPushes();
    pushes[held++] = {static_cast<std::uint32_t>(w), power, -force};
  }
  void endBlock() { energies.close(powers, owned); }
  void endPart() {
    energies.flush(powers);
    flushPushes();
  }

  /// The wall contacts' powers and pushes held, each sum's added exactly in one batch.
  void flushPushes() {
    double batch[kHeld];
    for (std::size_t q = 0; q < held; ++q) batch[q] = pushes[q].power;
    powers.wallPower.addAll(batch, held);
    for (std::size_t k = 0; k < powers.reaction.size(); ++k) {
      std::size_t terms = 0;
      for (std::size_t q = 0; q < held; ++q) {
        if (pushes[q].wall == k / 3) batch[terms++] = pushes[q].push[static_cast<int>(k % 3)];
      }
      powers.reaction[k].addAll(batch, terms);
    }
    held = 0;
  }

  static constexpr std::size_t kHeld = 256;  ///< wall contacts held before a flush
  struct Push {
    std::uint32_t wall;
    double power;  ///< [W]
    Vec3 push;     ///< on the wall [N]
  };
  std::size_t held = 0;
  Push pushes[kHeld];
};

/// The blocks' sums, in block order, into the state's powers and the walls' reactions (BlockSums).
void finishBlockSums(SimulationState& s, std::size_t blocks, std::size_t walls);
/// The parts' exact sums, merged (in any order: the same bits, over the ranks too) and rounded
/// once, into the state's powers and the walls' reactions (ExactSums).
void finishExactSums(SimulationState& s, std::size_t walls);

}  // namespace granular
