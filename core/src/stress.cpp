/// Eq. (1) and Eq. (2) over the whole box (stress.hpp).
#include "granular/stress.hpp"

#include <algorithm>
#include <cmath>

#include "granular/error.hpp"

namespace granular {

Mat3 volumeAveragedStress(const Simulation& sim, double volume) {
  const Particles& p = sim.particles();
  Mat3 sum = Mat3::Zero();
  sim.forEachContact([&](const ContactView& c) {
    const Vec3 branch = c.point - p.position[c.particle];
    sum += c.force * branch.transpose();
  });
  return sum / volume;
}

BoxStress measureBox(const Simulation& sim, const std::vector<Vec3>& reactions) {
  const std::vector<Wall>& walls = sim.walls();
  auto reactionOf = [&](const char* name, bool required) -> Vec3 {
    const long w = sim.findWall(name);
    if (w < 0) {
      if (required)
        throw ConfigError(std::string("measureBox: the box has no wall '") + name + "'");
      return Vec3::Zero();
    }
    return reactions.empty() ? walls[w].reaction : reactions.at(w);
  };
  auto wallPoint = [&](const char* name) { return walls[sim.findWall(name)].point; };
  const Particles& p = sim.particles();
  const Vec3 g = sim.config().gravity;

  BoxStress b;
  const Vec3 xMinus = reactionOf("x-", true), xPlus = reactionOf("x+", true);
  const Vec3 yMinus = reactionOf("y-", true), yPlus = reactionOf("y+", true);
  const Vec3 bottom = reactionOf("bottom", true);
  const bool hasTop = sim.findWall("top") >= 0;
  const Vec3 top = reactionOf("top", false);

  b.lower = Vec3(wallPoint("x-").x(), wallPoint("y-").y(), wallPoint("bottom").z());
  double zTop = 0;
  if (hasTop) {
    zTop = wallPoint("top").z();
  } else {
    zTop = b.lower.z();
    for (std::size_t i = 0; i < p.size(); ++i)
      zTop = std::max(zTop, p.position[i].z() + p.radius[i]);
  }
  b.upper = Vec3(wallPoint("x+").x(), wallPoint("y+").y(), zTop);
  const Vec3 size = b.upper - b.lower;
  b.volume = size.prod();

  double mass = 0, massHeight = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    mass += p.mass[i];
    massHeight += p.mass[i] * (p.position[i].z() - b.lower.z());
  }
  b.weight = mass * g.norm();
  b.centreOfMassHeight = massHeight / mass;

  // Wall reactions are the particles' forces on the walls; the walls' forces on the particles
  // are their negatives.
  b.topForce = top.z();
  b.bottomForce = -bottom.z();
  b.sideMeanForce = 0.25 * (xMinus.norm() + xPlus.norm() + yMinus.norm() + yPlus.norm());
  b.sideVerticalForce = -(xMinus.z() + xPlus.z() + yMinus.z() + yPlus.z());
  b.balanceError = (b.bottomForce - b.topForce + b.sideVerticalForce - b.weight) / b.weight;

  b.eq1 = volumeAveragedStress(sim, b.volume);
  // Eq. (2): σ_ii = -(push on the + face + push on the - face) / 2 / A_i, compression negative.
  const double areaX = size.y() * size.z(), areaY = size.x() * size.z(),
               areaZ = size.x() * size.y();
  b.eq2.x() = -(xPlus.x() - xMinus.x()) / (2.0 * areaX);
  b.eq2.y() = -(yPlus.y() - yMinus.y()) / (2.0 * areaY);
  b.eq2.z() = -(top.z() - bottom.z()) / (2.0 * areaZ);
  b.sigma33CentreOfMassTerm = b.weight / areaZ * (0.5 - b.centreOfMassHeight / size.z());
  return b;
}

}  // namespace granular
