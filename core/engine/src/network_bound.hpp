#pragma once
/// The network's frequency bound on the engine's state (network_frequency.cpp), for the step
/// control inside the step (simulation.cpp).
#include <functional>

#include "granular/network_frequency.hpp"
#include "granular/network_step.hpp"

namespace granular {

struct SimulationState;
/// With `enough`, the sweeps stop as soon as it holds for the bound so far (every sweep's bound
/// is an upper bound: stopping early only gives away tightness that was not needed).
NetworkFrequency networkFrequencyBound(const SimulationState& s, int sweeps, double lookahead,
                                       const std::function<bool(const NetworkFrequency&)>& enough);
NetworkStep networkStableStep(const SimulationState& s, double lookahead);
/// The step a bound allows `integrator`: its interval over the bound's damping ratios, over
/// ω_max (+∞ with no contacts).
double networkStepOf(Integrator integrator, const NetworkFrequency& f);

}  // namespace granular
