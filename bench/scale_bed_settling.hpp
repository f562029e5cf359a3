#pragma once
/// How granular_bench_scale and granular_bench_ranks settle their bed before timing it: the same
/// rule in both, so that both time the same bed.
#include "granular/simulation.hpp"

namespace granular::bench {

/// The settling run's configuration from the timed run's `timed`: its step and friction, with a
/// near-critical normal damping (γn = 400 1/s, ζ ≈ 0.6 for a mean pair, instead of the paper's
/// 60 1/s; the paper's soft, springy bed bounces as a whole for half a second, which would leave
/// the contact count depending on the moment the timing starts) and velocity Verlet whatever
/// the timed integrator. Gear5's stability interval shrinks as the damping grows: at this γn the
/// contact network's bound has a damping ratio near 1.4 (docs/physics.md §2.15), where Gear5 is
/// stable for ω Δt ≤ 0.057 only, and the engine stops Gear5 at the timed step of 10⁻⁴ s a few
/// hundred steps into the settling; velocity Verlet's interval there is 0.34, six times longer.
inline SimulationConfig settlingConfig(SimulationConfig timed) {
  timed.material.normalDamping = 400.0;
  timed.integrator = Integrator::VelocityVerlet;
  return timed;
}

}  // namespace granular::bench
