#pragma once
/// The sensitivity study of `granular paper`: the μ = 0.3 case with a constant tangential
/// stiffness beside the paper's Mindlin law, and with --sensitivity both laws over several seeds;
/// its numbers, its CSV and its section of report.md.
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "paper_case.hpp"

namespace granular::app {

/// The sensitivity study: the paper's μ = 0.3 case again with a constant k_t, the Mindlin value
/// at the settled Mindlin bed's R̄ and h̄; with --sensitivity, both laws from more seeds.
struct SensitivityOutcome {
  std::string skipped;                  ///< why the study was not run (empty: it was)
  double stiffness = 0;                 ///< the constant k_t [N/m]
  double coefficient = 0;               ///< (8/3) G/(2−ν) [Pa]
  BedContacts bed;                      ///< of the Mindlin bed k_t was taken from
  std::optional<CaseOutcome> constant;  ///< the paper's seed with the constant law
  /// --sensitivity: per seed (the paper's first, from the cases), Mindlin's and the constant
  /// law's runs; empty without it.
  std::vector<CaseOutcome> mindlinSeeds, constantSeeds;
  int defaultSeeds = 0;    ///< what --sensitivity runs without --seeds
  double seedSeconds = 0;  ///< wall-clock of the runs beyond the paper's seed [s]
};

/// What the sensitivity study compares, for one run of the μ = 0.3 case.
struct LawNumbers {
  double shareSettled = 0;   ///< side walls' upward reaction / weight, end of settling [-]
  double shareEnd = 0;       ///< the same at t = 1 s (the report's end window) [-]
  double convexity = 0;      ///< |σ33| centre / walls − 1 at mid-depth on Fig. 9's map [-]
  double tiltWalls = 0;      ///< σ1's tilt from the vertical near the walls, mid-depth [°]
  double wallFriction = 0;   ///< side walls' mobilised friction τ_w/σ_h, end of settling [-]
  double settledHeight = 0;  ///< [m]
  double sigma[3] = {};      ///< σ11, σ22, σ33 of Eq. (1) at t = 1 s [Pa]
};
LawNumbers lawNumbers(const CaseOutcome& c);

/// sensitivity/seeds.csv: one row per bed of --sensitivity (seed, law, k_t, the LawNumbers).
std::string sensitivityCsv(const SensitivityOutcome& s);

/// The report's "Sensitivity" section.
void sensitivitySection(std::ostringstream& out, const std::vector<CaseOutcome>& cases,
                        const SensitivityOutcome& s);

}  // namespace granular::app
