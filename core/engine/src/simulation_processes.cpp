/// A Simulation shared among processes: the sums merged over ranks that own a share of the
/// particles (setOwnership), or the run split by space (splitAmong, domain_split.hpp); and
/// what it says of that sharing.
#include "config_validation.hpp"
#include "domain_split.hpp"
#include "energy_ledger.hpp"
#include "run_partition.hpp"
#include "simulation_state.hpp"

namespace granular {

void Simulation::setOwnership(std::vector<std::uint8_t> owned,
                              std::shared_ptr<const Communicator> ranks) {
  SimulationState& s = *state_;
  requireConfig(owned.size() == s.particles.size(),
                "ownership: " + std::to_string(owned.size()) + " flags for " +
                    std::to_string(s.particles.size()) + " particles");
  requireConfig(ranks != nullptr, "ownership: the ranks to merge over must be given");
  s.owned = std::move(owned);
  s.ranks = std::move(ranks);
  s.config.exactSums = true;
  if (s.steps == 0) startLedger(s);
}

void Simulation::splitAmong(std::shared_ptr<const DomainMap> domains,
                            std::shared_ptr<const Communicator> ranks) {
  SimulationState& s = *state_;
  splitState(s, std::move(domains), std::move(ranks));
  s.partition = &splitRun();
  if (s.steps == 0) startLedger(s);
}

Simulation Simulation::wholeState() const {
  const SimulationState& s = *state_;
  return Simulation(s.partition->wholeState(s));
}

std::uint64_t Simulation::globalId(std::size_t i) const {
  const SimulationState& s = *state_;
  return s.partition->globalId(s, i);
}

const Communicator* Simulation::ranks() const {
  const SimulationState& s = *state_;
  return s.partition->ranks(s);
}

bool Simulation::owns(std::size_t i) const {
  const SimulationState& s = *state_;
  return s.owned.empty() || s.owned.at(i) != 0;
}

}  // namespace granular
