#pragma once
/// The energy ledger: each contact account's value since the start (EnergyAccumulators) and
/// the sums over the particles (particleSums, simulation_state.hpp).
#include "simulation_state.hpp"

namespace granular {

/// The ledger's starting values: the stored energies of a force evaluation at the current
/// state (which advances nothing, and leaves the forces of that state) and the potential
/// energy.
void startLedger(SimulationState& s);
/// One step of `dt` [s] into the ledger, from the powers of the last force evaluation and of
/// the one before it (`before`): Dissipated and Work by the trapezoid rule, Supplied summed.
void addStepToLedger(SimulationState& s, const ContactPowers& before, double dt);
/// The balance of `s` (Simulation::energy; collective in a run shared among processes).
EnergyBalance energyBalance(const SimulationState& s);

}  // namespace granular
