#pragma once
/// ParaView snapshots of a run through VTK's XML writers: the particles, the contact network
/// and the walls as poly data (.vtp), and .pvd collections that list them over time.
///
/// Array names carry their units. Particles (points): radius_m, velocity_m_s,
/// angular_velocity_rad_s, force_sum_N (Σ_j |F_ij|), stress_Pa (9 components, row-major:
/// Eq. (1) over the particle's own volume, granular::particleStresses). Contacts (one line
/// cell each: centre to centre for a particle pair, counted once; centre to the contact point
/// for a wall): normal_force_N, tangential_force_N (vectors, on the first particle),
/// normal_force_magnitude_N, wall (-1 for a pair, else the wall's index). Walls (an infinite
/// plane: one quad spanning the box; a rectangle: its quad; a frustum: 48 facets around its
/// axis; a mesh: its triangles), per cell: reaction_N (the particles' push on the whole wall),
/// velocity_m_s, wall, and the cell's own load (wall_cell_loads.hpp): force_N (the particles'
/// push on the cell), pressure_Pa and shear_Pa (its normal and tangential parts over the
/// cell's area, the normal part's magnitude: shells are touched from either side), shape (the
/// wall's granular::WallShape: 0 an infinite plane, 1 a rectangle, 2 a frustum, that is a
/// cylinder, cone, disc or annulus, 3 a mesh). Field data of the walls' file: box_min_m and
/// box_max_m (the scene's box, one tuple of 3 each), wall_name (one string a wall, indexed by
/// `wall`).
#include <filesystem>
#include <vector>

#include "granular/simulation.hpp"

namespace granular::app {

void writeParticlesVtp(const std::filesystem::path& file, const Simulation& sim);
void writeContactsVtp(const std::filesystem::path& file, const Simulation& sim);
/// `boxMin`, `boxMax`: the extent each wall's quad spans along its plane [m].
void writeWallsVtp(const std::filesystem::path& file, const Simulation& sim, const Vec3& boxMin,
                   const Vec3& boxMax);

struct PvdEntry {
  double time = 0;             ///< [s]
  std::filesystem::path file;  ///< relative to the .pvd's folder
};
/// Writes a .pvd collection (atomically: a reader never sees half of it).
void writePvd(const std::filesystem::path& file, const std::vector<PvdEntry>& entries);

}  // namespace granular::app
