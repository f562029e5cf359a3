#pragma once
/// Refusals of a configuration and of a scene's particles and walls (ConfigError), before any
/// state is built from them or changed by them.
#include <string>
#include <vector>

#include "granular/simulation.hpp"

namespace granular {

/// Throws ConfigError(what) unless `ok`.
void requireConfig(bool ok, const std::string& what);
/// A number as the refusals print it: 6 significant digits.
std::string shortNumber(double x);
/// The step's safety, accuracy floor and check interval.
void validateStepControl(const StepControl& c);
/// A wall's friction > 0 needs frictional particles (under `material`).
void requireWallFrictionWithin(const std::vector<Wall>& walls, const Material& material);
/// The smallest radius the run holds or will hold: the particles' and
/// SimulationConfig::smallestRadius [m].
double smallestRadius(const Particles& p, const SimulationConfig& config);
/// The configuration, the particles (sizes, masses, finite motion, no coincident centres) and
/// the walls of a new simulation.
void validateScene(const SimulationConfig& cfg, const Particles& p, const std::vector<Wall>& walls);

}  // namespace granular
