/// The settled silo's sections (silo_sections.hpp).
#include "silo_sections.hpp"

#include <algorithm>
#include <cmath>

#include "granular/coarse_grain.hpp"
#include "granular/error.hpp"

namespace granular::app {

namespace {

double meanDiameter(const Particles& p) {
  double sum = 0;
  for (std::size_t i = 0; i < p.size(); ++i) sum += 2.0 * p.radius[i];
  return p.size() > 0 ? sum / double(p.size()) : 0.0;
}

/// Grid points along a side `length` long at a quarter of the kernel width apart (the field
/// varies over the width, so four points resolve it), within bounds that keep a small bed
/// legible and a tall one quick.
int gridPoints(double length, double width, int most) {
  return std::clamp(static_cast<int>(std::lround(4.0 * length / width)) + 1, 21, most);
}

}  // namespace

std::vector<std::size_t> particlesBehindCut(const Simulation& sim) {
  const Particles& p = sim.particles();
  std::vector<std::size_t> behind;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.position[i].y() >= 0.0) behind.push_back(i);
  }
  return behind;
}

MidsectionStress midsectionStress(const Simulation& sim, const SiloSectionGeometry& g) {
  if (!(g.radius > 0) || !(g.top > g.floorZ)) {
    throw ConfigError("silo sections: need a radius > 0 and a top above the floor");
  }
  const double d = meanDiameter(sim.particles());
  MidsectionStress out;
  // Two diameters: the stress of a few dozen particles around each point, smooth enough for
  // principal directions, still several kernel widths across even a narrow silo.
  out.width = d > 0 ? 2.0 * d : 0.1 * g.radius;
  PlaneField& plane = out.plane;
  plane.xMin = -g.radius;
  plane.xMax = g.radius;
  plane.zMin = g.floorZ;
  plane.zMax = g.top;
  plane.y = 0.0;
  plane.nx = gridPoints(2.0 * g.radius, out.width, 81);
  plane.nz = gridPoints(g.top - g.floorZ, out.width, 161);
  plane.stress.assign(std::size_t(plane.nx) * plane.nz, Mat3::Zero());
  const CoarseGrainer cg(sim, out.width);
  for (int k = 0; k < plane.nz; ++k) {
    for (int i = 0; i < plane.nx; ++i) {
      plane.stress[std::size_t(k) * plane.nx + i] = cg.at(plane.point(i, k)).stress();
    }
  }

  // Downwards, as the weight travels: from three kernel widths below the top, where the stress
  // is the weight of a few layers and its direction no longer the surface's noise, and from
  // mid-depth, which fills the lower half where lines from above have stopped or converged.
  const double height = g.top - g.floorZ;
  std::vector<Vec3> starts;
  for (double z : {g.top - std::min(3.0 * out.width, 0.3 * height), g.floorZ + 0.5 * height}) {
    for (int s = 1; s <= 11; ++s) starts.emplace_back(-g.radius + s * g.radius / 6.0, 0.0, z);
  }
  out.sigma1 = principalTrajectories(plane, starts, g.radius / 100.0, -Vec3::UnitZ(), 0.05);
  return out;
}

}  // namespace granular::app
