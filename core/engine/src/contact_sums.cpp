/// The force pass's sums (contact_sums.hpp).
#include "contact_sums.hpp"

#include <algorithm>
#include <vector>

namespace granular {

namespace {

void addPowers(ContactPowers& sum, const ContactPowers& part) {
  for (std::size_t slot = 0; slot < kEnergySlots; ++slot) sum.energy[slot] += part.energy[slot];
  sum.wallPower += part.wallPower;
  sum.particleContacts += part.particleContacts;
  sum.wallContacts += part.wallContacts;
  sum.tangentialEvaluations += part.tangentialEvaluations;
}

}  // namespace

void finishBlockSums(SimulationState& s, std::size_t blocks, std::size_t walls) {
  const ContactScratch& out = s.contactScratch;
  ContactPowers powers;
  for (const ContactPowers& part : out.blockPowers) addPowers(powers, part);
  s.powers = powers;
  for (std::size_t w = 0; w < walls; ++w) {
    Vec3 reaction = Vec3::Zero();
    for (std::size_t b = 0; b < blocks; ++b) reaction += out.blockReaction[b * walls + w];
    s.walls[w].reaction = reaction;
  }
}

void finishExactSums(SimulationState& s, std::size_t walls) {
  ContactScratch& out = s.contactScratch;
  ExactPowers& total = out.partPowers[0];
  for (std::size_t t = 1; t < out.partPowers.size(); ++t) total.merge(out.partPowers[t]);
  if (s.ranks) total.mergeOverRanks(*s.ranks);
  ContactPowers powers;
  for (std::size_t slot = 0; slot < kEnergySlots; ++slot) {
    powers.energy[slot] = total.energy[slot].value();
  }
  powers.wallPower = total.wallPower.value();
  powers.particleContacts = total.particleContacts;
  powers.wallContacts = total.wallContacts;
  powers.tangentialEvaluations = total.tangentialEvaluations;
  s.powers = powers;
  for (std::size_t w = 0; w < walls; ++w) {
    s.walls[w].reaction = Vec3(total.reaction[3 * w].value(), total.reaction[3 * w + 1].value(),
                               total.reaction[3 * w + 2].value());
  }
}

void ExactPowers::clear(std::size_t walls) {
  for (ExactSum& e : energy) e = ExactSum();
  wallPower = ExactSum();
  reaction.assign(3 * walls, ExactSum());
  particleContacts = wallContacts = 0;
  tangentialEvaluations = 0;
}

void ExactPowers::mergeOverRanks(const Communicator& ranks) {
  std::vector<ExactSum> sums(energy, energy + kEnergySlots);
  sums.push_back(wallPower);
  sums.insert(sums.end(), reaction.begin(), reaction.end());
  std::vector<std::uint64_t> counts{particleContacts, wallContacts, tangentialEvaluations};
  ranks.mergeOverRanks(sums, counts);  // one reduction
  std::copy(sums.begin(), sums.begin() + kEnergySlots, energy);
  wallPower = sums[kEnergySlots];
  std::copy(sums.begin() + kEnergySlots + 1, sums.end(), reaction.begin());
  particleContacts = counts[0];
  wallContacts = counts[1];
  tangentialEvaluations = counts[2];
}

void ExactPowers::merge(const ExactPowers& other) {
  for (std::size_t slot = 0; slot < kEnergySlots; ++slot) energy[slot].merge(other.energy[slot]);
  wallPower.merge(other.wallPower);
  for (std::size_t k = 0; k < reaction.size(); ++k) reaction[k].merge(other.reaction[k]);
  particleContacts += other.particleContacts;
  wallContacts += other.wallContacts;
  tangentialEvaluations += other.tangentialEvaluations;
}

}  // namespace granular
