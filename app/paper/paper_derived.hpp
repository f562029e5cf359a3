#pragma once
/// Numbers the report and the sensitivity study derive from a case's samples: the end-of-stage-2
/// mean, the balance errors, the σ33 differences split, the side walls' share.
#include <string>

#include "paper_case.hpp"

namespace granular::app {

/// The window at the end of stage 2 over which the t = 1 s values are averaged [s]: ten contact
/// durations, so that the fluctuation of the bed's momentum (the balance error is exactly
/// M·a_cm/W) averages out, as the paper's "averaged reaction forces" ask.
constexpr double kEndWindow = 0.1;

/// What the report states about the end of stage 2.
struct Derived {
  BoxStress end;          ///< mean over the last kEndWindow of stage 2
  double maxBalance = 0;  ///< max |balance error| over stage 2 after its first interval
  double rel11 = 0, rel22 = 0, rel33 = 0;  ///< (Eq. 1 - Eq. 2) / |Eq. 2|
  double cmTerm = 0, remainder33 = 0;      ///< σ33 difference split, relative to |Eq. 2|
  double sideTerm = 0, residual33 = 0;     ///< the remainder split further (frictional walls)
  double lastBalance = 0;                  ///< balance error over the last output interval alone
  double maxShearRatio = 0;                ///< max |σ_ij|, i != j, over the mean |σ_ii| (Eq. 1)
  double sideShare = 0;                    ///< side-wall vertical support / weight
  double meanNormal = 0;                   ///< mean of the diagonal of Eq. (1) [Pa]
};

Derived derive(const CaseOutcome& c);

/// "μ = 0.3"; a case run with another friction than the paper's case it is compared with (a
/// scene from --scenes) says so.
std::string caseLabel(const CaseOutcome& c);

/// A fraction as a percentage ("+1.25 %").
std::string pct(double x, const char* pattern = "%+.2f %%");

}  // namespace granular::app
