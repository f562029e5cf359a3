#pragma once
/// Entry points of the force pass (force_pass.cpp).
#include <functional>
#include <vector>

#include "simulation_state.hpp"

namespace granular {

/// A loop over the particles [begin, end) that returns nonzero on failure.
using ParticleRangeLoop = std::function<int(std::size_t begin, std::size_t end)>;

/// Contact forces, torques, wall reactions and contact powers at the current state; advances the
/// tangential springs by one time step `dt` (0 evaluates without advancing them). If `after` is
/// given, it runs once the forces are complete, on ranges covering every particle once (on the
/// pass's threads, each on particles whose forces it summed), and the OR of its results is
/// returned: the step's corrector runs there without a parallel region of its own.
int computeContactForces(SimulationState& s, double dt, const ParticleRangeLoop* after = nullptr);

/// Evaluates every contact at the current state without advancing any history and calls
/// `visit` from both sides of each pair and once per wall contact. If `netForce` is given it
/// receives Σ_j F_ij per particle (contact forces only) from the same evaluation.
void visitContacts(const SimulationState& s, const std::function<void(const ContactView&)>& visit,
                   std::vector<Vec3>* netForce);

}  // namespace granular
