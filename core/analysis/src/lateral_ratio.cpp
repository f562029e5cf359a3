/// Lateral pressure ratio: measured and EN 1991-4's (lateral_ratio.hpp).
#include "granular/lateral_ratio.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "input_checks.hpp"

namespace granular {

double en1991LateralRatio(double internalFrictionAngle) {
  input_checks::requireNonNegative(internalFrictionAngle,
                                   "en1991LateralRatio: internal friction angle");
  if (internalFrictionAngle > std::numbers::pi / 2) {
    throw std::invalid_argument(
        "en1991LateralRatio: internal friction angle must be <= pi/2 rad "
        "(got " +
        formatNumber(internalFrictionAngle) + " rad)");
  }
  return 1.1 * (1.0 - std::sin(internalFrictionAngle));
}

double internalFrictionAngleFromStresses(double sigma1, double sigma3) {
  const std::string who = "internalFrictionAngleFromStresses";
  input_checks::requirePositive(sigma1, who + ": sigma1");
  input_checks::requireNonNegative(sigma3, who + ": sigma3");
  if (sigma3 > sigma1) {
    throw std::invalid_argument(who + ": needs sigma1 >= sigma3 (got " + formatNumber(sigma1) +
                                " Pa and " + formatNumber(sigma3) + " Pa)");
  }
  return std::asin((sigma1 - sigma3) / (sigma1 + sigma3));
}

std::vector<double> lateralToVertical(const std::vector<WallBandStats>& wallBands,
                                      const SliceStressProfile& slices) {
  const std::string who = "lateralToVertical";
  if (wallBands.size() != slices.slices.size()) {
    throw std::invalid_argument(who + ": " + std::to_string(wallBands.size()) + " bands but " +
                                std::to_string(slices.slices.size()) + " slices");
  }
  std::vector<double> ratio(wallBands.size());
  if (ratio.empty()) return ratio;
  const double range = std::max(std::abs(wallBands.back().zHigh - wallBands.front().zLow),
                                std::numeric_limits<double>::min());
  for (std::size_t k = 0; k < ratio.size(); ++k) {
    const WallBandStats& band = wallBands[k];
    const SliceStress& slice = slices.slices[k];
    if (std::abs(band.zLow - slice.zLow) > 1e-12 * range ||
        std::abs(band.zHigh - slice.zHigh) > 1e-12 * range) {
      throw std::invalid_argument(
          who + ": band " + std::to_string(k) + " spans [" + formatNumber(band.zLow) + ", " +
          formatNumber(band.zHigh) + "] m but slice " + std::to_string(k) + " spans [" +
          formatNumber(slice.zLow) + ", " + formatNumber(slice.zHigh) + "] m");
    }
    ratio[k] = slice.sigmaV > 0 ? band.meanPressure / slice.sigmaV
                                : std::numeric_limits<double>::quiet_NaN();
  }
  return ratio;
}

}  // namespace granular
