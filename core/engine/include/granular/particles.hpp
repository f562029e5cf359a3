#pragma once
/// The particles as a struct of arrays, addressed by integer index (docs/architecture.md §3).
#include <cstddef>
#include <vector>

#include "granular/vec3.hpp"

namespace granular {

/// Per-particle state. Hot arrays (position, velocity, force) are kept apart from cold ones
/// (radius, mass). The integrator's higher time derivatives live in `Simulation`, not here.
struct Particles {
  std::vector<Vec3> position;         ///< centre x_i [m]
  std::vector<Vec3> velocity;         ///< v_i [m/s]
  std::vector<Vec3> angularVelocity;  ///< ω_i [rad/s]
  std::vector<double> radius;         ///< R_i [m]
  std::vector<double> mass;           ///< m_i [kg]

  std::size_t size() const { return position.size(); }
  /// Appends a particle of the given density; returns its index.
  std::size_t add(const Vec3& x, double r, double density, const Vec3& v = Vec3::Zero());
  /// I = (2/5) m R² of particle i [kg m²].
  double inertia(std::size_t i) const { return 0.4 * mass[i] * radius[i] * radius[i]; }
};

}  // namespace granular
