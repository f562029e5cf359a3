#pragma once
/// The silo study's figures (silo_command.hpp): the wall pressure against height at rest and
/// during each discharge, the vertical stress with the fitted Janssen curve and the hydrostatic
/// line, and the discharged mass against time with Beverloo's rates.
#include <filesystem>
#include <vector>

#include "granular/silo_study.hpp"

namespace granular::app {

/// Writes wall_pressure.png, vertical_stress.png and discharge.png into `dir`; the files.
std::vector<std::filesystem::path> drawSiloFigures(const SiloStudyResult& result, double gravity,
                                                   const std::filesystem::path& dir);

}  // namespace granular::app
