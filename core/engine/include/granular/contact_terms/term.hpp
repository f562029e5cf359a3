#pragma once
/// What a term of the contact model declares about itself (docs/architecture.md, "The contact
/// model"): everything the engine needs of it, so that a new term is one file and a line in
/// the model's list (granular/contact_model.hpp). A term is a struct with
///   - `Parameters`: its material parameters with their defaults (Material derives from every
///     term's Parameters, so `material.friction` is the tangential spring's);
///   - `parameters`: a tuple of NumberParameter / ChoiceParameter / FlagParameter, one per
///     field: scene key, symbol, unit, allowed range, one-line doc;
///   - `history`: the names of its per-contact history slots, one double each (none for a
///     memoryless term); the model's ContactHistory holds every term's slots, and a term with
///     slots also gives `historyProblem(const double* slot)`, the state checks' rule for them.
///     Only frictional builds carry history and run the second loop: a term with either needs
///     friction (a compile-time check in contact_law.hpp);
///   - `energy`: its energy accounts (EnergyTerm; the ledger's columns), and `needsFriction`:
///     whether it acts only where friction is on (its accounts and history are then left out
///     of a frictionless scene's pass);
///   - `stableStep`: how it limits the time step, in words, for the docs; the limit itself is
///     its `linearise` (below);
///   - optionally `rule`: a rule between its parameters that no single range states, returning
///     a RuleProblem (validateMaterial and the scene loader apply it);
///   - optionally `idle`: which of its parameters the others leave without effect (the
///     constant law's k_t under Mindlin's), as IdleParameters; a scene that sets one is refused;
///   - optionally `Constants` with `constants(material)`: its constants, computed once a pass
///     (the kernel reads them as `k.template of<Term>()`);
///   - optionally `betweenLoops`: names of per-contact values it keeps from the law's first loop
///     to its second (`c.template between<Term>(slot)`);
///   - its kernel, inline functions on one contact of a chunk (contact_law.hpp composes them):
///     `first` and, for a term that needs every force of the first loop, `second`. Forces and
///     couples ACCUMULATE in the lane: a term adds to `normal`, to the tangential force and to
///     the couple `q` (+q on i, −q on the other body), never overwrites another's part;
///   - optionally `linearise(constants, LinearContact&)`: its springs and dashpots in the
///     contact network's linearisation, added to the contact's modes (the step bound,
///     network_frequency.hpp, adds nothing by name);
///   - optionally `active(const Parameters&)`: the term is optional and acts only where this
///     says (the law is built with and without it; a scene without it pays nothing);
///   - optionally `pureTorque`: it adds a couple (the build then carries the q rows), and
///     `readsBodies`: it reads the bodies' own radii, masses and spins (the chunk's raw rows;
///     a wall is a body of infinite radius and mass without spin);
///   - its energy accounts' powers (Dissipated, Work) on the velocity the force works on over
///     its step: the velocity the law reads plus the powers' lead (leadRate, leadTangential:
///     Verlet's forces act from a half-step velocity, and a power taken there would make the
///     ledger first order);
///   - optionally `mayPull`: its normal force may be attractive. It is listed after the normal
///     dashpot, whose no-pull floor holds for the contact's own repulsion only;
///   - optionally `reach(const Parameters&)`: how far beyond touch it acts [m] (a term without
///     it acts while the bodies touch, reach 0). The bodies then interact from the gap
///     −h = reach on: the neighbour list, the walls' candidates and a split run's ghosts reach
///     that far. On a gap (h < 0) the terms that do not reach see h = 0, and their forces,
///     couples, energies and history are dropped; a term that reaches sees the true h. Terms
///     that reach are listed after every term that does not.
/// Everything that lists material parameters (the scene loader, the one validation, the state
/// checks, the checkpoint, the scene fingerprint, the GUI, the docs test) reads these
/// declarations through granular/contact_model.hpp.
#include <cstddef>
#include <span>
#include <string_view>

#include "granular/value_range.hpp"

namespace granular {

/// One contact as the terms see it inside the law's loops (engine/src/contact_law.hpp): the
/// geometry the force pass gives, and what the terms before this one computed. A term's kernel
/// is `first` (the law's first loop: forces from the state) and, for the terms that need
/// friction, `second` (the second loop: the caps, which need every force of the first); both
/// are static inline templates on the chunk of contacts, which gives them their arrays
/// (`c.template energy<Term>(slot)`, `c.template history<Term>(slot)`, the velocities).
///
/// The sums start at −0, the identity of IEEE addition (−0 + x is x for every x, ±0 included):
/// the first term's part is then the sum itself, bit for bit.
struct ContactLane {
  double h, nx, ny, nz;  ///< overlap [m] (negative: a gap, seen by a term that reaches only),
                         ///< unit normal from i to the other body
  double radius, mass;   ///< R_ij [m], m_ij [kg]
  double elastic = 0;    ///< the normal elastic force F_e [N]
  double normal = -0.0;  ///< the normal force F_n, summed [N] (the force on i: −F_n n + F_t)
  double vtx = 0, vty = 0, vtz = 0;        ///< tangential velocity of the contact points [m/s]
  double tx = -0.0, ty = -0.0, tz = -0.0;  ///< tangential force, summed: trial (first),
                                           ///< capped (second) [N]
  double qx = -0.0, qy = -0.0, qz = -0.0;  ///< the couple on i, summed [N m]
  bool sliding = false;                    ///< the Coulomb cap holds (second loop)
};

/// The lead of entry e's normal rate ḣ for its powers (ContactChunk::ux: the velocity a force
/// works on over its step is the one the law reads plus the lead; zero for Gear and between
/// steps) [m/s].
template <class Chunk>
[[gnu::always_inline]] inline double leadRate(const Chunk& c, std::size_t e,
                                              const ContactLane& lane) {
  return c.ux[e] * lane.nx + c.uy[e] * lane.ny + c.uz[e] * lane.nz;
}
/// The same lead on the contact points' tangential velocity [m/s].
template <class Chunk>
[[gnu::always_inline]] inline void leadTangential(const Chunk& c, std::size_t e,
                                                  const ContactLane& lane, double& x, double& y,
                                                  double& z) {
  const double rate = leadRate(c, e, lane);
  x = c.ux[e] - rate * lane.nx;
  y = c.uy[e] - rate * lane.ny;
  z = c.uz[e] - rate * lane.nz;
}

/// One contact's modes of relative motion: normal, tangential at the contact points, rolling.
struct ContactModes {
  double normal = 0, tangential = 0, rolling = 0;
};

/// One contact linearised about its state, as the contact network's step bound sees it
/// (network_frequency.hpp): the engine gives the contact; each term adds its springs
/// (N/m; rolling N m/rad) and dashpots (N s/m; rolling N m s/rad) to the modes, and the damping
/// ratio of each mode it damps.
struct LinearContact {
  double radius = 0;          ///< R_ij [m]
  double mass = 0;            ///< m_ij [kg]
  double overlap = 0;         ///< h ≥ 0 [m]
  double rollingInertia = 0;  ///< the relative rotation's inertia about the contact [kg m²]
  ContactModes stiffness, damping;
  double leastRatio = 0;  ///< the least damping ratio of the modes (valid when `damped`)
  bool damped = false;

  /// A mode's damping ratio [-]: the least is kept.
  void leastDampingRatio(double ratio) {
    leastRatio = damped ? (ratio < leastRatio ? ratio : leastRatio) : ratio;
    damped = true;
  }
};

/// How a parameter is written in a scene file: a number, one of a list of names, true/false.
enum class ParameterKind { Number, Choice, Flag };

/// A number-valued parameter: the field of the term's Parameters it sets.
template <class P>
struct NumberParameter {
  static constexpr ParameterKind kind = ParameterKind::Number;
  std::string_view key;     ///< scene key under [material]
  std::string_view symbol;  ///< as the docs write it: "γn"
  std::string_view unit;    ///< SI unit, "-" for a pure number
  ValueRange range;         ///< allowed values (finite always)
  std::string_view doc;     ///< one line
  double P::*field;
};

/// A choice among names, stored as an enum whose values are the names' positions.
template <class P, class E>
struct ChoiceParameter {
  static constexpr ParameterKind kind = ParameterKind::Choice;
  std::string_view key;
  std::string_view symbol;
  std::span<const std::string_view> names;  ///< in the enum's order
  std::string_view doc;
  E P::*field;
};

/// A true/false parameter.
template <class P>
struct FlagParameter {
  static constexpr ParameterKind kind = ParameterKind::Flag;
  std::string_view key;
  std::string_view symbol;
  std::string_view doc;
  bool P::*field;
};

/// A broken rule between parameters: the key it is reported at and what the rule requires
/// ("needs tangential_stiffness > 0 N/m, ..."); an empty key when the rule holds.
struct RuleProblem {
  std::string_view key;
  std::string_view requirement;
};

/// A parameter that the values of the others leave without effect, and why ("applies to
/// tangential_law = \"constant\" only"); an empty key where there is none.
struct IdleParameter {
  std::string_view key;
  std::string_view reason;
};

/// What an energy account of the ledger is (EnergyBalance::total adds them with these signs):
enum class EnergyKind {
  Stored,      ///< held by the contacts now: each contact gives its energy [J]; +
  Dissipated,  ///< ∫ power dt (trapezoid): each contact gives its power [W]; +
  Slip,        ///< what its group's forces took and nothing else holds (no per-contact value):
               ///< −Work − ΔStored − Dissipated + Supplied of the group [J]; +
  Supplied,    ///< put into the contacts, not by the bodies: each contact gives its increment
               ///< [J]; −
  Work,        ///< ∫ power dt of the group's force on the relative motion [J]: Slip's input, not
               ///< a column
};

/// An energy account a term declares: the energy time series' column, its kind, and the group
/// whose forces it belongs to (a Slip account is the residual of its group).
struct EnergyTerm {
  std::string_view column;  ///< the time series' column (J)
  EnergyKind kind;
  std::string_view group;
  std::string_view doc;
};

}  // namespace granular
