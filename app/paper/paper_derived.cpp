/// Numbers derived from a case (paper_derived.hpp).
#include "paper_derived.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "run_header.hpp"

namespace granular::app {

std::string caseLabel(const CaseOutcome& c) {
  std::string label = "μ = " + format("%g", c.friction);
  if (c.friction != c.reference->friction) {
    label += " (compared with the paper's μ = " + format("%g", c.reference->friction) + ")";
  }
  return label;
}

Derived derive(const CaseOutcome& c) {
  Derived d;
  const auto& samples = c.result.samples;
  const double endTime = samples.back().time;
  std::vector<BoxStress> window;
  for (std::size_t k = 1; k < samples.size(); ++k) {
    d.maxBalance = std::max(d.maxBalance, std::abs(samples[k].box.balanceError));
    if (samples[k].time > endTime - kEndWindow + 1e-9) window.push_back(samples[k].box);
  }
  d.end = window.empty() ? samples.back().box : meanBoxStress(window);
  d.lastBalance = samples.back().box.balanceError;
  const BoxStress& b = d.end;
  d.rel11 = (b.eq1(0, 0) - b.eq2.x()) / std::abs(b.eq2.x());
  d.rel22 = (b.eq1(1, 1) - b.eq2.y()) / std::abs(b.eq2.y());
  d.rel33 = (b.eq1(2, 2) - b.eq2.z()) / std::abs(b.eq2.z());
  d.cmTerm = b.sigma33CentreOfMassTerm / std::abs(b.eq2.z());
  d.remainder33 = d.rel33 - d.cmTerm;
  d.sideTerm = b.sigma33SideFrictionTerm / std::abs(b.eq2.z());
  d.residual33 = d.remainder33 - d.sideTerm;
  d.meanNormal = (b.eq1(0, 0) + b.eq1(1, 1) + b.eq1(2, 2)) / 3.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (i != j) d.maxShearRatio = std::max(d.maxShearRatio, std::abs(b.eq1(i, j)));
    }
  }
  d.maxShearRatio /= std::abs(d.meanNormal);
  d.sideShare = b.sideVerticalForce / b.weight;
  return d;
}

std::string pct(double x, const char* pattern) {
  return format(pattern, 100 * x);
}

}  // namespace granular::app
