/// Least squares straight line (line_fit.hpp).
#include "line_fit.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace granular {

LineFit fitLine(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  double xMean = 0, yMean = 0;
  for (std::size_t k = 0; k < n; ++k) {
    xMean += x[k];
    yMean += y[k];
  }
  xMean /= static_cast<double>(n);
  yMean /= static_cast<double>(n);
  double sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < n; ++k) {
    sxx += (x[k] - xMean) * (x[k] - xMean);
    sxy += (x[k] - xMean) * (y[k] - yMean);
  }
  if (!(sxx > 0)) throw std::invalid_argument("fitLine: all abscissae are equal");
  LineFit fit;
  fit.points = n;
  fit.slope = sxy / sxx;
  fit.intercept = yMean - fit.slope * xMean;
  if (n < 3) {
    fit.slopeStandardError = std::numeric_limits<double>::quiet_NaN();
    return fit;
  }
  double sse = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double r = y[k] - (yMean + fit.slope * (x[k] - xMean));
    sse += r * r;
  }
  fit.slopeStandardError = std::sqrt(sse / static_cast<double>(n - 2) / sxx);
  return fit;
}

}  // namespace granular
