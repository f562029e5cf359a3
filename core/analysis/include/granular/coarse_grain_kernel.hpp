#pragma once
/// The coarse-graining kernel of the local fields (docs/physics.md §2.11; Weinhart et al., Granular
/// Matter 14:289, 2012): Lucy's polynomial, its gradient, and its integral along a contact's
/// branch, with which the coarse-grained stress satisfies the momentum balance for any width.
#include "granular/vec3.hpp"

namespace granular {

/// Lucy's kernel (Lucy, Astron. J. 82:1013, 1977) of width c: compact support r < c, twice
/// continuously differentiable (φ, φ′ and φ″ vanish at r = c) and normalised in 3-D,
///   φ(r) = 105/(16π c³) · (1 + 3ρ)(1 − ρ)³ = 105/(16π c³) · (1 − 6ρ² + 8ρ³ − 3ρ⁴),  ρ = r/c,
/// since ∫₀¹ 4πρ² (1 − 6ρ² + 8ρ³ − 3ρ⁴) dρ = 4π (1/3 − 6/5 + 4/3 − 3/7) = 16π/105.
class LucyKernel {
 public:
  /// width c [m] > 0; throws ConfigError otherwise.
  explicit LucyKernel(double width);

  double width() const { return width_; }  ///< c [m]

  /// φ at distance r ≥ 0 [1/m³]. The factored form keeps full relative accuracy near the edge,
  /// where the expanded one cancels to an absolute 1e-16 K.
  double value(double distance) const {
    const double rho = distance / width_;
    if (!(rho < 1)) return 0;
    const double gap = 1 - rho;
    return norm_ * (1 + 3 * rho) * (gap * gap * gap);
  }

  /// φ(|r|) [1/m³].
  double operator()(const Vec3& r) const { return value(r.norm()); }

  /// ∇φ(r) = φ′(|r|) r/|r| = −12·105/(16π c⁵) (1 − ρ)² r [1/m⁴]: smooth at r = 0, where it is 0.
  Vec3 gradient(const Vec3& r) const {
    const double rho = r.norm() / width_;
    if (!(rho < 1)) return Vec3::Zero();
    const double gap = 1 - rho;
    return (-12 * norm_ / (width_ * width_) * gap * gap) * r;
  }

  /// ψ(r; a, b) = ∫₀¹ φ(r − a − s(b − a)) ds [1/m³]: the kernel averaged along the branch from
  /// a to b (a contact's stress is spread along it, physics.md §2.11). ψ = φ(r − a) when a = b.
  ///
  /// Method: with d = b − a, L = |d|, u the signed distance along the line from the point
  /// closest to r (at distance m from r), the integrand is K(1 − 6ρ² + 8ρ³ − 3ρ⁴) with
  /// ρ² = (u² + m²)/c², non-zero for |u| < √(c² − m²). The u-range is clipped to that support
  /// (so the work does not grow with L/c, and the C² edge of the support is an end point, not
  /// an interior kink) and split at u = 0. On each side the integrand is analytic, its only
  /// singularities the branch points u = ±i m of ρ³; the side is cut into pieces no longer than
  /// their distance √(u² + m²) to those points (geometric grading towards u = 0, down to 1/4096
  /// of the side; below that the non-polynomial part is O(m³) and negligible), each integrated
  /// with 12-point Gauss–Legendre. Then every piece sees its singularity beyond the Bernstein
  /// ellipse of parameter ≥ 4.6, and the error is below 4.6^(−24) ≈ 1e-16 of the integrand's
  /// scale: ψ is exact to round-off (≈1e-15 K, K = 105/(16π c³); tests/test_coarse_grain_kernel
  /// checks it against the closed form). Cost: 12 kernel evaluations per piece, 1–6 pieces for
  /// a typical branch, at most ~26.
  double lineIntegral(const Vec3& r, const Vec3& a, const Vec3& b) const;

  /// ∇_r ψ(r; a, b) = ∫₀¹ ∇φ(r − a − s(b − a)) ds [1/m⁴], by the same quadrature. It satisfies
  /// (b − a)·∇_r ψ = φ(r − a) − φ(r − b) (the integrand is −d/ds of φ along the branch), the
  /// reason the coarse-grained momentum balance holds for any width.
  Vec3 lineIntegralGradient(const Vec3& r, const Vec3& a, const Vec3& b) const;

 private:
  double width_;
  double norm_;  ///< K = 105/(16π c³) [1/m³]
};

}  // namespace granular
