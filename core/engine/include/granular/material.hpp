#pragma once
/// Material of the particles and the contact law constants derived from it (docs/physics.md §1).
namespace granular {

/// Normal elastic law: F = (2/3) E/(1-ν²) R^(2-α) h^α with α = 1 (Hooke) or α = 3/2 (Hertz).
enum class NormalLaw { Hooke, Hertz };

/// Particle material, the paper's Table. Defaults are the paper's values (μ = 0 case).
struct Material {
  double youngModulus = 0.3e6;      ///< elastic modulus E [Pa]
  double poissonRatio = 0.30;       ///< Poisson's ratio ν [-]
  double shearModulus = 0.11e6;     ///< shear modulus G [Pa]
  double density = 500.0;           ///< particle density ρ [kg/m³]
  double friction = 0.0;            ///< Coulomb friction coefficient μ [-], particles and walls
  double normalDamping = 60.0;      ///< normal viscous damping γn [1/s]
  double tangentialDamping = 10.0;  ///< tangential viscous damping γt [1/s]
  NormalLaw normalLaw = NormalLaw::Hooke;  ///< α = 1 (Hooke) or 3/2 (Hertz)
  /// The normal force is clamped at zero, F_n = max(0, k h^α + γn m ḣ): it never pulls (design
  /// §2). False, for comparison with codes that allow a pull: F_n = k h^α + γn m ḣ, which the
  /// dashpot makes negative while overlapping spheres separate fast enough.
  bool noPull = true;

  /// (2/3) E/(1-ν²): multiplies R^(2-α) h^α in the normal elastic force [Pa].
  double normalCoefficient() const {
    return 2.0 / 3.0 * youngModulus / (1.0 - poissonRatio * poissonRatio);
  }
  /// (8/3) G/(2-ν): multiplies sqrt(R h) in the tangential spring stiffness [Pa].
  double tangentialCoefficient() const { return 8.0 / 3.0 * shearModulus / (2.0 - poissonRatio); }
  /// α of the normal law [-].
  double exponent() const { return normalLaw == NormalLaw::Hooke ? 1.0 : 1.5; }
  /// True when the tangential force can be non-zero: the Coulomb cap μ|F_n| is then positive.
  /// With μ = 0 the tangential force is min(|F_st|, 0) = 0 whatever γt is, so the scene needs
  /// neither tangential history nor rotations.
  bool hasFriction() const { return friction > 0.0; }
};

}  // namespace granular
