#pragma once
/// Checks of a state's integrity, shared by the step (non-finite values) and the checkpoint
/// reader (everything a corrupted or hand-made file could get wrong).
#include <optional>
#include <string>

#include "simulation_state.hpp"

namespace granular {

/// The first particle with a field of Particles (particle_fields.hpp: position, velocity,
/// angular velocity, radius, mass) not finite, described as "particle 12: velocity (nan, 0, 0)
/// m/s is not finite"; nullopt when all are finite.
/// With `owned` (a run split by space) only the particles owned here (owned[i] != 0) are looked
/// at, and each is named by its global id, ids[i].
std::optional<std::string> firstNonFiniteParticle(const Particles& particles,
                                                  const std::vector<std::uint8_t>* owned = nullptr,
                                                  const std::vector<std::uint64_t>* ids = nullptr);

/// Refuses (CheckpointError naming `file`) a restored state the engine could not step safely:
/// arrays of different lengths, contact indices out of range or unsorted, unknown enumeration
/// values, non-finite or out-of-range numbers. Everything the step indexes with is checked here,
/// so that no file, however corrupted, makes the engine read out of bounds.
void validateRestoredState(const SimulationState& state, const std::string& file);

}  // namespace granular
