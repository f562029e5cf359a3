#pragma once
/// report.md of `granular paper`: our numbers beside the paper's, with a sentence on each
/// difference and the targets met or not.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "granular/compaction.hpp"
#include "paper_figures.hpp"
#include "paper_reference.hpp"

namespace granular::app {

/// How stage 1 went (kept in settle_summary.txt, so a run restored from the checkpoint can still
/// report it).
struct SettleSummary {
  std::string endedBy;  ///< "kinetic energy below threshold" or "max time"
  double duration = 0;  ///< simulated [s]
  double steps = 0;
  double wallSeconds = 0;   ///< wall-clock of the run that settled it [s]
  double finalKinetic = 0;  ///< [J]
  double threshold = 0;     ///< kinetic energy threshold [J]
  double sustain = 0;       ///< [s]
  double cap = 0;           ///< max time [s]
};

/// A settled bed's contacts: each particle pair once, each particle-wall contact once (R_ij = R_i
/// at a wall), for the constant law's k_t = (8/3) G/(2−ν) √(R̄ h̄).
struct BedContacts {
  std::size_t count = 0;
  double meanRadius = 0;   ///< R̄, the mean reduced radius R_ij [m]
  double meanOverlap = 0;  ///< h̄ [m]
  /// Mindlin's k_t = (8/3) G/(2−ν) √(R_i h) averaged over the contacts with the side walls
  /// (x-, x+, y-, y+) [N/m]
  double sideWallMindlin = 0;
};

struct CaseOutcome {
  const PaperReference* reference = nullptr;
  std::string folder;            ///< under --out: "mu0", "mu03", "mu03_constant_kt"
  double constantStiffness = 0;  ///< k_t of the constant tangential law; 0: Mindlin's [N/m]
  std::uint64_t seed = 0;        ///< the grid generator's seed (0: not a grid)
  BedContacts bed;               ///< of the settled bed
  CompactionResult result;
  SettleSummary settle;
  double boxSide = 0;          ///< [m]
  double density = 0;          ///< density used [kg/m³]
  double friction = 0;         ///< μ of the scene run (the paper's case may differ: --scenes)
  double timeStep = 0;         ///< [s]
  double contactDuration = 0;  ///< [s]
  std::string integrator;
  double wallSeconds = 0;                ///< this invocation, both stages or stage 2 only [s]
  std::map<std::string, double> fields;  ///< stress-field summary (paper_fields.hpp)
};

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

/// The report; `figures` are embedded in a Figures section (none: a note that they are missing).
std::string paperReport(const std::vector<CaseOutcome>& cases,
                        const SensitivityOutcome& sensitivity,
                        const std::vector<FigureFile>& figures, double totalWallSeconds);

}  // namespace granular::app
