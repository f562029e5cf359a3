#pragma once
/// The contacts of a state as a CSV table, for measuring forces without decoding ParaView files.
///
/// One row per contact with overlap h > 0 (a particle pair once, particle < other_particle; a
/// particle-wall contact once), at the state written: particle, other_particle (empty for a
/// wall), wall (the wall's name; empty for a pair), point_x_m, point_y_m, point_z_m (the contact
/// point, the middle of the overlap on the line of centres), overlap_m, normal_x, normal_y,
/// normal_z (unit normal from particle towards the other body), normal_force_N (the normal
/// push, −F·n: >= 0, and 0 when the no-pull clamp holds a closing contact at zero force),
/// normal_force_x_N, _y_N, _z_N and tangential_force_x_N, _y_N, _z_N (the force on particle,
/// split along n and across it), tangential_force_N (its magnitude), step and time_s (the state's
/// step and simulation clock, the same on every row).
#include <filesystem>

#include "granular/simulation.hpp"

namespace granular::app {

/// Writes the table to a temporary file renamed into place. IoError if it cannot be written.
void writeContactCsv(const std::filesystem::path& path, const Simulation& sim);

}  // namespace granular::app
