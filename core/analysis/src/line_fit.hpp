#pragma once
/// The least squares straight line y = intercept + slope x, for the Beverloo fit (beverloo.hpp)
/// and the steady discharge rate (discharge_rate.hpp).
#include <cstddef>
#include <vector>

namespace granular {

/// A fitted line and the regression's standard error of its slope.
struct LineFit {
  double slope = 0;      ///< [y's unit / x's unit]
  double intercept = 0;  ///< [y's unit]
  /// sqrt(SSE / (n − 2) / Σ (x − x̄)²), the slope's standard error under independent residuals of
  /// equal variance; NaN for two points, which leave no residual [y's unit / x's unit].
  double slopeStandardError = 0;
  std::size_t points = 0;  ///< n
};

/// Ordinary least squares over the pairs (x_k, y_k), from sums about the means so that a large
/// offset in x (a late time window) costs no precision. The caller checks the input: equal
/// lengths, finite values, >= 2 points. Throws std::invalid_argument when all x are equal.
LineFit fitLine(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace granular
