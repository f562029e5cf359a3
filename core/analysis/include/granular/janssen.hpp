#pragma once
/// Janssen's vertical stress in a silo (the basis of EN 1991-4's filling pressures) and its least
/// squares fit to measured stresses. A slice of the bed at depth h carries its weight partly on
/// the slice below and partly, by wall friction, on the wall; the balance
/// dσ_v/dh = γ − (λ / R_h) σ_v with λ = μ_w K gives
///
///     σ_v(h) = (γ R_h / λ) (1 − exp(−λ h / R_h)),   p_h = K σ_v,   τ_w = μ_w p_h,
///
/// h the depth below the bed's surface [m], R_h = A/U the hydraulic radius of the cross-section
/// (area over wetted perimeter) [m], γ = ρ_b g the bulk weight density [N/m³], K the lateral
/// pressure ratio [-] and μ_w the wall friction coefficient [-]. Near the surface σ_v follows the
/// hydrostatic line γ h; deep down it tends to γ R_h / λ. Stresses are magnitudes, compression
/// positive.
#include <cstddef>
#include <vector>

namespace granular {

/// The smallest and largest λ = μ_w K the fits consider [-]: from nearly frictionless walls to
/// far beyond any granular material's μ_w K (EN 1991-4 tables μ_w ≤ 0.6 and K ≤ 0.7).
inline constexpr double kJanssenLambdaMin = 1e-4;
inline constexpr double kJanssenLambdaMax = 10.0;

/// R_h = A/U = D/4 of a circular cross-section of diameter D [m].
double circleHydraulicRadius(double diameter);

/// σ_v(h) = (γ R_h / λ)(1 − exp(−λ h / R_h)) [Pa] at depth h >= 0 [m], bulk weight density γ
/// [N/m³], hydraulic radius R_h > 0 [m] and λ = μ_w K >= 0 [-]. Evaluated as γ h (1 − e^(−x))/x
/// with x = λ h / R_h and expm1, so λ → 0 (and h = 0) give the hydrostatic γ h to full precision
/// instead of 0/0. Throws std::invalid_argument on a negative or non-finite depth or λ, a
/// non-finite γ, or R_h <= 0.
double janssenVerticalStress(double depth, double gamma, double hydraulicRadius, double lambda);

/// A Janssen curve fitted to stresses measured at depths.
struct JanssenFit {
  double lambda = 0;  ///< λ = μ_w K [-]
  double gamma = 0;   ///< γ = ρ_b g: the given one, or the fitted one [N/m³]
  /// γ R_h / λ, the stress the curve tends to deep down [Pa].
  double asymptoticStress = 0;
  /// sqrt(mean(((fit − data)/fit)²)) over the points with depth h > 0 (at h = 0 the curve is 0
  /// and any data there only add noise) [-]: 0.05 reads "the data follow the curve within 5 %".
  double rmsRelativeResidual = 0;
  std::size_t points = 0;       ///< points given
  std::size_t pointsInRms = 0;  ///< of them, those with h > 0 (the RMS's points)
  /// λ came out within the golden-section tolerance of kJanssenLambdaMin or kJanssenLambdaMax:
  /// the data prefer a λ outside the range (at the lower end: a hydrostatic profile, no wall
  /// friction seen), so λ is a bound rather than a value.
  bool lambdaAtBound = false;
  bool gammaFitted = false;  ///< γ was fitted (fitJanssenLambdaAndGamma), not given
};

/// The λ that minimises Σ (σ_v(h_i; γ, λ) − σ_i)² with γ given (measured as the bed's mass over
/// its volume, times g): a grid over log λ on [kJanssenLambdaMin, kJanssenLambdaMax] picks the
/// basin, golden-section search on log λ narrows it to 10⁻¹² (relative in λ). The residual is the
/// absolute stress [Pa], so the deep points, whose stress is largest and best measured, weigh
/// most. depths [m] >= 0 and sigmaV [Pa] pair up by index; R_h [m] and γ [N/m³] as in
/// janssenVerticalStress. Throws std::invalid_argument, naming the value, on lengths that differ,
/// fewer than 3 points at depth > 0 (two fix a curve of γ and λ; a third is the least that leaves a
/// residual to judge it),
/// a non-finite value, a negative depth, R_h <= 0 or γ <= 0.
JanssenFit fitJanssen(const std::vector<double>& depths, const std::vector<double>& sigmaV,
                      double hydraulicRadius, double gamma);

/// Both γ and λ: for each λ the best γ is the linear least squares one,
/// γ(λ) = Σ f_i σ_i / Σ f_i² with f_i = σ_v(h_i; 1, λ), and the search over λ is fitJanssen's.
/// For data whose bulk density is not known apart (or to check the measured one). Throws as
/// fitJanssen, and when no positive γ fits the data.
JanssenFit fitJanssenLambdaAndGamma(const std::vector<double>& depths,
                                    const std::vector<double>& sigmaV, double hydraulicRadius);

}  // namespace granular
