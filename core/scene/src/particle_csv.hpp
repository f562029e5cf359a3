#pragma once
/// Reading particles from a CSV file (private to the core; used by the scene loader, which checks
/// the file early, and by the scene builder, which places the particles).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "granular/vec3.hpp"

namespace granular {

/// One row of a particle CSV file.
struct CsvParticle {
  Vec3 position = Vec3::Zero();         ///< centre [m]
  double radius = 0.0;                  ///< [m]
  Vec3 velocity = Vec3::Zero();         ///< [m/s]; zero when the file has no vx,vy,vz
  Vec3 angularVelocity = Vec3::Zero();  ///< [rad/s]; zero when the file has no wx,wy,wz
  double mass = 0.0;                    ///< [kg]: a saved state's; 0 (from the density) else
  std::size_t line = 0;  ///< line of the row in the file (from 1); 0 if not from a file
};

/// A particle file as read: its rows and the hash of what they give.
struct ParticleCsv {
  std::vector<CsvParticle> rows;
  /// FNV-1a of the values the rows give, row by row (x, y, z, r, vx, vy, vz, wx, wy, wz, each
  /// by its bits; an absent column gives zeros): the same particles written with other line
  /// ends, columns in another order, "0.100" for "0.10" or comments added hash alike, so a run
  /// resumes across such an edit; any changed value, row or row order does not.
  std::uint64_t contentHash = 0;
};

/// Reads a header line naming the columns, then one row per particle. The header's names say
/// which field is which, in any order, each once: x, y, z and r (or radius) are required (a
/// saved state's: mass too), vx, vy, vz and wx, wy, wz are optional, each group all three or none
/// (m, m/s, rad/s, kg). Every row has
/// one field per column. Blank lines and lines starting with '#' are skipped. Throws ConfigError
/// naming the file and line: on the header (an unknown, duplicate or missing column, with the
/// known names), or on the first bad row (its row and column: not a number, NaN/inf,
/// radius <= 0, wrong field count), or when there is no row.
/// What a particle CSV file is: particles to place (the scene's own, masses from the density)
/// or a state granular saved (final_state.csv or a snapshot), which also gives the masses and
/// whose id, step and time_s columns are passed over.
enum class CsvKind { Particles, SavedState };

ParticleCsv readParticleCsv(const std::filesystem::path& path, CsvKind kind = CsvKind::Particles);

}  // namespace granular
