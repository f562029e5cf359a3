/// The binary contact's limits on the step and on the tangential damping (granular/simulation.hpp):
/// the engine's fallback while there is no contact, and the scene loader's check.
#include <sstream>

#include "config_validation.hpp"
#include "granular/error.hpp"
#include "granular/simulation.hpp"

namespace granular {

double maxStableStep(const ContactScale& scale, Integrator integrator) {
  const double fraction =
      integrator == Integrator::Gear5 ? kMaxStepFractionGear5 : kMaxStepFractionVerlet;
  return fraction * scale.duration;
}

void requireStableStep(double dt, const ContactScale& scale, Integrator integrator) {
  const double limit = maxStableStep(scale, integrator);
  if (!(dt <= limit)) {
    const bool gear = integrator == Integrator::Gear5;
    std::ostringstream msg;
    msg << "time step " << dt << " s is above the stable limit " << limit << " s of "
        << (gear ? "gear5" : "velocity Verlet") << " = 1/" << (gear ? 50 : 10);
    if (scale.tangentialSpring) {
      msg << " of the half-period " << shortNumber(scale.duration)
          << " s of a sticking contact's constant tangential spring (the stiffest: radius ";
    } else if (scale.rollingSpring) {
      msg << " of the half-period " << shortNumber(scale.duration)
          << " s of a contact's rolling spring (k_r = β_r μ_r² k_n R_ij², shorter than the "
             "normal contact's duration; the stiffest: radius ";
    } else {
      msg << " of the contact duration " << shortNumber(scale.duration)
          << " s of the stiffest contact (radius ";
    }
    msg << scale.radius << " m "
        << (scale.againstWall ? "against a wall" : "against an equal particle") << "); use at most "
        << limit << " s"
        << (gear ? " (Gear gains energy in a damped bed above it), or velocity Verlet up to 1/10"
                 : " (1/50 to 1/20 of the duration is usual)");
    throw TimeStepError(msg.str());
  }
}

double maxTangentialDamping(double dt, Integrator integrator) {
  const double stability =
      integrator == Integrator::Gear5 ? kDamperStabilityGear5 : kDamperStabilityVerlet;
  return stability / (kTangentialContactsAtOnce * kTangentialRatePerContact * dt);
}

void requireStableTangentialDamping(const Material& material, double dt, Integrator integrator) {
  if (!material.hasFriction()) return;  // no tangential force: γt acts on nothing
  const double limit = maxTangentialDamping(dt, integrator);
  if (!(material.tangentialDamping <= limit)) {
    const bool gear = integrator == Integrator::Gear5;
    std::ostringstream msg;
    msg << "tangential damping " << material.tangentialDamping << " 1/s is above the stable limit "
        << limit << " 1/s at the time step " << dt << " s of "
        << (gear ? "gear5" : "velocity Verlet")
        << ": a sticking contact's dashpot slows it at 3.5 γt, a bed's contacts act together (up "
           "to 6 at once) and "
        << (gear ? "gear5" : "velocity Verlet") << " keeps a damper stable only for rate·Δt <= "
        << (gear ? kDamperStabilityGear5 : kDamperStabilityVerlet) << "; use at most " << limit
        << " 1/s or a smaller time step";
    throw ConfigError(msg.str());
  }
}

}  // namespace granular
