#pragma once
/// Reading particles from a CSV file (private to the core; used by the scene loader, which checks
/// the file early, and by the scene builder, which places the particles).
#include <cstddef>
#include <filesystem>
#include <vector>

#include "granular/vec3.hpp"

namespace granular {

/// One row of a particle CSV file.
struct CsvParticle {
  Vec3 position = Vec3::Zero();  ///< centre [m]
  double radius = 0.0;           ///< [m]
  Vec3 velocity = Vec3::Zero();  ///< [m/s]; zero when the row has only x,y,z,r
  std::size_t line = 0;          ///< line of the row in the file (from 1); 0 if not from a file
};

/// Reads a header line, then rows x,y,z,r[,vx,vy,vz] (m, m/s). Blank lines and lines starting
/// with '#' are skipped. Throws ConfigError naming the file, line, row and column of the first
/// bad field (not a number, NaN/inf, radius <= 0, wrong field count) or when there is no row.
std::vector<CsvParticle> readParticleCsv(const std::filesystem::path& path);

}  // namespace granular
