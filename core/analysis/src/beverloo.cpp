/// Beverloo's law and its fit (beverloo.hpp).
#include "granular/beverloo.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "input_checks.hpp"
#include "line_fit.hpp"

namespace granular {
namespace {

namespace ic = input_checks;

/// Gauss–Newton stops when neither C nor k moves by more than this, relative to itself (k: to
/// max(|k|, 1), as k may be 0).
constexpr double kStepTolerance = 1e-12;
constexpr int kMaxSteps = 100;
/// A step that does not lower the sum is halved at most this often, then refinement ends.
constexpr int kMaxHalvings = 40;

/// W without the input checks; the jammed orifice gives 0.
double rate(double c, double k, double prefactor, double orifice, double d) {
  const double s = orifice - k * d;
  return s > 0 ? c * prefactor * std::pow(s, 2.5) : 0.0;
}

/// Σ ((W(D₀ᵢ) − Wᵢ)/Wᵢ)², the sum the refinement lowers [-].
double relativeSumOfSquares(const std::vector<double>& orifices, const std::vector<double>& rates,
                            double c, double k, double prefactor, double d) {
  double sum = 0;
  for (std::size_t i = 0; i < orifices.size(); ++i) {
    const double r = (rate(c, k, prefactor, orifices[i], d) - rates[i]) / rates[i];
    sum += r * r;
  }
  return sum;
}

/// Gauss–Newton on (C, k) for the relative residuals, from the given start; returns the steps
/// taken.
int refine(const std::vector<double>& orifices, const std::vector<double>& rates, double prefactor,
           double d, double& c, double& k) {
  const auto n = static_cast<Eigen::Index>(orifices.size());
  double sum = relativeSumOfSquares(orifices, rates, c, k, prefactor, d);
  int steps = 0;
  for (; steps < kMaxSteps; ++steps) {
    Eigen::MatrixXd jacobian(n, 2);
    Eigen::VectorXd residual(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double s = std::max(orifices[i] - k * d, 0.0);
      jacobian(i, 0) = prefactor * std::pow(s, 2.5) / rates[i];
      jacobian(i, 1) = -2.5 * c * prefactor * d * std::pow(s, 1.5) / rates[i];
      residual(i) = (c * prefactor * std::pow(s, 2.5) - rates[i]) / rates[i];
    }
    // QR of the Jacobian itself rather than the normal equations, which would square its
    // condition number.
    const Eigen::Vector2d delta = jacobian.colPivHouseholderQr().solve(-residual);
    double scale = 1.0;
    bool lowered = false;
    for (int h = 0; h < kMaxHalvings; ++h, scale *= 0.5) {
      const double trial = relativeSumOfSquares(orifices, rates, c + scale * delta(0),
                                                k + scale * delta(1), prefactor, d);
      if (trial < sum) {
        sum = trial;
        lowered = true;
        break;
      }
    }
    if (!lowered) break;
    c += scale * delta(0);
    k += scale * delta(1);
    if (std::abs(scale * delta(0)) <= kStepTolerance * std::abs(c) &&
        std::abs(scale * delta(1)) <= kStepTolerance * std::max(std::abs(k), 1.0)) {
      ++steps;
      break;
    }
  }
  return steps;
}

}  // namespace

double beverlooRate(double c, double k, double rhoBulk, double g, double orifice,
                    double particleDiameter) {
  ic::requireNonNegative(c, "beverlooRate: C");
  ic::requireNonNegative(k, "beverlooRate: k");
  ic::requirePositive(rhoBulk, "beverlooRate: bulk density");
  ic::requirePositive(g, "beverlooRate: gravity");
  ic::requireNonNegative(orifice, "beverlooRate: orifice diameter");
  ic::requirePositive(particleDiameter, "beverlooRate: particle diameter");
  return rate(c, k, rhoBulk * std::sqrt(g), orifice, particleDiameter);
}

BeverlooFit fitBeverloo(const std::vector<double>& orifices, const std::vector<double>& rates,
                        double rhoBulk, double g, double particleDiameter, bool refineOnRates) {
  const std::string who = "fitBeverloo";
  ic::requireSameLength(orifices, rates, who + ": orifices and rates");
  ic::requireAtLeast(orifices.size(), 2, who,
                     "two fix C and k; a third is the least for a residual that judges them");
  ic::requirePositive(rhoBulk, who + ": bulk density");
  ic::requirePositive(g, who + ": gravity");
  ic::requirePositive(particleDiameter, who + ": particle diameter");
  std::vector<double> linearised(rates.size());
  for (std::size_t i = 0; i < rates.size(); ++i) {
    ic::requirePositive(orifices[i], who + ": orifice[" + std::to_string(i) + "]");
    ic::requirePositive(rates[i], who + ": rate[" + std::to_string(i) + "]");
    linearised[i] = std::pow(rates[i], 0.4);
  }
  if (std::all_of(orifices.begin(), orifices.end(),
                  [&](double o) { return o == orifices.front(); })) {
    throw std::invalid_argument(who + ": all orifices are " + formatNumber(orifices.front()) +
                                " m; C and k need at least two different ones");
  }
  const LineFit line = fitLine(orifices, linearised);
  if (!(line.slope > 0)) {
    throw std::invalid_argument(who + ": the rates do not grow with the orifice (slope of " +
                                "W^(2/5) against D0: " + formatNumber(line.slope) + ")");
  }
  const double prefactor = rhoBulk * std::sqrt(g);
  BeverlooFit fit;
  fit.c = std::pow(line.slope, 2.5) / prefactor;
  fit.k = -line.intercept / (line.slope * particleDiameter);
  fit.points = orifices.size();
  if (refineOnRates) {
    fit.refinementSteps = refine(orifices, rates, prefactor, particleDiameter, fit.c, fit.k);
  }
  double sum = 0;
  for (std::size_t i = 0; i < rates.size(); ++i) {
    const double relative =
        (rate(fit.c, fit.k, prefactor, orifices[i], particleDiameter) - rates[i]) / rates[i];
    sum += relative * relative;
  }
  fit.rmsRelativeResidual = std::sqrt(sum / static_cast<double>(rates.size()));
  return fit;
}

}  // namespace granular
