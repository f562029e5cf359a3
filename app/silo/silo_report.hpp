#pragma once
/// The silo study's report.md and its tables (silo_command.hpp): our numbers beside Janssen's
/// and Beverloo's, and each target met or not.
#include <filesystem>
#include <string>
#include <vector>

#include "granular/silo_study.hpp"

namespace granular::app {

/// The targets the report checks.
struct SiloTargets {
  double janssenRms = 0.05;         ///< σ_v about the fitted Janssen curve, relative RMS [-]
  double lambdaAgreement = 0.15;    ///< fitted μ_w K against the measured one, relative [-]
  double cMin = 0.55, cMax = 0.65;  ///< Beverloo's C, the literature's range [-]
};

/// report.md's text for `result` (run from `scene`, in `seconds` of wall clock), listing the
/// `figures` written beside it (file names).
std::string siloReport(const SiloStudyResult& result, const std::string& scene, double seconds,
                       const std::vector<std::string>& figures, const SiloTargets& targets = {});
/// levels.csv (one row a level at rest) and discharge.csv (one row a sample of each orifice).
void writeSiloTables(const SiloStudyResult& result, const std::filesystem::path& dir);

}  // namespace granular::app
