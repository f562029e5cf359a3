/// Steady discharge rate from a mass-time series (discharge_rate.hpp).
#include "granular/discharge_rate.hpp"

#include <stdexcept>
#include <string>

#include "input_checks.hpp"
#include "line_fit.hpp"

namespace granular {
namespace {

namespace ic = input_checks;

void checkSeries(const std::vector<double>& time, const std::vector<double>& mass,
                 const std::string& who) {
  ic::requireSameLength(time, mass, who + ": times and masses");
  ic::requireFiniteSeries(time, who + ": time");
  ic::requireFiniteSeries(mass, who + ": mass");
  for (std::size_t k = 1; k < time.size(); ++k) {
    if (!(time[k] > time[k - 1])) {
      throw std::invalid_argument(who + ": times must be ascending: time[" + std::to_string(k - 1) +
                                  "] = " + formatNumber(time[k - 1]) + " s, time[" +
                                  std::to_string(k) + "] = " + formatNumber(time[k]) + " s");
    }
  }
}

/// The line through the samples `inWindow` selects.
template <class Select>
SteadyRate fitWindow(const std::vector<double>& time, const std::vector<double>& mass,
                     const std::string& who, Select inWindow) {
  std::vector<double> t, m;
  for (std::size_t k = 0; k < time.size(); ++k) {
    if (!inWindow(k)) continue;
    t.push_back(time[k]);
    m.push_back(mass[k]);
  }
  ic::requireAtLeast(t.size(), 3, who + ": samples in the window",
                     "two fix a line; a third is the least for its standard error");
  const LineFit line = fitLine(t, m);
  SteadyRate rate;
  rate.rate = line.slope;
  rate.standardError = line.slopeStandardError;
  rate.intercept = line.intercept;
  rate.t0 = t.front();
  rate.t1 = t.back();
  rate.samples = t.size();
  return rate;
}

}  // namespace

SteadyRate steadyDischargeRate(const std::vector<double>& time, const std::vector<double>& mass,
                               double fromFraction, double toFraction,
                               std::optional<double> totalMass) {
  const std::string who = "steadyDischargeRate";
  checkSeries(time, mass, who);
  ic::requireNonNegative(fromFraction, who + ": fromFraction");
  ic::requireFinite(toFraction, who + ": toFraction");
  if (!(fromFraction < toFraction) || toFraction > 1) {
    throw std::invalid_argument(who + ": needs 0 <= fromFraction < toFraction <= 1 (got " +
                                formatNumber(fromFraction) + " and " + formatNumber(toFraction) +
                                ")");
  }
  if (mass.empty()) throw std::invalid_argument(who + ": no samples");
  const double total = totalMass ? *totalMass : mass.back();
  ic::requirePositive(total, who + (totalMass ? ": total mass" : ": last sample's mass"));
  const double lo = fromFraction * total, hi = toFraction * total;
  return fitWindow(time, mass, who, [&](std::size_t k) { return mass[k] >= lo && mass[k] <= hi; });
}

SteadyRate steadyDischargeRateInWindow(const std::vector<double>& time,
                                       const std::vector<double>& mass, double t0, double t1) {
  const std::string who = "steadyDischargeRateInWindow";
  checkSeries(time, mass, who);
  ic::requireFinite(t0, who + ": t0");
  ic::requireFinite(t1, who + ": t1");
  if (!(t0 < t1)) {
    throw std::invalid_argument(who + ": needs t0 < t1 (got " + formatNumber(t0) + " s and " +
                                formatNumber(t1) + " s)");
  }
  return fitWindow(time, mass, who, [&](std::size_t k) { return time[k] >= t0 && time[k] <= t1; });
}

}  // namespace granular
