#pragma once
/// One case of `granular paper` as it ran: how stage 1 went, the settled bed's contacts and the
/// compaction's result, what the report, the figures and the sensitivity study read.
#include <cstdint>
#include <map>
#include <string>

#include "granular/compaction.hpp"
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

}  // namespace granular::app
