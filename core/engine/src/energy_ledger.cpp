/// The energy ledger (docs/physics.md): the sums over the particles, each contact account's
/// value since the start, and the balance a Simulation reports.
#include "energy_ledger.hpp"

#include <omp.h>

#include <algorithm>
#include <string_view>
#include <vector>

#include "force_pass.hpp"

namespace granular {

ParticleSums particleSums(const SimulationState& s) {
  const Particles& p = s.particles;
  const bool all = s.owned.empty();
  // Runs of particles summed by the threads, then merged: exact sums, so the same bits however
  // the particles are split (a stage that ends on its kinetic energy asks every step).
  const std::size_t n = p.size();
  const std::size_t teams =
      std::size_t(passThreads(s) > 0 ? passThreads(s) : omp_get_max_threads());
  std::vector<ParticleSums> parts(n >= 1024 ? teams : 1);
#pragma omp parallel num_threads(int(parts.size()))
  {
    const std::size_t t = std::size_t(omp_get_thread_num());
    const std::size_t used = std::size_t(omp_get_num_threads());
    ParticleSums& part = parts[t];
    // The terms in batches, each added with the exact sum's batched add: the same accumulators
    // as adding them one by one, at a fraction of the cost.
    constexpr std::size_t kBatch = 256;
    double kinetic[kBatch], potential[kBatch], spin[kBatch];
    std::size_t held = 0;
    auto flush = [&] {
      part.translational.addAll(kinetic, held);
      part.potential.addAll(potential, held);
      if (s.frictional) part.rotational.addAll(spin, held);
      held = 0;
    };
    for (std::size_t i = n * t / used; i < n * (t + 1) / used; ++i) {
      if (!all && !s.owned[i]) continue;
      kinetic[held] = 0.5 * p.mass[i] * p.velocity[i].squaredNorm();
      potential[held] = p.mass[i] * s.config.gravity.dot(p.position[i]);
      if (s.frictional) spin[held] = 0.5 * p.inertia(i) * p.angularVelocity[i].squaredNorm();
      if (++held == kBatch) flush();
    }
    flush();
  }
  ParticleSums sums = parts[0];
  for (std::size_t t = 1; t < parts.size(); ++t) {
    sums.translational.merge(parts[t].translational);
    sums.rotational.merge(parts[t].rotational);
    sums.potential.merge(parts[t].potential);
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

EnergyBalance Simulation::energy() const {
  return energyBalance(*state_);
}

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
