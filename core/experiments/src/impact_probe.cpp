/// The two-sphere impact probe (impact_probe.hpp).
#include "granular/impact_probe.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace granular {

double pairReducedRadius(const PairImpactSpec& spec) {
  return 0.5 * spec.radius;
}

double pairReducedMass(const PairImpactSpec& spec) {
  const double r = spec.radius;
  return 0.5 * spec.material.density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
}

std::optional<ImpactPrediction> predictPairImpact(const PairImpactSpec& spec) {
  const Material& mat = spec.material;
  const double radius = pairReducedRadius(spec), mass = pairReducedMass(spec);
  if (mat.normalLaw == NormalLaw::Hooke) {
    const auto impact = mat.noPull ? hookeDampedImpact : hookeDampedImpactWithPull;
    return impact(mat.normalCoefficient() * radius, mat.normalDamping, mass, spec.approachSpeed);
  }
  if (mat.normalDamping == 0.0) {
    return hertzUndampedImpact(mat.normalCoefficient() * std::sqrt(radius), mass,
                               spec.approachSpeed);
  }
  return std::nullopt;
}

double gapForTouchPhase(const PairImpactSpec& spec, double phase) {
  return spec.approachSpeed * spec.timeStep * (2.0 + phase);  // the gap closes at that speed
}

Simulation makePairImpact(const PairImpactSpec& spec) {
  const double r = spec.radius, offset = r + 0.5 * spec.initialGap;
  Particles p;
  p.add(Vec3(-offset, 0, 0), r, spec.material.density, Vec3(0.5 * spec.approachSpeed, 0, 0));
  p.add(Vec3(offset, 0, 0), r, spec.material.density, Vec3(-0.5 * spec.approachSpeed, 0, 0));
  SimulationConfig cfg;
  cfg.material = spec.material;
  cfg.gravity = Vec3::Zero();
  cfg.integrator = spec.integrator;
  cfg.timeStep = spec.timeStep;
  cfg.impactSpeed = spec.approachSpeed;
  cfg.threads = 1;
  return Simulation(std::move(p), {}, cfg);
}

ImpactMeasurement traceContact(Simulation& sim,
                               const std::function<double(const Simulation&)>& overlap,
                               double maxTime) {
  ImpactMeasurement m;
  double previous = overlap(sim), previousTime = sim.time(), start = -1.0;
  while (sim.time() < maxTime) {
    sim.step();
    ++m.steps;
    const double h = overlap(sim), t = sim.time();
    m.peakOverlap = std::max(m.peakOverlap, h);
    // The overlap is linear in time while no force acts, so these crossings are exact when
    // the neighbouring step end lies in free flight.
    if (start < 0.0 && previous <= 0.0 && h > 0.0) {
      start = previousTime + (t - previousTime) * (-previous) / (h - previous);
    } else if (start >= 0.0 && previous > 0.0 && h <= 0.0) {
      m.overlapDuration = previousTime + (t - previousTime) * previous / (previous - h) - start;
      m.separated = true;
      break;
    }
    previous = h;
    previousTime = t;
  }
  return m;
}

ImpactMeasurement measurePairImpact(Simulation& sim, double approachSpeed, double maxTime) {
  ImpactMeasurement m = traceContact(
      sim,
      [](const Simulation& s) {
        const Particles& p = s.particles();
        return p.radius[0] + p.radius[1] - (p.position[1] - p.position[0]).norm();
      },
      maxTime);
  const Particles& p = sim.particles();
  const Vec3 normal = (p.position[1] - p.position[0]).normalized();
  m.restitution = (p.velocity[1] - p.velocity[0]).dot(normal) / approachSpeed;
  return m;
}

}  // namespace granular
