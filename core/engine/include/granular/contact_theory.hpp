#pragma once
/// Closed-form results for a single binary contact under the law of docs/physics.md §1. Used to
/// choose and check the time step, and by the tests as the reference the simulation must reproduce.
#include "granular/material.hpp"

namespace granular {

/// Outcome of a head-on impact of two bodies (or one body on a wall) along the normal.
struct ImpactPrediction {
  double forceDuration = 0;    ///< time from first touch until the normal force vanishes [s]
  double overlapDuration = 0;  ///< time from first touch until the overlap closes [s]
  double restitution = 0;      ///< normal rebound speed / approach speed [-]
  double peakOverlap = 0;      ///< largest overlap reached [m]
};

/// Linear spring k and dashpot c = γn·m on reduced mass m, approach speed v0 > 0, with the no-pull
/// clamp: the force k·h + c·ḣ is zero once it would become negative. The motion is the damped
/// oscillation h = (v0/ωd) e^(-βt) sin(ωd t) until k·h + c·ḣ = 0, then free separation at the
/// velocity reached (no force acts, so the overlap closes at constant speed). Requires an
/// under-damped contact (γn/2 < sqrt(k/m)); throws ConfigError otherwise.
ImpactPrediction hookeDampedImpact(double stiffness, double normalDamping, double reducedMass,
                                   double approachSpeed);

/// The same contact without the no-pull clamp (Material::noPull false): the damped oscillation
/// runs until the overlap closes, at t = π/ωd, the force k·h + c·ḣ pulling after it has turned
/// negative. Force and overlap duration π/ωd, restitution e^(−βπ/ωd), the same peak overlap.
/// Requires an under-damped contact; throws ConfigError otherwise.
ImpactPrediction hookeDampedImpactWithPull(double stiffness, double normalDamping,
                                           double reducedMass, double approachSpeed);

/// Hertz F = K·h^(3/2) without damping (K = (4/3)E*·sqrt(R*) = (2/3)E/(1-ν²)·sqrt(R_ij) here):
/// duration 3.2181·(m/K)^(2/5)·v^(-1/5) (= 2.87·(m*²/(R* E*² v))^(1/5)), peak overlap
/// (5 m v²/(4 K))^(2/5), restitution 1.
ImpactPrediction hertzUndampedImpact(double hertzConstant, double reducedMass,
                                     double approachSpeed);

/// The peak overlap of a head-on impact at approach speed `speed` [m/s] on a contact of reduced
/// radius and mass (a wall contact: the particle's own) under the material's normal law: the
/// damped Hooke or undamped Hertz closed form above [m]. Beyond the particle's radius a sphere
/// passes through a wall, whatever the time step.
double peakImpactOverlap(const Material& material, double reducedRadius, double reducedMass,
                         double speed);
/// The approach speed whose head-on impact reaches the peak overlap `overlap` [m/s]: the
/// speed a contact of this material holds (the peak grows as v under Hooke, as v^(4/5) under
/// Hertz).
double speedForPeakOverlap(const Material& material, double reducedRadius, double reducedMass,
                           double overlap);

/// The shortest contact among the pairs a scene can produce: the smallest particle against a wall
/// and against another smallest particle (for Hooke these two have the same k/m; for Hertz the pair
/// is shorter). For Hertz, whose duration depends on the impact speed, `impactSpeed` [m/s] is the
/// largest approach speed expected; it is ignored for Hooke. With friction and the constant
/// tangential law, a contact's duration is the shorter of the normal force's and the tangential
/// spring's half-period π √(m_ij/(3.5 k_t)); with rolling resistance, also of the rolling
/// spring's half-period π √(I_r/k_r), k_r = β_r μ_r² k_n R_ij² and I_r the relative rotation's
/// inertia about the contact point ((7/5) m R² a sphere; infinite for a wall).
struct ContactScale {
  double duration = 0;       ///< force duration of the stiffest contact [s]
  double radius = 0;         ///< radius of the particle in that contact [m]
  bool againstWall = false;  ///< the stiffest contact is particle-wall (else particle-particle)
  /// The duration is a constant tangential spring's half-period (material.tangential_law =
  /// "constant"), shorter than the normal contact's.
  bool tangentialSpring = false;
  /// The duration is the rolling spring's half-period (material.rolling_friction > 0 with
  /// β_r μ_r² above about 1.6), shorter than the normal contact's.
  bool rollingSpring = false;
};
ContactScale stiffestContact(const Material& material, double smallestRadius, double impactSpeed);

/// The largest time step the core accepts, as a fraction of the stiffest contact's duration,
/// per integrator. Velocity Verlet is stable below duration·2/π ≈ 0.64·duration for one undamped
/// spring; 1/10 keeps a margin for a particle with many contacts and for damping (a settled
/// 144-sphere bed holds its energy at t_c/10, Hooke and Hertz, μ = 0.3, γn = 200 1/s). Gear's
/// predictor-corrector has a much smaller stability region once the force depends on the
/// velocity: the same bed gains energy under Gear at t_c/10 (Hooke, γn = 60 1/s) and up to t_c/40
/// (Hertz, γn = 200), and holds it at t_c/50 (bench/RESULTS.md, "Gear in a bed"). The usual
/// accurate range is 1/50 to 1/20 for Verlet, 1/50 and below for Gear.
inline constexpr double kMaxStepFractionVerlet = 0.1;
inline constexpr double kMaxStepFractionGear5 = 0.02;

/// The tangential dashpot F_t = −γt m_ij v_t of a sticking contact is an explicit damper, and
/// each integrator keeps a damper x'' = −λ x' stable only below a largest λΔt: Gear5 (with
/// c0 = 3/20) 0.1634, velocity Verlet (dashpots at the half-step velocity) exactly 2. Those are
/// the roots of the schemes' amplification matrices on x'' = −λ x' (docs/physics.md §2.7).
inline constexpr double kDamperStabilityGear5 = 0.163;
inline constexpr double kDamperStabilityVerlet = 2.0;
/// One contact's dashpot slows the contact-point velocity at the rate
/// γt m_ij (1/m_i + 1/m_j + a_i²/I_i + a_j²/I_j): translation and rotation of both spheres. For
/// solid spheres (I = (2/5) m R², lever arm a ≈ R) a²/I = 5/(2m), so the rate is (7/2) γt for any
/// two sizes and against a wall (m_j = I_j = ∞) alike.
inline constexpr double kTangentialRatePerContact = 3.5;
/// A bed's dashpots act together: the largest rate of the whole network (the largest eigenvalue
/// of M⁻¹C) was measured at 3.4 (the demo's 200 settled spheres) and 3.9 (the paper's 1980) times
/// one contact's; 6 allows for denser, compressed beds.
inline constexpr double kTangentialContactsAtOnce = 6.0;

}  // namespace granular
