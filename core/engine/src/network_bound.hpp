#pragma once
/// The network's frequency bound on the engine's state (network_frequency.cpp), for the step
/// control inside the step (simulation.cpp).
#include "granular/network_frequency.hpp"
#include "granular/network_step.hpp"

namespace granular {

struct SimulationState;
NetworkFrequency networkFrequencyBound(const SimulationState& s, int sweeps, double lookahead);
NetworkStep networkStableStep(const SimulationState& s, double lookahead);

}  // namespace granular
