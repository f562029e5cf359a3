#pragma once
/// report.md of `granular paper`: our numbers beside the paper's, with a sentence on each
/// difference and the targets met or not.
#include <string>
#include <vector>

#include "paper_case.hpp"
#include "paper_figures.hpp"
#include "paper_sensitivity.hpp"

namespace granular::app {

/// The report; `figures` are embedded in a Figures section (none: a note that they are missing).
std::string paperReport(const std::vector<CaseOutcome>& cases,
                        const SensitivityOutcome& sensitivity,
                        const std::vector<FigureFile>& figures, double totalWallSeconds);

}  // namespace granular::app
