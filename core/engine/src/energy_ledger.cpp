/// The energy ledger (docs/physics.md): the sums over the particles, each contact account's
/// value since the start, and the balance a Simulation reports.
#include "energy_ledger.hpp"

#include <string_view>

#include "force_pass.hpp"

namespace granular {

ParticleSums particleSums(const SimulationState& s) {
  const Particles& p = s.particles;
  const bool all = s.owned.empty();
  ParticleSums sums;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!all && !s.owned[i]) continue;
    sums.translational.add(0.5 * p.mass[i] * p.velocity[i].squaredNorm());
    sums.potential.add(p.mass[i] * s.config.gravity.dot(p.position[i]));
    if (s.frictional) sums.rotational.add(0.5 * p.inertia(i) * p.angularVelocity[i].squaredNorm());
  }
  if (s.ranks) {
    std::vector<ExactSum> merged{sums.translational, sums.rotational, sums.potential};
    s.ranks->mergeOverRanks(merged);
    sums = {merged[0], merged[1], merged[2]};
  }
  return sums;
}

void startLedger(SimulationState& s) {
  computeContactForces(s, 0.0);
  s.energy.initialPotential = particleSums(s).potential.value();
  for (std::size_t slot = 0; slot < kEnergySlots; ++slot) {
    s.energy.initialStored[slot] = s.powers.energy[slot];
  }
}

void addStepToLedger(SimulationState& s, const ContactPowers& before, double dt) {
  const ContactPowers& now = s.powers;
  EnergyAccumulators& e = s.energy;
  const double half = 0.5 * dt;
  for (std::size_t slot = 0; slot < kEnergySlots; ++slot) {
    switch (kEnergySlotTable[slot].kind) {
      case EnergyKind::Dissipated:
      case EnergyKind::Work:
        e.account[slot] += half * (before.energy[slot] + now.energy[slot]);
        break;
      case EnergyKind::Supplied:
        e.account[slot] += now.energy[slot];
        break;
      case EnergyKind::Stored:
      case EnergyKind::Slip:
        break;
    }
  }
  e.wallWork += half * (before.wallPower + now.wallPower);
}

double Simulation::kineticEnergy() const {
  ParticleSums sums = particleSums(*state_);
  sums.translational.merge(sums.rotational);
  return sums.translational.value();
}

namespace {

/// The Slip of a group: −Work − (Stored − its start) − Dissipated + Supplied, over the group's
/// accounts, in that order.
double slip(const SimulationState& s, std::string_view group) {
  const EnergyAccumulators& e = s.energy;
  double value = 0.0;
  for (EnergyKind kind :
       {EnergyKind::Work, EnergyKind::Stored, EnergyKind::Dissipated, EnergyKind::Supplied}) {
    for (const EnergyAccountSpec& a : energyAccounts()) {
      if (a.account.group != group || a.account.kind != kind) continue;
      switch (kind) {
        case EnergyKind::Work:
          value -= e.account[a.slot];
          break;
        case EnergyKind::Stored:
          value -= s.powers.energy[a.slot] - e.initialStored[a.slot];
          break;
        case EnergyKind::Dissipated:
          value -= e.account[a.slot];
          break;
        case EnergyKind::Supplied:
          value += e.account[a.slot];
          break;
        case EnergyKind::Slip:
          break;
      }
    }
  }
  return value;
}

}  // namespace

EnergyBalance Simulation::energy() const { return energyBalance(*state_); }

EnergyBalance energyBalance(const SimulationState& s) {
  EnergyBalance b;
  const ParticleSums sums = particleSums(s);
  b.kineticTranslational = sums.translational.value();
  b.kineticRotational = sums.rotational.value();
  const double potential = sums.potential.value();
  const EnergyAccumulators& e = s.energy;
  // Each column's value; a Slip account is what its group's forces took from the particles and
  // neither its springs nor its dashpots hold: −W − ΔE_s − D + S.
  for (const EnergyAccountSpec& column : energyColumns(s.config.material)) {
    const std::size_t slot = column.slot;
    double value = 0.0;
    switch (column.account.kind) {
      case EnergyKind::Stored:
        value = s.powers.energy[slot];
        break;
      case EnergyKind::Dissipated:
      case EnergyKind::Supplied:
      case EnergyKind::Work:
        value = e.account[slot];
        break;
      case EnergyKind::Slip:
        value = slip(s, column.account.group);
        break;
    }
    b.contact.push_back({column.account.column, column.account.kind, value});
  }
  b.gravityWork = potential - e.initialPotential;
  b.wallWork = e.wallWork;
  b.exchanged = e.exchanged;
  return b;
}

}  // namespace granular
