#pragma once
/// The silo study's figures (silo_command.hpp): the wall pressure against height at rest and
/// during each discharge, the vertical stress with the fitted Janssen curve and the hydrostatic
/// line, and the discharged mass against time with Beverloo's rates.
#include <filesystem>
#include <vector>

#include "granular/render/image.hpp"
#include "granular/silo_study.hpp"

namespace granular::app {

/// p_h against height at rest (with its scatter) and during each discharge's steady window.
render::Image wallPressureFigure(const SiloStudyResult& result);
/// σ_v of Eq. (1) against height, Janssen's fitted curve and the hydrostatic line ρ_b g h.
render::Image verticalStressFigure(const SiloStudyResult& result);
/// The discharged mass against time per orifice, with Beverloo's fitted rate through each
/// steady window.
render::Image dischargeFigure(const SiloStudyResult& result);
/// Writes the three as wall_pressure.png, vertical_stress.png and discharge.png into `dir`;
/// the files.
std::vector<std::filesystem::path> drawSiloFigures(const SiloStudyResult& result,
                                                   const std::filesystem::path& dir);

}  // namespace granular::app
