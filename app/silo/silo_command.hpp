#pragma once
/// `granular silo`: fills the study's silo, measures its wall pressures and vertical stresses at
/// rest against Janssen's, discharges it through each orifice against Beverloo's law, and writes
/// report.md, the measured tables as CSV and the figures (docs/guide.md).
#include <cstdint>
#include <filesystem>

namespace granular::app {

struct SiloOptions {
  std::filesystem::path outDir = "runs/silo";  ///< output folder
  std::filesystem::path scene;                 ///< the silo (silo-study.toml)
  /// Particles poured in, instead of the scene's 10000: a quick look (fewer) or a taller bed
  /// (more; the cylinder must hold it) [-]; 0 keeps the scene's.
  std::uint64_t particles = 0;
  double dischargeTime = 1.0;  ///< each orifice's discharge [s]
  bool quiet = false;          ///< no progress lines
};

/// Exit status as for `granular run`.
int siloCommand(const SiloOptions& options);

}  // namespace granular::app
