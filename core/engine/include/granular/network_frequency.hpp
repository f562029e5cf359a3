#pragma once
/// The highest eigenfrequency of the live contact network, bounded from above (docs/physics.md
/// §2.14): the contacts as linear springs about the current state (normal k_n = dF_n/dh,
/// tangential k_t at the contact points where friction is on, rolling k_r where rolling
/// resistance is on), the particles as rigid bodies (translations; rotations with friction).
/// The bound is the block Gershgorin bound of the mass-weighted stiffness matrix
/// A = M^(-1/2) K M^(-1/2), computed contact by contact in O(contacts); tests check it against
/// the exact spectrum (tests/test_network_frequency.cpp). It is the basis of a step chosen from
/// the network rather than from the stiffest binary contact.
#include <cstddef>

#include "granular/contact_terms/term.hpp"
#include "granular/material.hpp"
#include "granular/simulation.hpp"

namespace granular {

/// The linear stiffnesses of one contact at overlap h [m] between bodies of reduced radius R_ij
/// [m] (a wall contact: R_i): normal k_n = dF_n^e/dh [N/m]; tangential k_t [N/m] (0 without
/// friction); rolling k_r [N m/rad] (0 without rolling resistance).
using ContactStiffness = ContactModes;
ContactStiffness contactStiffness(const Material& material, double reducedRadius, double overlap);

/// One body of a contact as the linearised network sees it: its mass [kg], moment of inertia
/// [kg m²] and the lever arm R − h/2 of the contact point [m].
struct ContactBody {
  double mass = 0, inertia = 0, arm = 0;
};

/// ‖G‖ for one body of a contact: the largest gain from that body's mass-weighted
/// displacement (translation ũ = √m u and, with `rotations`, rotation φ̃ = √I φ) to the
/// contact's spring stretches weighted by √k (normal, tangential at the contact point, rolling).
/// A contact's part of A between bodies i and j is G_i^T G_j, so its norm is at most
/// gain_i · gain_j.
double contactGain(const ContactStiffness& k, const ContactBody& body, bool rotations);

/// The bound on ω_max [rad/s] of the network as it is now, and the particle whose row sets it.
/// With `sweeps` = 0 it is the block Gershgorin bound: the largest Σ over a particle's contacts
/// of gain_i (gain_i + gain_other). Each sweep of the power method on the contacts' gain matrix
/// lowers it, still an upper bound (Collatz–Wielandt). 0 with no contacts.
///
/// With `lookahead` > 0 [s], pairs (and wall contacts) not yet touching count too when they
/// close their gap within `lookahead` at their present closing speed: a neighbour-list
/// candidate approaching at u across gap g ≤ u · lookahead. Under Hertz's law such a contact,
/// and a touching one that is closing, is counted at the overlap it would add in a head-on
/// impact at u (the peak overlap (5 m u² / (4 κ √R))^(2/5)), so that an impact does not arrive
/// at a step chosen for the bed's gentle contacts.
///
/// The dashpots' matrix C (normal γn m_ij, tangential γt m_ij at the contact point, rolling
/// C_r) is bounded the same way: Γ ≥ λ_max(M^(-1/2) C M^(-1/2)), the fastest damping rate.
struct NetworkFrequency {
  double omegaMax = 0;
  std::size_t particle = 0;
  std::size_t contacts = 0;     ///< touching contacts counted
  std::size_t approaching = 0;  ///< contacts not yet touching counted (the lookahead)
  double dampingRate = 0;       ///< Γ [1/s]
  /// Γ / (2 ω_max): the damping ratio of a mode at the frequency bound damped at the bound on
  /// the rates; the step is chosen at this (ω, Γ) corner (physics.md §2.15).
  double dampingRatio = 0;
  /// The smallest damping ratio of one contact's own modes [-] (normal γn √(m_ij/k_n)/2,
  /// tangential γt √(m_ij/k_t)/2 with friction, rolling η_r): the stand-in for the least damped
  /// mode, which Gear's interval needs (undamped, Gear5 grows; physics.md §2.15).
  double smallestDampingRatio = 0;
  /// The fastest closing speed among the contacts counted, touching or about to touch [m/s]
  /// (0 with none): the approach speeds the run actually has, which a Hertz contact's duration
  /// depends on (the step control's accuracy floor follows it).
  double fastestApproach = 0;
  /// Σ ½ m_ij |v_i − v_j|² over the contacts counted (v_j a wall's velocity at the contact,
  /// m_ij the particle's mass there) [J]: the kinetic energy of the contacts' relative motion,
  /// closing, separating or sliding, which an impact turns into spring energy. Against what
  /// the springs store it tells impacts from a network that moves slowly (the step control's
  /// accuracy floor is for impacts).
  double relativeKinetic = 0;
};
NetworkFrequency networkFrequencyBound(const Simulation& sim, int sweeps = 32,
                                       double lookahead = 0.0);

}  // namespace granular
