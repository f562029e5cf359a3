/// Janssen's closed form and its fits (janssen.hpp).
#include "granular/janssen.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "input_checks.hpp"
#include "scalar_minimum.hpp"

namespace granular {
namespace {

namespace ic = input_checks;

/// Grid points over log λ: 200 intervals over five decades put ~40 in each decade, so a basin
/// of the least squares sum is never narrower than the grid.
constexpr int kLambdaGridPoints = 201;
/// Golden-section tolerance on log λ: a relative 10⁻¹² in λ.
constexpr double kLogLambdaTolerance = 1e-12;

/// σ_v(h; 1, λ), the curve for unit γ [m]; inputs already checked.
double unitCurve(double depth, double hydraulicRadius, double lambda) {
  const double x = lambda * depth / hydraulicRadius;
  if (x == 0.0) return depth;
  return depth * (-std::expm1(-x) / x);
}

/// The checks both fits make; returns the number of points with h > 0.
std::size_t checkFitInput(const std::vector<double>& depths, const std::vector<double>& sigmaV,
                          double hydraulicRadius, const std::string& who) {
  ic::requireSameLength(depths, sigmaV, who + ": depths and stresses");
  ic::requireFiniteSeries(depths, who + ": depth");
  ic::requireFiniteSeries(sigmaV, who + ": stress");
  ic::requirePositive(hydraulicRadius, who + ": hydraulic radius");
  std::size_t below = 0;
  for (std::size_t k = 0; k < depths.size(); ++k) {
    ic::requireNonNegative(depths[k], who + ": depth[" + std::to_string(k) + "]");
    if (depths[k] > 0) ++below;
  }
  ic::requireAtLeast(below, 3, who + ": points at depth > 0",
                     "two fix a curve of gamma and lambda; a third is the least for a residual");
  return below;
}

/// Σ (γ f_i − σ_i)² for the curve of unit γ f [Pa²].
double sumOfSquares(const std::vector<double>& depths, const std::vector<double>& sigmaV,
                    double hydraulicRadius, double gamma, double lambda) {
  double sum = 0;
  for (std::size_t k = 0; k < depths.size(); ++k) {
    const double r = gamma * unitCurve(depths[k], hydraulicRadius, lambda) - sigmaV[k];
    sum += r * r;
  }
  return sum;
}

/// The least squares γ for a given λ: Σ f σ / Σ f² [N/m³].
double bestGamma(const std::vector<double>& depths, const std::vector<double>& sigmaV,
                 double hydraulicRadius, double lambda) {
  double fs = 0, ff = 0;
  for (std::size_t k = 0; k < depths.size(); ++k) {
    const double f = unitCurve(depths[k], hydraulicRadius, lambda);
    fs += f * sigmaV[k];
    ff += f * f;
  }
  return fs / ff;
}

/// The fit's summary once λ and γ are known.
JanssenFit summarise(const std::vector<double>& depths, const std::vector<double>& sigmaV,
                     double hydraulicRadius, double gamma, double lambda, bool atBound,
                     bool gammaFitted, std::size_t pointsInRms) {
  JanssenFit fit;
  fit.lambda = lambda;
  fit.gamma = gamma;
  fit.asymptoticStress = gamma * hydraulicRadius / lambda;
  fit.points = depths.size();
  fit.pointsInRms = pointsInRms;
  fit.lambdaAtBound = atBound;
  fit.gammaFitted = gammaFitted;
  double sum = 0;
  for (std::size_t k = 0; k < depths.size(); ++k) {
    if (!(depths[k] > 0)) continue;
    const double curve = gamma * unitCurve(depths[k], hydraulicRadius, lambda);
    const double relative = (curve - sigmaV[k]) / curve;
    sum += relative * relative;
  }
  fit.rmsRelativeResidual = std::sqrt(sum / static_cast<double>(pointsInRms));
  return fit;
}

}  // namespace

double circleHydraulicRadius(double diameter) {
  ic::requirePositive(diameter, "circleHydraulicRadius: diameter");
  return diameter / 4.0;
}

double janssenVerticalStress(double depth, double gamma, double hydraulicRadius, double lambda) {
  ic::requireNonNegative(depth, "janssenVerticalStress: depth");
  ic::requireFinite(gamma, "janssenVerticalStress: gamma");
  ic::requirePositive(hydraulicRadius, "janssenVerticalStress: hydraulic radius");
  ic::requireNonNegative(lambda, "janssenVerticalStress: lambda");
  return gamma * unitCurve(depth, hydraulicRadius, lambda);
}

JanssenFit fitJanssen(const std::vector<double>& depths, const std::vector<double>& sigmaV,
                      double hydraulicRadius, double gamma) {
  const std::size_t below = checkFitInput(depths, sigmaV, hydraulicRadius, "fitJanssen");
  ic::requirePositive(gamma, "fitJanssen: gamma");
  const ScalarMinimum m = minimiseOnInterval(
      [&](double logLambda) {
        return sumOfSquares(depths, sigmaV, hydraulicRadius, gamma, std::exp(logLambda));
      },
      std::log(kJanssenLambdaMin), std::log(kJanssenLambdaMax), kLambdaGridPoints,
      kLogLambdaTolerance);
  return summarise(depths, sigmaV, hydraulicRadius, gamma, std::exp(m.x), m.atBound, false, below);
}

JanssenFit fitJanssenLambdaAndGamma(const std::vector<double>& depths,
                                    const std::vector<double>& sigmaV, double hydraulicRadius) {
  const std::size_t below =
      checkFitInput(depths, sigmaV, hydraulicRadius, "fitJanssenLambdaAndGamma");
  const ScalarMinimum m = minimiseOnInterval(
      [&](double logLambda) {
        const double lambda = std::exp(logLambda);
        const double gamma = bestGamma(depths, sigmaV, hydraulicRadius, lambda);
        return sumOfSquares(depths, sigmaV, hydraulicRadius, gamma, lambda);
      },
      std::log(kJanssenLambdaMin), std::log(kJanssenLambdaMax), kLambdaGridPoints,
      kLogLambdaTolerance);
  const double lambda = std::exp(m.x);
  const double gamma = bestGamma(depths, sigmaV, hydraulicRadius, lambda);
  if (!(gamma > 0)) {
    throw std::invalid_argument("fitJanssenLambdaAndGamma: the best fitting gamma is " +
                                formatNumber(gamma) +
                                " N/m^3; the stresses must be magnitudes, compression positive");
  }
  return summarise(depths, sigmaV, hydraulicRadius, gamma, lambda, m.atBound, true, below);
}

}  // namespace granular
