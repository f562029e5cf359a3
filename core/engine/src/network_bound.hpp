#pragma once
/// The network's frequency bound on the engine's state (network_frequency.cpp; its contacts,
/// network_contacts.cpp; their motion, network_motion.cpp), for the step control inside the
/// step (simulation.cpp).
#include <cstddef>
#include <functional>

#include "contact_constants.hpp"
#include "granular/network_frequency.hpp"
#include "granular/network_spectrum.hpp"
#include "granular/network_step.hpp"

namespace granular {

struct SimulationState;

/// One contact of the linearised network: bodies i and j (j = i: a wall), the unit normal from
/// i towards j (into the wall), R_ij [m], m_ij [kg], the overlap it is linearised at [m] (under
/// Hertz's law with the overlap a head-on impact at its closing speed adds), that closing speed
/// [m/s], whether it touches now (else a candidate about to touch), and the speed of its bodies'
/// centres relative to each other (to the wall's point) [m/s], sliding and separating included.
struct NetworkContact {
  std::size_t i = 0, j = 0;
  Vec3 normal;
  double reduced = 0, mass = 0, overlap = 0, approach = 0;
  bool touching = true;
  double relativeSpeed = 0;
};
/// Calls `visit` for every touching contact (a pair from its first side) and, with `lookahead`
/// > 0 [s], every neighbour-list candidate (pair or wall) that closes its gap within it at its
/// present closing speed: the contacts the bound and the estimate count, on one thread, in the
/// order NetworkWalk (network_contacts.hpp) gives.
void visitNetworkContacts(const SimulationState& s, double lookahead,
                          const std::function<void(const NetworkContact&)>& visit);
/// A network contact's springs and dashpots on its modes (contact_linearisation.hpp), with the
/// relative rotation's inertia of its bodies.
LinearContact linearisedContact(const SimulationState& s, const NetworkContact& n,
                                const ContactConstants& constants, unsigned optional);
/// What the step control's accuracy floor reads, without the bound: the contacts counted
/// (touching and, within `lookahead` [s], about to touch), their fastest approach and the
/// kinetic energy of their relative motion (NetworkFrequency's fields of those names; the
/// frequencies left 0). Collective in a split run. A pass over the contacts alone: a fraction
/// of a check's cost.
NetworkFrequency networkMotion(const SimulationState& s, double lookahead);
/// With `enough`, the sweeps stop as soon as it holds for the bound so far (every sweep's bound
/// is an upper bound: stopping early only gives away tightness that was not needed).
NetworkFrequency networkFrequencyBound(const SimulationState& s, int sweeps, double lookahead,
                                       const std::function<bool(const NetworkFrequency&)>& enough);
NetworkStep networkStableStep(const SimulationState& s, double lookahead);
/// networkSpectrumEstimate (granular/network_spectrum.hpp) on the engine's state, capped by
/// `bound`, a bound on the same contacts (the same `lookahead`) that the caller has already.
NetworkSpectrum networkSpectrumEstimate(const SimulationState& s, double lookahead,
                                        const NetworkFrequency& bound, NetworkSpectrumStart* start,
                                        int iterations, double tolerance);
/// The step a bound allows `integrator`: its interval over the bound's damping ratios, over
/// ω_max (+∞ with no contacts).
double networkStepOf(Integrator integrator, const NetworkFrequency& f);

}  // namespace granular
