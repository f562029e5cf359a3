/// Time-series error metrics (series_error.hpp): zero for identical series, the right value for
/// a known offset, exact interpolation across shifted sample times, the start time honoured.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "granular/series_error.hpp"

using namespace granular;

namespace {

/// value(t) = a + b t sampled at t0, t0 + dt, ... (n samples).
SampledSeries linear(double a, double b, double t0, double dt, int n) {
  SampledSeries s;
  for (int k = 0; k < n; ++k) {
    s.time.push_back(t0 + k * dt);
    s.value.push_back(a + b * s.time.back());
  }
  return s;
}

}  // namespace

TEST(SeriesError, IdenticalSeriesHaveZeroError) {
  const SampledSeries s = linear(-1500.0, -100.0, 0.0, 0.01, 101);
  EXPECT_EQ(maxRelativeDeviation(s, s, 0.1), 0.0);
}

TEST(SeriesError, KnownOffsetGivesItsRelativeSize) {
  const SampledSeries ref = linear(-1000.0, 0.0, 0.0, 0.01, 101);
  SampledSeries run = ref;
  for (double& v : run.value) v *= 1.01;
  EXPECT_NEAR(maxRelativeDeviation(run, ref, 0.1), 0.01, 1e-12);
  // The largest deviation wins, wherever it is.
  run = ref;
  run.value[57] = -1030.0;
  EXPECT_NEAR(maxRelativeDeviation(run, ref, 0.1), 0.03, 1e-12);
}

TEST(SeriesError, RunIsInterpolatedToTheReferenceTimes) {
  // A linear signal sampled late by a fraction of the interval: interpolation is exact.
  const SampledSeries ref = linear(-1500.0, -200.0, 0.0, 0.01, 101);
  const SampledSeries run = linear(-1500.0, -200.0, 0.0004, 0.01, 101);
  EXPECT_NEAR(maxRelativeDeviation(run, ref, 0.1), 0.0, 1e-14);
  EXPECT_NEAR(interpolateSeries(run, 0.5), -1600.0, 1e-9);
  // Without interpolation the lag would show as 200 Pa/s × 0.4 ms against 1500 Pa.
  SampledSeries naive = run;
  naive.time = ref.time;
  EXPECT_NEAR(maxRelativeDeviation(naive, ref, 0.1), 200.0 * 0.0004 / (1500.0 + 200.0 * 0.1), 1e-9);
}

TEST(SeriesError, SamplesBeforeTheStartTimeAreIgnored) {
  const SampledSeries ref = linear(-1000.0, 0.0, 0.0, 0.01, 101);
  SampledSeries run = ref;
  run.value[5] = 0.0;  // t = 0.05 s: a 100 % deviation inside the start-up transient
  EXPECT_EQ(maxRelativeDeviation(run, ref, 0.1), 0.0);
  EXPECT_NEAR(maxRelativeDeviation(run, ref, 0.0), 1.0, 1e-12);
}

TEST(SeriesError, MalformedInputIsRefused) {
  const SampledSeries ref = linear(-1000.0, 0.0, 0.0, 0.01, 11);
  SampledSeries shortValues = ref;
  shortValues.value.pop_back();
  EXPECT_THROW(maxRelativeDeviation(shortValues, ref, 0.0), std::invalid_argument);
  SampledSeries unsorted = ref;
  std::swap(unsorted.time[2], unsorted.time[3]);
  EXPECT_THROW(maxRelativeDeviation(ref, unsorted, 0.0), std::invalid_argument);
  EXPECT_THROW(maxRelativeDeviation(ref, ref, 1.0), std::invalid_argument);  // nothing after
  SampledSeries zero = ref;
  zero.value[4] = 0.0;
  EXPECT_THROW(maxRelativeDeviation(ref, zero, 0.0), std::invalid_argument);
  EXPECT_THROW(interpolateSeries(ref, 0.2), std::invalid_argument);  // outside [0, 0.1] s
}
