#pragma once
/// The checks and warnings the loader makes once the whole scene is read (private to the core):
/// the default impact speed, the time step against the engine's stability rules, and the
/// overlaps no time step mends. They run here so that a message names the scene's key.
#include <string>
#include <vector>

#include "granular/scene.hpp"
#include "particles_reader.hpp"
#include "toml_table_reader.hpp"

namespace granular {

/// The largest approach speed a contact can have: two particles head-on, each at the largest
/// speed a particle can reach, which is its largest initial speed, plus the free-fall speed from
/// the highest particle top to the floor, plus twice the fastest wall's speed (a particle struck
/// by a wall leaves it at up to twice the wall's speed). A particle meets a wall at most at that
/// speed plus the wall's, which is less than twice it. The walls are the stages' moving walls
/// and `walls` (the [[walls]] array, with their turns).
double defaultImpactSpeed(const MotionBound& bound, const BoxSpec& box, const Vec3& gravity,
                          const std::vector<StageSpec>& stages, const std::vector<Wall>& walls);

/// The engine's stability rule (Simulation refuses the same step), checked with the density the
/// builder will use, so that the message can name the key. Also refuses a total_mass that would
/// give a density beyond the declared bound, and a damping that over-damps the stiffest contact.
void checkTimeStep(const TomlTableReader& root, const std::string& file, Scene& scene,
                   const MotionBound& bound);

/// Warnings of overlaps beyond a radius, which no time step mends (the contact is too soft for
/// the load): an impact at the expected approach speed, and the bed's weight on its floor.
void warnOfDeepOverlaps(const TomlTableReader& root, const std::string& file, Scene& scene,
                        const MotionBound& bound, bool impactSpeedGiven);

}  // namespace granular
