#pragma once
/// The settled silo seen in section, for `granular silo`'s report: a cut-away view of the bed's
/// far half coloured by each particle's Σ|F_ij| (the force chains on the cut face), and the
/// vertical stress on the midsection with the trajectories of the major principal stress.
#include <filesystem>
#include <vector>

#include "granular/render/image.hpp"
#include "granular/simulation.hpp"
#include "silo_sections.hpp"

namespace granular::app {

/// The figures' width at 150 dpi [px]; a narrower figure is the same at a lower resolution.
inline constexpr int kSectionFigureWidth = 1000;

/// The particles behind the cut y = 0 (particlesBehindCut) seen from −y, nearly orthographically,
/// coloured by Σ_j |F_ij| over all their contacts, walls included [N], from 0 to the drawn
/// particles' 99th percentile (the few most loaded particles would otherwise leave the chains
/// in the dark half of the scale); the cylinder's back wall tinted, its sides and the floor
/// drawn, axes in metres true to the cut face. Opens its own OpenGL context
/// (render::RenderError without one).
render::Image cutawayFigure(const Simulation& settled, const SiloSectionGeometry& geometry,
                            int width = kSectionFigureWidth);

/// −σ33, the coarse-grained vertical stress with compression positive, on the midsection y = 0
/// as filled contours, with σ1 trajectories over it (midsectionStress), axes in metres.
render::Image midsectionStressFigure(const Simulation& settled, const SiloSectionGeometry& geometry,
                                     int width = kSectionFigureWidth);

/// Writes both as cutaway.png and midsection_stress.png into `dir` (which must exist); the
/// files.
std::vector<std::filesystem::path> writeSiloSectionFigures(const Simulation& settled,
                                                           const SiloSectionGeometry& geometry,
                                                           const std::filesystem::path& dir);

}  // namespace granular::app
