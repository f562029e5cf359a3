#pragma once
/// Small scenes for the physics tests: binary impacts and their measurement.
#include <cmath>
#include <numbers>

#include "granular/simulation.hpp"

namespace granular::testing {

inline double sphereMass(double r, double density) {
  return density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
}

/// What a binary impact produced, measured from the trajectory.
struct MeasuredImpact {
  double overlapDuration = 0;  ///< between the interpolated zero crossings of the overlap [s]
  double restitution = 0;      ///< rebound / approach normal speed [-]
  double peakOverlap = 0;      ///< [m]
  Vec3 velocityAfter = Vec3::Zero();
  Vec3 angularVelocityAfter = Vec3::Zero();
};

/// Steps `sim` until the overlap function (positive while in contact) has gone positive and back
/// to negative, and measures the contact from the trajectory.
template <class Overlap>
MeasuredImpact measureImpact(Simulation& sim, Overlap overlap, double approachSpeed,
                             std::size_t particle, const Vec3& normal, double maxTime) {
  MeasuredImpact m;
  double previous = overlap(sim), previousTime = sim.time();
  double start = -1.0;
  while (sim.time() < maxTime) {
    sim.step();
    const double h = overlap(sim);
    m.peakOverlap = std::max(m.peakOverlap, h);
    if (previous <= 0.0 && h > 0.0) {
      start = previousTime + (sim.time() - previousTime) * (-previous) / (h - previous);
    }
    if (start >= 0.0 && previous > 0.0 && h <= 0.0) {
      const double end = previousTime + (sim.time() - previousTime) * previous / (previous - h);
      m.overlapDuration = end - start;
      break;
    }
    previous = h;
    previousTime = sim.time();
  }
  m.velocityAfter = sim.particles().velocity[particle];
  m.angularVelocityAfter = sim.particles().angularVelocity[particle];
  m.restitution = m.velocityAfter.dot(normal) / approachSpeed;
  return m;
}

}  // namespace granular::testing
