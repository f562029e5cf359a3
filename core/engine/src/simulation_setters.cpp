/// The setters that re-shape a running simulation: its skin, walls, step, step control,
/// contact law and integrator. A change they refuse (ConfigError, TimeStepError) leaves the
/// state as it was.
#include <algorithm>
#include <cmath>

#include "config_validation.hpp"
#include "force_pass.hpp"
#include "simulation_passes.hpp"
#include "simulation_state.hpp"
#include "step_check.hpp"
#include "wall_motion.hpp"

namespace granular {

void Simulation::setSkin(double skin) {
  requireConfig(std::isfinite(skin) && skin >= 0,
                "skin = " + shortNumber(skin) + " m: must be >= 0");
  SimulationState& s = *state_;
  const Particles& p = s.particles;
  const double rMin = smallestRadius(p, s.config);
  s.config.skin = skin;
  s.neighbours.skin = skin > 0 ? skin : 0.3 * rMin;
  s.neighbours.valid = false;  // rebuilt (history kept) at the next step
}

std::size_t Simulation::addWall(const Wall& wall) {
  validateWall(wall);
  SimulationState& s = *state_;
  requireWallFrictionWithin({wall}, s.config.material);
  s.walls.push_back(wall);
  s.neighbours.valid = false;  // the new wall needs its candidate list
  rebuildList(s);
  return s.walls.size() - 1;
}

void Simulation::setTimeStep(double dt) {
  requireConfig(std::isfinite(dt) && dt > 0, "time step = " + shortNumber(dt) + " s: must be > 0");
  SimulationState& s = *state_;
  if (!s.stepLimitDisabled && !s.config.step.automatic) {
    requireAllowedStep(s, dt, s.config.integrator);
  }
  s.targetStep = dt;
  changeStep(s, dt);
}

void Simulation::setStepControl(const StepControl& control) {
  validateStepControl(control);
  SimulationState& s = *state_;
  const StepControl before = s.config.step;
  s.config.step = control;
  try {
    if (control.automatic) {
      checkStep(s);
    } else if (!s.stepLimitDisabled) {
      requireAllowedStep(s, targetStep(s), s.config.integrator);
    }
  } catch (...) {
    s.config.step = before;
    throw;
  }
}

void Simulation::setMaterial(const Material& material) {
  SimulationState& s = *state_;
  const Material& now = s.config.material;
  if (sameMaterial(material, now)) {
    return;  // nothing changes, not even the bits
  }
  validateMaterial(material);
  requireWallFrictionWithin(s.walls, material);
  const Particles& p = s.particles;
  const double rMin = smallestRadius(p, s.config);
  const ContactScale scale = stiffestContact(material, rMin, s.config.impactSpeed);
  if (!s.stepLimitDisabled && !s.config.step.automatic) {
    if (material.hasFriction() == s.frictional) {
      // The network under the new law (the contacts are where they are).
      const Material current = s.config.material;
      const ContactScale currentScale = s.contactScale;
      s.config.material = material;
      s.contactScale = scale;
      try {
        requireAllowedStep(s, targetStep(s), s.config.integrator);
      } catch (...) {
        s.config.material = current;
        s.contactScale = currentScale;
        throw;
      }
      s.config.material = current;
      s.contactScale = currentScale;
    } else {
      // Rotations come or go: the binary contacts' limit, as with no contact.
      requireStableStep(targetStep(s), scale, s.config.integrator);
      requireStableTangentialDamping(material, targetStep(s), s.config.integrator);
    }
  }
  // Accepted: nothing above has changed the state.
  const double reachBefore = reachBeyondTouch(s.config.material);
  s.config.material = material;
  s.contactScale = scale;
  const std::size_t n = p.size();
  if (material.hasFriction() != s.frictional) {
    s.frictional = material.hasFriction();
    if (s.frictional) {  // rotations start at rest, springs unstretched, as in a new run
      s.rotation.d2.assign(n, Vec3::Zero());
      if (s.config.integrator == Integrator::Gear5) {
        for (std::vector<Vec3>* d : {&s.rotation.d3, &s.rotation.d4, &s.rotation.d5}) {
          d->assign(n, Vec3::Zero());
        }
      }
    } else {  // the frictionless path has no rotations
      s.rotation = Derivatives{};
      std::vector<Vec3>().swap(s.torque);
      s.particles.angularVelocity.assign(n, Vec3::Zero());
    }
    // A list built for the other path holds no springs (or ones no longer wanted): start anew.
    NeighbourList& list = s.neighbours;
    for (std::vector<std::uint32_t>* v : {&list.rowStart, &list.second}) v->clear();
    list.springs = PairSprings{};
    list.wallParticles.clear();
    list.wallHistory.clear();
    list.wallNormal.clear();
    list.meshTriangleStart.clear();
    list.meshTriangles.clear();
    rebuildList(s);
  } else if (reachBeyondTouch(material) != reachBefore) {
    rebuildList(s);  // the pairs within the new reach
  }
  // The accelerations under the new law, as a new simulation starts (springs kept: dt = 0).
  computeContactForces(s, 0.0);
  startAccelerations(s);
  if (s.config.step.automatic) checkStep(s);  // the step for the new law
}

void Simulation::setIntegrator(Integrator integrator) {
  SimulationState& s = *state_;
  if (integrator == s.config.integrator) return;
  if (!s.stepLimitDisabled && !s.config.step.automatic) {
    requireAllowedStep(s, targetStep(s), integrator);
  }
  const std::size_t n = s.particles.size();
  for (Derivatives* d : {&s.translation, &s.rotation}) {
    if (d->d2.empty()) continue;  // no rotations on the frictionless path
    for (std::vector<Vec3>* higher : {&d->d3, &d->d4, &d->d5}) {
      if (integrator == Integrator::Gear5) {
        higher->assign(n, Vec3::Zero());
      } else {
        std::vector<Vec3>().swap(*higher);  // Verlet keeps only the acceleration
      }
    }
  }
  s.config.integrator = integrator;
  if (s.config.step.automatic) checkStep(s);  // the new integrator's interval
}

}  // namespace granular
