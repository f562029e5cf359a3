#pragma once
/// What the settled silo's section figures (silo_section_figures.hpp) show, measured on the
/// bed: the particles behind the cut y = 0, and the coarse-grained stress on the midsection
/// y = 0 with its σ1 trajectories.
#include <cstddef>
#include <vector>

#include "granular/simulation.hpp"
#include "granular/stress_field.hpp"

namespace granular::app {

/// The silo: a cylinder about the z axis through the origin, standing on a flat floor or on a
/// conical hopper.
struct SiloSectionGeometry {
  double radius = 0;  ///< the cylinder's [m]
  double floorZ = 0;  ///< the floor's height, or the hopper's outlet's [m]
  double top = 0;     ///< the bed's top, where the midsection ends (e.g. its highest particle) [m]
  /// A conical hopper's top, where it meets the cylinder, and its radius at floorZ [m]; a
  /// transition at or below the floor: a flat floor.
  double transition = 0;
  double outletRadius = 0;

  bool hasHopper() const { return transition > floorZ; }
  /// The wall's radius at height z [m]: the cone's below the transition.
  double wallRadius(double z) const {
    if (!hasHopper() || z >= transition) return radius;
    return outletRadius + (radius - outletRadius) * (z - floorZ) / (transition - floorZ);
  }
};

/// The particles whose centres lie behind the cut, y ≥ 0: the half of the bed a viewer on −y
/// sees once the front half is taken away. Indices into sim.particles(), ascending.
std::vector<std::size_t> particlesBehindCut(const Simulation& sim);

/// The coarse-grained stress on the midsection y = 0 (coarse_grain.hpp; compression negative).
/// Within a kernel width of the wall and the floor it falls off towards them: the kernel reaches
/// past them, where no material is, and spreads the stress there.
struct MidsectionStress {
  /// σ on a grid over x ∈ [−R, R], z ∈ [floor, top] of the plane y = 0 [Pa].
  PlaneField plane;
  double width = 0;  ///< the Lucy kernel's support radius c: two mean particle diameters [m]
  /// Trajectories of σ1, the most compressive principal stress of the in-plane tensor, traced
  /// downwards from a row three kernel widths below the top and a row at mid-depth [m].
  std::vector<std::vector<Vec3>> sigma1;

  /// −σ33 at grid point (i, k): the vertical stress with compression positive, as the silo
  /// study's σ_v [Pa].
  double verticalStress(int i, int k) const {
    return -plane.stress[std::size_t(k) * plane.nx + i](2, 2);
  }
};

/// Throws ConfigError for a geometry without a positive radius and a top above the floor.
MidsectionStress midsectionStress(const Simulation& settled, const SiloSectionGeometry& geometry);

}  // namespace granular::app
