/// The switches of engine_studies.hpp: they set flags of the state that the step and the
/// setters read (simulation.cpp).
#include "granular/engine_studies.hpp"

#include <cmath>

#include "config_validation.hpp"
#include "simulation_state.hpp"

namespace granular {

/// The one way in from the studies' functions to the state (a friend of Simulation).
struct SimulationStudies {
  static SimulationState& state(Simulation& sim) { return *sim.state_; }
  static const SimulationState& state(const Simulation& sim) { return *sim.state_; }
};

namespace studies {

void setRebuildEveryStep(Simulation& sim, bool on) {
  SimulationStudies::state(sim).rebuildEveryStep = on;
}

void disableStepLimit(Simulation& sim, bool off) {
  SimulationStudies::state(sim).stepLimitDisabled = off;
}

StepControlCost stepControlCost(const Simulation& sim) {
  return SimulationStudies::state(sim).stepControlCost;
}

void scaleSpectrumEstimate(Simulation& sim, double factor) {
  requireConfig(std::isfinite(factor) && factor > 0.0, "the estimate's factor must be > 0");
  SimulationStudies::state(sim).estimateScale = factor;
}

}  // namespace studies
}  // namespace granular
