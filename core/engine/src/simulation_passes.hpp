#pragma once
/// Passes of the step (simulation.cpp) that the set-up and the setters also run.
#include "simulation_state.hpp"

namespace granular {

/// Rebuilds the neighbour list, carrying the springs, between the run's partition's hooks
/// (a run split by space redistributes its particles first).
void rebuildList(SimulationState& s);
/// The accelerations of the last force evaluation, as a run starts: a = F/m + g and, with
/// friction, dω/dt = T/I.
void startAccelerations(SimulationState& s);

}  // namespace granular
