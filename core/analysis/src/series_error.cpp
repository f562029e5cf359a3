/// Time-series error metrics (series_error.hpp).
#include "granular/series_error.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace granular {
namespace {

void requireWellFormed(const SampledSeries& s, const char* what) {
  if (s.time.size() != s.value.size()) {
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(s.time.size()) +
                                " times but " + std::to_string(s.value.size()) + " values");
  }
  if (s.time.empty()) throw std::invalid_argument(std::string(what) + ": no samples");
  if (!std::is_sorted(s.time.begin(), s.time.end())) {
    throw std::invalid_argument(std::string(what) + ": times must be ascending");
  }
}

/// interpolateSeries for a series already checked.
double interpolateChecked(const SampledSeries& series, double t) {
  const std::vector<double>& x = series.time;
  if (t < x.front() || t > x.back()) {
    throw std::invalid_argument("time " + std::to_string(t) + " s is outside the series' range [" +
                                std::to_string(x.front()) + ", " + std::to_string(x.back()) +
                                "] s");
  }
  // First sample at or after t; a sample exactly at t is returned as it is.
  const std::size_t hi = std::lower_bound(x.begin(), x.end(), t) - x.begin();
  if (x[hi] == t || hi == 0) return series.value[hi];
  const std::size_t lo = hi - 1;
  const double w = (t - x[lo]) / (x[hi] - x[lo]);
  return (1.0 - w) * series.value[lo] + w * series.value[hi];
}

}  // namespace

double interpolateSeries(const SampledSeries& series, double t) {
  requireWellFormed(series, "series");
  return interpolateChecked(series, t);
}

double relativeDeviation(double x, double r) {
  if (r == 0.0) throw std::invalid_argument("relative deviation from a zero reference");
  return std::abs(x - r) / std::abs(r);
}

double maxRelativeDeviation(const SampledSeries& run, const SampledSeries& reference, double tMin) {
  requireWellFormed(run, "run series");
  requireWellFormed(reference, "reference series");
  double worst = 0.0;
  std::size_t compared = 0;
  for (std::size_t k = 0; k < reference.time.size(); ++k) {
    const double t = reference.time[k];
    if (t < tMin || t < run.time.front() || t > run.time.back()) continue;
    worst = std::max(worst, relativeDeviation(interpolateChecked(run, t), reference.value[k]));
    ++compared;
  }
  if (compared == 0) {
    throw std::invalid_argument("no reference sample at t >= " + std::to_string(tMin) +
                                " s inside the run's time range");
  }
  return worst;
}

}  // namespace granular
