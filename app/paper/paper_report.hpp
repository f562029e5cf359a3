#pragma once
/// report.md of `granular paper`: our numbers beside the paper's, with a sentence on each
/// difference and the targets met or not.
#include <map>
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

struct CaseOutcome {
  const PaperReference* reference = nullptr;
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

/// The report; `figures` are embedded in a Figures section (none: a note that they are missing).
std::string paperReport(const std::vector<CaseOutcome>& cases,
                        const std::vector<FigureFile>& figures, double totalWallSeconds);

}  // namespace granular::app
