#pragma once
/// The steady mass flow rate of a silo's discharge from the discharged mass against time: the
/// slope of a straight line fitted over the middle of the discharge, after the start-up (the
/// orifice opening, the flow pattern forming) and before the end (the bed too shallow for a
/// constant rate). Beverloo's law (beverloo.hpp) describes that steady rate.
#include <cstddef>
#include <optional>
#include <vector>

namespace granular {

/// A steady rate and the samples it rests on.
struct SteadyRate {
  double rate = 0;  ///< the fitted line's slope dm/dt [kg/s]
  /// The slope's standard error from the regression, sqrt(SSE / (n − 2) / Σ (t − t̄)²) [kg/s]:
  /// the scatter of the samples about the line, not the rate's run-to-run spread.
  double standardError = 0;
  double intercept = 0;     ///< the line's mass at t = 0 [kg]
  double t0 = 0;            ///< the first sample's time in the window [s]
  double t1 = 0;            ///< the last sample's time in the window [s]
  std::size_t samples = 0;  ///< the samples in the window
};

/// The rate over the samples whose discharged mass m lies within
/// [fromFraction, toFraction] × the total mass (0 <= fromFraction < toFraction <= 1): the total
/// is `totalMass` when given (the bed's mass, for a discharge not yet finished) [kg], else the
/// last sample's mass. time [s] ascending, mass [kg] discharged since the start, paired by index.
/// Throws std::invalid_argument, naming the value, on lengths that differ, a non-finite value,
/// times not ascending, fractions out of order or range, a total <= 0, or fewer than 3 samples in
/// the window (two fix a line; a third is the least for its standard error).
SteadyRate steadyDischargeRate(const std::vector<double>& time, const std::vector<double>& mass,
                               double fromFraction = 0.2, double toFraction = 0.8,
                               std::optional<double> totalMass = std::nullopt);

/// The rate over the samples with t0 <= t <= t1 [s]; throws as steadyDischargeRate, and when
/// t0 >= t1.
SteadyRate steadyDischargeRateInWindow(const std::vector<double>& time,
                                       const std::vector<double>& mass, double t0, double t1);

}  // namespace granular
