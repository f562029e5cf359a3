/// The silo analyses against closed forms: Janssen's curve, its limits and its fits. Every
/// expected value is derived by hand in the test's comment.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "granular/janssen.hpp"

using namespace granular;

namespace {

constexpr double kPi = std::numbers::pi;

/// The message of the std::invalid_argument `call` throws, or "" (and a failure) when it throws
/// none.
std::string refusal(const std::function<void()>& call) {
  try {
    call();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "no std::invalid_argument thrown";
  return "";
}

/// Expects `call` to be refused with a message that contains `words`.
void expectRefused(const std::function<void()>& call, const std::string& words) {
  const std::string message = refusal(call);
  EXPECT_NE(message.find(words), std::string::npos) << "message: " << message;
}

/// A silo of the size the paper's beds have: D = 0.2 m (R_h = 0.05 m), ρ_b = 600 kg/m³,
/// μ_w = 0.3 and K = 0.5 (λ = 0.15).
constexpr double kHydraulicRadius = 0.05;
constexpr double kGamma = 600.0 * 9.81;
constexpr double kLambda = 0.15;

/// Depths 0, 0.025, ..., 0.5 m: ten hydraulic radii, where σ_v reaches 1 − e^(−1.5) = 78 % of its
/// asymptote, so the data see both the hydrostatic start and the bend.
std::vector<double> janssenDepths() {
  std::vector<double> h;
  for (int k = 0; k <= 20; ++k) h.push_back(0.025 * k);
  return h;
}

std::vector<double> janssenData(const std::vector<double>& depths, double gamma, double lambda) {
  std::vector<double> s;
  for (double h : depths) s.push_back(janssenVerticalStress(h, gamma, kHydraulicRadius, lambda));
  return s;
}

/// Σ (σ_v(h_i; γ, λ) − σ_i)², the sum the fits minimise [Pa²].
double janssenSumOfSquares(const std::vector<double>& depths, const std::vector<double>& sigma,
                           double gamma, double lambda) {
  double sum = 0;
  for (std::size_t k = 0; k < depths.size(); ++k) {
    const double r = janssenVerticalStress(depths[k], gamma, kHydraulicRadius, lambda) - sigma[k];
    sum += r * r;
  }
  return sum;
}

/// ±amplitude alternately, point by point: a deterministic "noise" with no trend, so that a
/// smooth curve fitted through it stays near the noiseless one.
std::vector<double> alternately(std::vector<double> values, double amplitude) {
  for (std::size_t k = 0; k < values.size(); ++k) values[k] *= 1.0 + (k % 2 ? -1 : 1) * amplitude;
  return values;
}

}  // namespace

// ---- Janssen ------------------------------------------------------------------------------------

TEST(Janssen, ClosedFormMeetsItsLimitsAndItsBalance) {
  const double gamma = kGamma, rh = kHydraulicRadius;
  // h = 0 and λ = 0: the hydrostatic line γ h, without 0/0.
  EXPECT_EQ(janssenVerticalStress(0.0, gamma, rh, kLambda), 0.0);
  EXPECT_EQ(janssenVerticalStress(0.3, gamma, rh, 0.0), gamma * 0.3);
  // λ → 0: (1 − e^(−x))/x = 1 − x/2 + x²/6 − ..., so with x = λh/R_h = 10⁻¹² · 6 the stress is
  // γh (1 − 3·10⁻¹²) to 10⁻²³; 1 − exp(−x) without expm1 would lose 4 of those 16 digits.
  const double x = 1e-12 * 0.3 / rh;
  EXPECT_NEAR(janssenVerticalStress(0.3, gamma, rh, 1e-12) / (gamma * 0.3), 1.0 - x / 2, 1e-15);
  // Deep down: e^(−100) is below double precision, so σ_v is γ R_h / λ.
  const double deep = 100.0 * rh / kLambda;
  EXPECT_NEAR(janssenVerticalStress(deep, gamma, rh, kLambda) / (gamma * rh / kLambda), 1.0, 1e-15);
  // The balance of a slice, dσ_v/dh = γ − (λ/R_h) σ_v, by a central difference (its error is
  // σ''' δ²/6 ≈ γ (λ/R_h)² δ²/6, 10⁻¹⁰ relative at δ = 10⁻⁵ m, far below the 10⁻⁷ asked).
  for (double h : {0.01, 0.1, 0.4}) {
    const double delta = 1e-5;
    const double slope = (janssenVerticalStress(h + delta, gamma, rh, kLambda) -
                          janssenVerticalStress(h - delta, gamma, rh, kLambda)) /
                         (2 * delta);
    const double balance = gamma - kLambda / rh * janssenVerticalStress(h, gamma, rh, kLambda);
    EXPECT_NEAR(slope / balance, 1.0, 1e-7) << "h = " << h;
  }
  EXPECT_EQ(circleHydraulicRadius(0.2), 0.05);  // π D²/4 over π D
}

TEST(Janssen, FitRecoversLambdaFromExactData) {
  const std::vector<double> h = janssenDepths();
  const JanssenFit fit = fitJanssen(h, janssenData(h, kGamma, kLambda), kHydraulicRadius, kGamma);
  EXPECT_NEAR(fit.lambda / kLambda, 1.0, 1e-6);
  EXPECT_EQ(fit.gamma, kGamma);
  EXPECT_NEAR(fit.asymptoticStress / (kGamma * kHydraulicRadius / kLambda), 1.0, 1e-6);
  EXPECT_LT(fit.rmsRelativeResidual, 1e-6);
  EXPECT_EQ(fit.points, 21u);
  EXPECT_EQ(fit.pointsInRms, 20u);  // all but h = 0
  EXPECT_FALSE(fit.lambdaAtBound);
  EXPECT_FALSE(fit.gammaFitted);
  // A reading at the surface, where every curve is 0, moves neither λ nor the RMS, which leaves
  // h = 0 out.
  std::vector<double> surfaceReading = janssenData(h, kGamma, kLambda);
  surfaceReading[0] = 100.0;
  const JanssenFit withSurface = fitJanssen(h, surfaceReading, kHydraulicRadius, kGamma);
  EXPECT_NEAR(withSurface.lambda / kLambda, 1.0, 1e-6);
  EXPECT_LT(withSurface.rmsRelativeResidual, 1e-6);
}

TEST(Janssen, FitOfLambdaAndGammaRecoversBoth) {
  const std::vector<double> h = janssenDepths();
  for (double lambda : {0.02, kLambda, 0.8}) {
    const JanssenFit fit =
        fitJanssenLambdaAndGamma(h, janssenData(h, 0.7 * kGamma, lambda), kHydraulicRadius);
    EXPECT_NEAR(fit.lambda / lambda, 1.0, 1e-6) << "lambda = " << lambda;
    EXPECT_NEAR(fit.gamma / (0.7 * kGamma), 1.0, 1e-6) << "lambda = " << lambda;
    EXPECT_LT(fit.rmsRelativeResidual, 1e-6);
    EXPECT_TRUE(fit.gammaFitted);
  }
}

TEST(Janssen, NoisyDataGiveTheNoiseLevelAsRms) {
  // Data 2 % above and below the curve alternately. Were the fit the noiseless curve, every
  // relative residual (fit − data)/fit would be ∓0.02 exactly, so the RMS would be 0.02. The
  // least squares fit can only lower Σ (fit − data)², and alternating noise has almost no
  // component along the smooth changes of the curve with λ and γ, so the RMS stays within a tenth
  // of 0.02 and λ within 2 %.
  const std::vector<double> h = janssenDepths();
  const std::vector<double> data = alternately(janssenData(h, kGamma, kLambda), 0.02);
  const JanssenFit one = fitJanssen(h, data, kHydraulicRadius, kGamma);
  const JanssenFit two = fitJanssenLambdaAndGamma(h, data, kHydraulicRadius);
  for (const JanssenFit& fit : {one, two}) {
    EXPECT_NEAR(fit.rmsRelativeResidual, 0.02, 0.002);
    EXPECT_NEAR(fit.lambda / kLambda, 1.0, 0.02);
    EXPECT_LE(janssenSumOfSquares(h, data, fit.gamma, fit.lambda),
              janssenSumOfSquares(h, data, kGamma, kLambda));
    // The RMS as defined: over the 20 points below the surface, relative to the fitted curve.
    double sum = 0;
    for (std::size_t k = 1; k < h.size(); ++k) {
      const double curve = janssenVerticalStress(h[k], fit.gamma, kHydraulicRadius, fit.lambda);
      sum += (curve - data[k]) * (curve - data[k]) / (curve * curve);
    }
    EXPECT_NEAR(fit.rmsRelativeResidual, std::sqrt(sum / 20), 1e-12);
  }
  // A least squares minimum: moving λ either way by 10⁻⁴ (relative) raises the sum.
  const double best = janssenSumOfSquares(h, data, kGamma, one.lambda);
  EXPECT_LT(best, janssenSumOfSquares(h, data, kGamma, one.lambda * (1 + 1e-4)));
  EXPECT_LT(best, janssenSumOfSquares(h, data, kGamma, one.lambda * (1 - 1e-4)));
}

TEST(Janssen, HydrostaticDataPutLambdaAtItsLowerBound) {
  // σ = γ h is Janssen's curve for λ = 0, below the range: the fit stops at kJanssenLambdaMin
  // and says so.
  const std::vector<double> h = janssenDepths();
  std::vector<double> hydrostatic;
  for (double depth : h) hydrostatic.push_back(kGamma * depth);
  const JanssenFit fit = fitJanssen(h, hydrostatic, kHydraulicRadius, kGamma);
  EXPECT_TRUE(fit.lambdaAtBound);
  EXPECT_NEAR(fit.lambda / kJanssenLambdaMin, 1.0, 1e-9);
  EXPECT_FALSE(
      fitJanssen(h, janssenData(h, kGamma, kLambda), kHydraulicRadius, kGamma).lambdaAtBound);
}

TEST(Janssen, FitRefusesBadInput) {
  const std::vector<double> h = {0.1, 0.2, 0.3};
  const std::vector<double> s = {500.0, 900.0, 1200.0};
  expectRefused([&] { fitJanssen(h, {500.0, 900.0}, 0.05, kGamma); }, "3 against 2");
  expectRefused([&] { fitJanssen({0.1, 0.2}, {500.0, 900.0}, 0.05, kGamma); }, "2 points");
  // Three points, but one at the surface: only two below it.
  expectRefused(
      [&] {
        fitJanssen({0.0, 0.1, 0.2}, {0.0, 500.0, 900.0}, 0.05, kGamma);
      },
      "depth > 0: 2 points");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expectRefused([&] { fitJanssen(h, {500.0, nan, 1200.0}, 0.05, kGamma); }, "stress[1]");
  expectRefused([&] { fitJanssen({0.1, -0.2, 0.3}, s, 0.05, kGamma); }, "depth[1]");
  expectRefused([&] { fitJanssen(h, s, 0.0, kGamma); }, "hydraulic radius must be > 0 (got 0)");
  expectRefused([&] { fitJanssen(h, s, -0.05, kGamma); }, "got -0.05");
  expectRefused([&] { fitJanssen(h, s, 0.05, 0.0); }, "gamma must be > 0");
  expectRefused(
      [&] {
        fitJanssenLambdaAndGamma(h, {-500.0, -900.0, -1200.0}, 0.05);
      },
      "compression positive");
  expectRefused([&] { janssenVerticalStress(0.1, kGamma, 0.05, -0.1); }, "lambda must be >= 0");
}
