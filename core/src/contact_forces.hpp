#pragma once
/// The contact law of design §2 for one contact, shared by particle pairs and particle-wall
/// contacts. Header-only so the force pass inlines it.
#include <algorithm>
#include <cmath>

#include "simulation_state.hpp"

namespace granular {

/// Constants of the law for a scene, computed once.
struct ContactConstants {
  double normalCoefficient;      ///< (2/3) E/(1-ν²) [Pa]
  double tangentialCoefficient;  ///< (8/3) G/(2-ν) [Pa]
  double normalDamping;          ///< γn [1/s]
  double tangentialDamping;      ///< γt [1/s]
  double friction;               ///< μ [-]
  double dt;                     ///< [s]
};

/// Normal elastic force magnitude k·R^(2-α)·h^α and its stored energy ∫ F dh.
template <NormalLaw kLaw>
inline double normalElasticForce(const ContactConstants& c, double radius, double overlap,
                                 double& energy) {
  if constexpr (kLaw == NormalLaw::Hooke) {
    const double f = c.normalCoefficient * radius * overlap;
    energy = 0.5 * f * overlap;
    return f;
  } else {
    const double f = c.normalCoefficient * std::sqrt(radius * overlap) * overlap;
    energy = 0.4 * f * overlap;
    return f;
  }
}

/// Tangential force of one contact (design §2): spring k_t ξ with k_t = (8/3) G sqrt(R h)/(2-ν)
/// plus dashpot γt m v_t, capped at the Coulomb limit μ F_n; while sliding, ξ is reset so that
/// the spring alone equals the limit. `advance` adds v_t Δt to ξ (the time step); without it the
/// force is evaluated for the stored ξ (measurements between steps).
template <bool kAdvance>
[[gnu::always_inline]] inline Vec3 tangentialForce(const ContactConstants& c,
                                                   TangentialHistory& history, const Vec3& n,
                                                   const Vec3& contactVelocity, double radius,
                                                   double overlap, double mass, double normalForce,
                                                   ContactPowers& powers) {
  const Vec3 vt = contactVelocity - contactVelocity.dot(n) * n;
  // Rotate the spring into the current tangent plane, keeping its length: the contact frame
  // turns with the particles, the stretch does not grow or shrink by it.
  Vec3 xi = history.stretch;
  const double length2 = xi.squaredNorm();
  if (length2 > 0.0) {
    xi -= xi.dot(n) * n;
    const double projected2 = xi.squaredNorm();
    xi *= projected2 > 0.0 ? std::sqrt(length2 / projected2) : 0.0;
  }
  const double kt = c.tangentialCoefficient * std::sqrt(radius * overlap);
  if constexpr (kAdvance) {
    powers.stiffnessWork += 0.5 * (kt - history.stiffness) * length2;
    xi += vt * c.dt;
  }
  Vec3 ft = -kt * xi - c.tangentialDamping * mass * vt;
  const double limit = c.friction * normalForce;
  const double ft2 = ft.squaredNorm();
  if (ft2 > limit * limit) {
    ft *= limit / std::sqrt(ft2);                   // gross sliding: Coulomb
    xi = kt > 0.0 ? Vec3(-ft / kt) : Vec3::Zero();  // the spring carries the whole limit
  } else {
    powers.tangentialDampingPower += c.tangentialDamping * mass * vt.squaredNorm();
  }
  powers.tangentialPower += ft.dot(vt);
  powers.elasticTangential += 0.5 * kt * xi.squaredNorm();
  ++powers.tangentialEvaluations;
  if constexpr (kAdvance) history = TangentialHistory{xi, kt};
  return ft;
}

}  // namespace granular
