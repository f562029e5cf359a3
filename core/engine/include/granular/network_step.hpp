#pragma once
/// The time step the live contact network allows (docs/physics.md §2.14–2.15): the bound on its
/// highest frequency (network_frequency.hpp) under the integrator's own stability interval at
/// the network's largest damping ratio.
#include <cstddef>

#include "granular/material.hpp"
#include "granular/simulation.hpp"

namespace granular {

/// The spectral radius of one step of `integrator`, as implemented (Gear5::predict/correct,
/// VelocityVerlet::drift/kick), on x'' = −ω² x − 2ζω x' at ω Δt = w: the step is a linear map
/// of the state (x, v, a[, x''', x'''', x''''']), built by stepping each unit vector.
double stepSpectralRadius(Integrator integrator, double w, double zeta);

/// The largest ω Δt at which one step of `integrator`, as implemented, on x'' = −ω² x − 2ζω x'
/// has spectral radius at most 1 + `growthPerStep` (Gear5 is never exactly stable undamped: its
/// growth per step is a power of ω Δt; velocity Verlet is, up to ω Δt = 2). Computed from the
/// step's linear map, by bisection to 10⁻⁶.
double stableOmegaDt(Integrator integrator, double zeta, double growthPerStep = 1e-9);

/// The largest ω Δt stable for every damping ratio in [ζ_lo, ζ_hi]: the smallest stableOmegaDt
/// over that range, on the grid (k/64)² widened outwards (so the answer only shortens), each grid
/// value computed once per process. A mode of the network at most at the frequency bound and
/// damped at most at the rates' bound, but at least as much as the least damped contact, is
/// then stable (physics.md §2.15: ζ·stableOmegaDt(ζ) grows with ζ, so the modes damped more
/// than the corner's ratio are covered too). What the step control calls at every check.
double stableOmegaDtOver(Integrator integrator, double zetaLow, double zetaHigh);

/// The step the network allows now and what sets it.
struct NetworkStep {
  double dt = 0;            ///< stableOmegaDt(ζ) / ω_max [s]; +∞ with no contacts
  double omegaMax = 0;      ///< the network's frequency bound [rad/s]
  double zeta = 0;          ///< Γ / (2 ω_max): the bound's damping ratio (NetworkFrequency)
  double smallestZeta = 0;  ///< the least damped contact mode's ratio
  std::size_t particle = 0;
};
/// With `lookahead` [s]: contacts about to form count too (networkFrequencyBound).
NetworkStep networkStableStep(const Simulation& sim, double lookahead = 0.0);

/// The step the contact network of a dense bed of the scene's smallest spheres allows, for a
/// scene that starts without contacts: a face-centred cubic block of 108 spheres of radius
/// `smallestRadius` (the densest packing: 12 contacts a sphere, more than any random bed's 6 or
/// so) touching each other and a floor, at rest, with `config`'s material, under Hertz's law at
/// the overlap of an impact at config.impactSpeed. What the stiffest binary contact's duration
/// does not see, the rates of the rolling dashpots on the spheres' own rotational inertia, which
/// shrink Gear's interval, it does: the scene loader judges a fixed step of a scene with rolling
/// resistance by it. The network's step [s] and what sets it.
NetworkStep denseBedStep(const SimulationConfig& config, double smallestRadius);

}  // namespace granular
