#pragma once
/// Small scenes for the physics tests: binary impacts and their measurement.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "granular/impact_probe.hpp"
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
  const ImpactMeasurement traced = traceContact(
      sim, [&overlap](const Simulation& s) { return overlap(s); }, maxTime);
  MeasuredImpact m;
  m.peakOverlap = traced.peakOverlap;
  m.overlapDuration = traced.overlapDuration;
  m.velocityAfter = sim.particles().velocity[particle];
  m.angularVelocityAfter = sim.particles().angularVelocity[particle];
  m.restitution = m.velocityAfter.dot(normal) / approachSpeed;
  return m;
}

}  // namespace granular::testing

namespace granular::testing {

/// A box of side `side` with walls on all faces but the top, and nx·ny·nz particles on a grid of
/// cubic cells 0.1 m above its floor, radii uniform in [0.03, 0.035] m and random velocities up
/// to `speed` m/s: a small version of the paper's stage 1.
inline Simulation fallingGrid(int nx, int ny, int nz, const SimulationConfig& cfg, double speed,
                              unsigned seed = 7) {
  const double cell = 0.1, side = nx * cell;
  std::uint64_t state = seed * 0x9E3779B97F4A7C15ULL + 1;
  auto uniform = [&state]() {  // splitmix64: reproducible on every platform
    state += 0x9E3779B97F4A7C15ULL;
    std::uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  };
  Particles p;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const Vec3 x((i + 0.5) * cell, (j + 0.5) * cell, (k + 0.5) * cell);
        // One draw per statement (argument order is unspecified); z, y, x as GCC evaluated it.
        const double vz = uniform() - 0.5, vy = uniform() - 0.5, vx = uniform() - 0.5;
        const Vec3 v = speed * Vec3(vx, vy, vz);
        p.add(x, 0.03 + 0.005 * uniform(), cfg.material.density, v);
      }
    }
  }
  std::vector<Wall> walls = {
      {"x-", Vec3(0, 0, 0), Vec3(1, 0, 0)},     {"x+", Vec3(side, 0, 0), Vec3(-1, 0, 0)},
      {"y-", Vec3(0, 0, 0), Vec3(0, 1, 0)},     {"y+", Vec3(0, side, 0), Vec3(0, -1, 0)},
      {"bottom", Vec3(0, 0, 0), Vec3(0, 0, 1)},
  };
  return Simulation(std::move(p), std::move(walls), cfg);
}

/// A Hertz bed (μ = 0.3, γn = 200) of nx × ny × nz spheres fallen and settled for 2.5 s at an
/// automatic velocity-Verlet step on `threads` threads: at rest its accuracy floor stretches, and
/// the step comes from the network's spectrum (its estimate, docs/physics.md §2.16).
inline Simulation settledAutomaticBed(int nx = 3, int ny = 3, int nz = 3, int threads = 0,
                                      Integrator integrator = Integrator::VelocityVerlet) {
  SimulationConfig cfg;
  cfg.material.normalLaw = NormalLaw::Hertz;
  cfg.material.friction = 0.3;
  cfg.material.normalDamping = 200.0;
  cfg.integrator = integrator;
  cfg.impactSpeed = 3.0;
  cfg.step.automatic = true;
  cfg.threads = threads;
  Simulation sim = fallingGrid(nx, ny, nz, cfg, 0.3);
  sim.advanceTo(2.5);
  return sim;
}

/// A bed at rest: after `settle` seconds, over the next `watch`, the largest kinetic energy
/// and the largest move of the ledger's total, each as a fraction of gravity's work so far.
struct RestingBed {
  EnergyBalance settled;
  double kinetic = 0, moved = 0;  ///< [-] of |gravity's work|
};
inline RestingBed watchAtRest(Simulation& sim, double settle, double watch) {
  while (sim.time() < settle) sim.step();
  RestingBed bed{sim.energy()};
  while (sim.time() < settle + watch) {
    sim.step();
    const EnergyBalance e = sim.energy();
    bed.kinetic = std::max(bed.kinetic, e.kineticTranslational + e.kineticRotational);
    bed.moved = std::max(bed.moved, std::abs(e.total() - bed.settled.total()));
  }
  const double scale = std::abs(bed.settled.gravityWork);
  bed.kinetic /= scale;
  bed.moved /= scale;
  return bed;
}

}  // namespace granular::testing
