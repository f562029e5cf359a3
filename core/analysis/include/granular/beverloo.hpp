#pragma once
/// Beverloo's law for the mass flow rate out of a silo's orifice and its least squares fit to
/// measured rates. The rate does not depend on the fill height; it scales with the orifice's
/// "effective" diameter D₀ − k d, the rim losing a band about k/2 particle diameters wide:
///
///     W = C ρ_b √g (D₀ − k d)^(5/2),
///
/// W the mass flow rate [kg/s], ρ_b the bulk density [kg/m³], g gravity [m/s²], D₀ the orifice's
/// diameter [m], d the particle diameter [m], C [-] and k [-] the empirical constants (typically
/// C ≈ 0.55–0.65, k ≈ 1.3–2.9).
#include <cstddef>
#include <vector>

namespace granular {

/// W = C ρ_b √g (D₀ − k d)^(5/2) [kg/s], and 0 where D₀ <= k d (the orifice jams). C, k, D₀ >= 0;
/// ρ_b [kg/m³], g [m/s²] and d [m] > 0. Throws std::invalid_argument on a value outside these
/// ranges or not finite.
double beverlooRate(double c, double k, double rhoBulk, double g, double orifice,
                    double particleDiameter);

/// C and k fitted to rates measured at several orifices.
struct BeverlooFit {
  double c = 0;  ///< C [-]
  double k = 0;  ///< k [-]
  /// sqrt(mean(((fit − data)/data)²)) over all points [-]: relative to the measured rate, which is
  /// > 0 for every point, while the fitted one may be 0 at a jammed orifice. With two points the
  /// fit passes through both and this is 0: three are the least for a residual that judges it.
  double rmsRelativeResidual = 0;
  std::size_t points = 0;  ///< the points used (all given)
  /// Gauss–Newton steps taken on W after the linear fit (0 when not refined, or when the linear
  /// fit already was the least squares one on W's relative residuals).
  int refinementSteps = 0;
};

/// First W^(2/5) = a D₀ + b, a straight line: least squares gives a = (C ρ_b √g)^(2/5) and
/// b = −a k d, so C = a^(5/2)/(ρ_b √g) and k = −b/(a d). That line weighs the points as W^(2/5)
/// does; with `refineOnRates` Gauss–Newton on the rates themselves,
/// Σ ((W(D₀ᵢ; C, k) − Wᵢ)/Wᵢ)² [-], then starts from it, halving a step until the sum falls, and
/// stops when a step changes C and k by less than 10⁻¹² relative (or after 100 steps). The
/// residuals are relative because the rates span decades (W ∝ (D₀ − k d)^(5/2)) and each is
/// measured to a similar relative precision: absolute ones would fit the widest orifice and leave
/// the narrow ones off by several times the noise. So the refinement minimises the RMS it
/// reports. orifices [m] and rates [kg/s] pair up by index; ρ_b, g, d
/// as beverlooRate. Throws std::invalid_argument, naming the value, on lengths that differ, fewer
/// than 2 points, a non-finite value, an orifice or rate <= 0, orifices all equal, or rates that
/// do not grow with the orifice (a <= 0).
BeverlooFit fitBeverloo(const std::vector<double>& orifices, const std::vector<double>& rates,
                        double rhoBulk, double g, double particleDiameter,
                        bool refineOnRates = true);

}  // namespace granular
