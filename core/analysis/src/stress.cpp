/// Eq. (1) and Eq. (2) over the whole box (stress.hpp).
#include "granular/stress.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>
#include <utility>

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

ParticleMeasures particleMeasures(const Simulation& sim) {
  const Particles& p = sim.particles();
  ParticleMeasures m;
  m.stresses.assign(p.size(), Mat3::Zero());
  m.forceSums.assign(p.size(), 0.0);
  sim.forEachContact([&](const ContactView& c) {
    m.stresses[c.particle] += c.force * (c.point - p.position[c.particle]).transpose();
    m.forceSums[c.particle] += c.force.norm();
  });
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r = p.radius[i];
    m.stresses[i] /= 4.0 / 3.0 * std::numbers::pi * r * r * r;
  }
  return m;
}

std::vector<Mat3> particleStresses(const Simulation& sim) {
  return particleMeasures(sim).stresses;
}

namespace {

/// Lower and upper corners of the box: the side walls and floor, and the top wall or, without
/// one, the highest particle surface.
std::pair<Vec3, Vec3> boxCorners(const Simulation& sim) {
  auto point = [&](const char* name) {
    const long w = sim.findWall(name);
    if (w < 0) throw ConfigError(std::string("measureBox: the box has no wall '") + name + "'");
    return sim.walls()[w].point;
  };
  const Vec3 lower(point("x-").x(), point("y-").y(), point("bottom").z());
  double zTop = lower.z();
  if (sim.findWall("top") >= 0) {
    zTop = point("top").z();
  } else {
    const Particles& p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i)
      zTop = std::max(zTop, p.position[i].z() + p.radius[i]);
  }
  return {lower, Vec3(point("x+").x(), point("y+").y(), zTop)};
}

}  // namespace

std::vector<double> particleForceSums(const Simulation& sim) {
  return particleMeasures(sim).forceSums;
}

BoxContactSums boxContactSums(const Simulation& sim) {
  const auto [lower, upper] = boxCorners(sim);
  std::vector<bool> side(sim.walls().size(), false);
  for (const char* name : {"x-", "x+", "y-", "y+"}) side[sim.findWall(name)] = true;
  const Particles& p = sim.particles();
  BoxContactSums sums;
  Mat3 sum = Mat3::Zero();
  // `lower` is captured by copy explicitly: clang before 16 cannot capture a structured binding.
  sim.forEachContact([&, lower = lower](const ContactView& c) {
    sum += c.force * (c.point - p.position[c.particle]).transpose();
    if (c.isWall() && side[c.wall()]) {
      sums.sideFrictionMoment += c.force.z() * (c.point.z() - lower.z());
    }
  });
  sums.eq1 = sum / (upper - lower).prod();
  return sums;
}

BoxStress meanBoxStress(const std::vector<BoxStress>& samples) {
  BoxStress m;
  if (samples.empty()) return m;
  const double w = 1.0 / static_cast<double>(samples.size());
  for (const BoxStress& b : samples) {
    m.lower += w * b.lower;
    m.upper += w * b.upper;
    m.volume += w * b.volume;
    m.weight += w * b.weight;
    m.topForce += w * b.topForce;
    m.bottomForce += w * b.bottomForce;
    m.sideMeanForce += w * b.sideMeanForce;
    m.sideVerticalForce += w * b.sideVerticalForce;
    m.balanceError += w * b.balanceError;
    m.eq1 += w * b.eq1;
    m.eq2 += w * b.eq2;
    m.centreOfMassHeight += w * b.centreOfMassHeight;
    m.sigma33CentreOfMassTerm += w * b.sigma33CentreOfMassTerm;
    m.sigma33SideFrictionTerm += w * b.sigma33SideFrictionTerm;
    m.sideFrictionMoment += w * b.sideFrictionMoment;
  }
  return m;
}

BoxStress measureBox(const Simulation& sim, const std::vector<Vec3>& reactions,
                     const BoxContactSums* sums) {
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
  const Particles& p = sim.particles();
  const Vec3 g = sim.config().gravity;

  BoxStress b;
  const Vec3 xMinus = reactionOf("x-", true), xPlus = reactionOf("x+", true);
  const Vec3 yMinus = reactionOf("y-", true), yPlus = reactionOf("y+", true);
  const Vec3 bottom = reactionOf("bottom", true);
  const Vec3 top = reactionOf("top", false);

  std::tie(b.lower, b.upper) = boxCorners(sim);
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

  const BoxContactSums now = sums ? BoxContactSums{} : boxContactSums(sim);
  const BoxContactSums& contact = sums ? *sums : now;
  b.eq1 = contact.eq1;
  b.sideFrictionMoment = contact.sideFrictionMoment;
  // Eq. (2): σ_ii = -(push on the + face + push on the - face) / 2 / A_i, compression negative.
  const double areaX = size.y() * size.z(), areaY = size.x() * size.z(),
               areaZ = size.x() * size.y();
  b.eq2.x() = -(xPlus.x() - xMinus.x()) / (2.0 * areaX);
  b.eq2.y() = -(yPlus.y() - yMinus.y()) / (2.0 * areaY);
  b.eq2.z() = -(top.z() - bottom.z()) / (2.0 * areaZ);
  b.sigma33CentreOfMassTerm = b.weight / areaZ * (0.5 - b.centreOfMassHeight / size.z());
  b.sigma33SideFrictionTerm = (b.sideFrictionMoment / size.z() - 0.5 * b.sideVerticalForce) / areaZ;
  return b;
}

}  // namespace granular
