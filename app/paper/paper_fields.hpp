#pragma once
/// The stress fields of the settled bed (end of stage 1), the paper's Section 3.3 last part and
/// beyond it: Eq. (1) over representative spheres, spline-interpolated onto the midsection
/// (Fig. 9), σ1 trajectories (Fig. 10), coarse-grained fields with their momentum-balance check,
/// and the vertical profile against Janssen's law (frictional) or hydrostatics (frictionless).
#include <filesystem>
#include <map>
#include <string>

#include "granular/simulation.hpp"

namespace granular::app {

/// Writes DIR/fields/: midsection.csv (σ33 of both methods on the y = L/2 plane),
/// trajectories.csv, profiles.csv, wall_stress.csv, representative.vti, midsection.vti,
/// coarse_grained.vti, trajectories.vtp and summary.txt (the numbers the report states).
/// Returns the summary's key-value pairs.
std::map<std::string, double> writeStressFields(const Simulation& settled,
                                                const std::filesystem::path& caseDir);

}  // namespace granular::app
