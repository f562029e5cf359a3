#pragma once
/// Error of a sampled time series against a reference series, for accuracy benchmarks: runs at
/// different time steps sample at slightly different times (a sample is taken at the first step
/// end at or after each output time), so the run is interpolated to the reference's times.
#include <vector>

namespace granular {

/// Samples of one quantity: times ascending [s], one value per time [any unit].
struct SampledSeries {
  std::vector<double> time;
  std::vector<double> value;
};

/// Linear interpolation of `series` at time t [s]; t must lie within its time range.
double interpolateSeries(const SampledSeries& series, double t);

/// max over the reference samples with t ≥ tMin (and inside the run's time range) of
/// |x(t) − r(t)| / |r(t)|, x the run interpolated linearly to the reference's time t [-].
/// Throws std::invalid_argument when a series is malformed (sizes differ, times not ascending),
/// when no reference sample qualifies, or when a compared reference value is zero.
double maxRelativeDeviation(const SampledSeries& run, const SampledSeries& reference, double tMin);

/// |x − r| / |r| [-]; r must not be zero.
double relativeDeviation(double x, double r);

}  // namespace granular
