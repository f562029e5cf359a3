#pragma once
/// The per-particle fields, each named once (in the spirit of LAMMPS's AtomVec lists): the
/// checkpoint, the split run's records and ghosts, the spatial reordering and the state checks
/// walk these lists rather than naming the arrays themselves, so that a new per-particle field
/// is one line here and every one of them carries it.
///
/// A field's line gives its name as messages print it, its unit, when the state holds it
/// (FieldNeeds), its array (a member of Particles or of SimulationState, or of one of their
/// members) and the checkpoint version that first holds it. Its type, Vec3 or double (or, for a
/// split run's bookkeeping, an integer), is the array's.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <vector>

#include "granular/particles.hpp"
#include "simulation_state.hpp"

namespace granular {

/// When the state holds a field (its array has one entry per particle; otherwise none): the
/// conditions all hold. kGhost is not a condition: the field travels to the ghosts after each
/// prediction (refreshSplitGhosts), as the force pass reads it there (the accelerations: Verlet's
/// powers' lead, contact_gather.hpp), where the run holds it.
enum FieldNeeds : unsigned {
  kAlways = 0,
  kFriction = 1U << 0,  ///< a frictional run (rotations)
  kGear5 = 1U << 1,     ///< the Gear integrator (derivatives beyond the acceleration)
  kSplit = 1U << 2,     ///< a run split by space among processes
  kGhost = 1U << 3,
};

/// The checkpoint version that holds every field listed before versions were given per field.
inline constexpr std::uint32_t kFieldsSinceFirstVersion = 2;

/// What a message or a file says of a field.
struct FieldSpec {
  std::string_view name;  ///< as messages print it: "angular velocity"
  std::string_view unit;  ///< "rad/s"; empty for a count or a flag
  unsigned needs;         ///< FieldNeeds
  std::uint32_t since;    ///< the first checkpoint version that holds it
};

/// A field's array in its owner: owner.*array, or (owner.*part).*array for one a member holds.
template <class Owner, class Array>
struct Member {
  Array Owner::*array;
  template <class O>
  constexpr auto& operator()(O& owner) const {
    return owner.*array;
  }
};
template <class Owner, class Part, class Array>
struct NestedMember {
  Part Owner::*part;
  Array Part::*array;
  template <class O>
  constexpr auto& operator()(O& owner) const {
    return (owner.*part).*array;
  }
};

/// One line of a list: the field's spec and its array in an Owner (Particles or
/// SimulationState), const or not.
template <class Owner, unsigned Needs, class Get>
struct FieldEntry {
  using Of = Owner;
  static constexpr unsigned needs = Needs;
  using Array = std::remove_cvref_t<std::invoke_result_t<Get, Owner&>>;
  using Value = typename Array::value_type;
  /// Doubles a particle's value takes in a record or a ghost message (0: not a double field).
  static constexpr std::size_t doubles = std::is_same_v<Value, Vec3>     ? 3
                                         : std::is_same_v<Value, double> ? 1
                                                                         : 0;
  FieldSpec spec;
  Get get;
};

/// A field that is a member array of its owner: field<kAlways>("mass", "kg", &Particles::mass).
template <unsigned Needs, class Owner, class Array>
constexpr auto field(std::string_view name, std::string_view unit, Array Owner::*array,
                     std::uint32_t since = kFieldsSinceFirstVersion) {
  return FieldEntry<Owner, Needs, Member<Owner, Array>>{{name, unit, Needs, since}, {array}};
}
/// A field that is an array of a member of its owner:
/// field<kGear5>("jerk", "m/s^3", &SimulationState::translation, &Derivatives::d3).
template <unsigned Needs, class Owner, class Part, class Array>
constexpr auto field(std::string_view name, std::string_view unit, Part Owner::*part,
                     Array Part::*array, std::uint32_t since = kFieldsSinceFirstVersion) {
  return FieldEntry<Owner, Needs, NestedMember<Owner, Part, Array>>{{name, unit, Needs, since},
                                                                    {part, array}};
}

// ---- The lists ----------------------------------------------------------------------------

// One line a field: its name as messages print it, its unit, when the state holds it, its
// array, and (after the array) the checkpoint version that first holds it where that is not
// the first; a new field also raises kCheckpointVersion. The lists are in the checkpoint's
// order.
// clang-format off

/// The fields of Particles.
inline constexpr auto kParticleFields = std::tuple{
    field<kGhost>("position", "m", &Particles::position),
    field<kGhost>("velocity", "m/s", &Particles::velocity),
    field<kGhost>("angular velocity", "rad/s", &Particles::angularVelocity),
    field<kAlways>("radius", "m", &Particles::radius),
    field<kAlways>("mass", "kg", &Particles::mass),
};

/// The integrator's fields of a SimulationState: the last forces and the derivatives.
inline constexpr auto kMotionFields = std::tuple{
    field<kAlways>("force", "N", &SimulationState::force),
    field<kFriction>("torque", "N m", &SimulationState::torque),
    field<kGhost>("acceleration", "m/s^2", &SimulationState::translation, &Derivatives::d2),
    field<kGear5>("jerk", "m/s^3", &SimulationState::translation, &Derivatives::d3),
    field<kGear5>("snap", "m/s^4", &SimulationState::translation, &Derivatives::d4),
    field<kGear5>("crackle", "m/s^5", &SimulationState::translation, &Derivatives::d5),
    field<kFriction | kGhost>("angular acceleration", "rad/s^2", &SimulationState::rotation, &Derivatives::d2),
    field<kFriction | kGear5>("angular jerk", "rad/s^3", &SimulationState::rotation, &Derivatives::d3),
    field<kFriction | kGear5>("angular snap", "rad/s^4", &SimulationState::rotation, &Derivatives::d4),
    field<kFriction | kGear5>("angular crackle", "rad/s^5", &SimulationState::rotation, &Derivatives::d5),
};

/// A split run's bookkeeping of a SimulationState: not checkpointed (a checkpoint holds the
/// whole run), travelling as a record's id or recomputed from the domains.
inline constexpr auto kSplitFields = std::tuple{
    field<kSplit>("global id", "", &SimulationState::split, &DomainSplit::globalId),
    field<kSplit>("ownership", "", &SimulationState::owned),
};

// clang-format on

// Every array of Particles and of Derivatives is listed: a member added without a line here
// fails to compile (all vectors have one size whatever they hold).
static_assert(sizeof(Particles) ==
                  std::tuple_size_v<decltype(kParticleFields)> * sizeof(std::vector<double>),
              "a Particles array is missing from kParticleFields");
static_assert(sizeof(Derivatives) == 4 * sizeof(std::vector<Vec3>),
              "a Derivatives array is missing from kMotionFields");

// ---- Walking the lists --------------------------------------------------------------------

namespace fields_detail {
template <class List, class Owner, class Visit>
void visitAll(const List& list, Owner& owner, Visit& visit) {
  std::apply([&](const auto&... entry) { (visit(entry.spec, entry.get(owner)), ...); }, list);
}
/// Calls visit(entry, offset) for each entry, offset: the doubles of the entries before it.
template <class List, class Visit>
constexpr void visitOffsets(const List& list, std::size_t& offset, Visit& visit) {
  std::apply(
      [&](const auto&... entry) {
        ((visit(entry, offset), offset += std::remove_cvref_t<decltype(entry)>::doubles), ...);
      },
      list);
}
}  // namespace fields_detail

/// Calls visit(spec, array) for each field of `particles` (const or not).
template <class P, class Visit>
void forEachParticleField(P& particles, Visit&& visit) {
  fields_detail::visitAll(kParticleFields, particles, visit);
}
/// Calls visit(spec, from, to) for each field, `from`'s array and `to`'s.
template <class Visit>
void forEachParticleFieldPair(const Particles& from, Particles& to, Visit&& visit) {
  std::apply(
      [&](const auto&... entry) { (visit(entry.spec, entry.get(from), entry.get(to)), ...); },
      kParticleFields);
}
/// Calls visit(spec, array) for each integrator field of `state` (const or not).
template <class S, class Visit>
void forEachMotionField(S& state, Visit&& visit) {
  fields_detail::visitAll(kMotionFields, state, visit);
}
/// Calls visit(spec, array) for every per-particle field of `state`: the particles', the
/// integrator's, and a split run's.
template <class S, class Visit>
void forEachStateField(S& state, Visit&& visit) {
  forEachParticleField(state.particles, visit);
  forEachMotionField(state, visit);
  fields_detail::visitAll(kSplitFields, state, visit);
}

/// Calls visit(entry, offset) for each field of the particles and the integrator, offset:
/// where its doubles start in a particle's record (ParticleRecord::value). Entries are
/// FieldEntry (entry.get(particles) or entry.get(state), by Owner).
template <class Visit>
constexpr void forEachRecordField(Visit&& visit) {
  std::size_t offset = 0;
  fields_detail::visitOffsets(kParticleFields, offset, visit);
  fields_detail::visitOffsets(kMotionFields, offset, visit);
}

/// The doubles of a particle's record: every field of the particles and the integrator.
constexpr std::size_t recordDoubles() {
  std::size_t total = 0;
  forEachRecordField([&](const auto& entry, std::size_t) {
    total += std::remove_cvref_t<decltype(entry)>::doubles;
  });
  return total;
}

/// Calls visit(entry, offset) for each field sent to the ghosts (kGhost), offset: where its
/// doubles start in a ghost's message.
template <class Visit>
constexpr void forEachGhostField(Visit&& visit) {
  std::size_t offset = 0;
  forEachRecordField([&](const auto& entry, std::size_t) {
    using Entry = std::remove_cvref_t<decltype(entry)>;
    if constexpr ((Entry::needs & kGhost) != 0) {
      visit(entry, offset);
      offset += Entry::doubles;
    }
  });
}

/// The doubles of a ghost's message.
constexpr std::size_t ghostDoubles() {
  std::size_t total = 0;
  forEachGhostField([&](const auto& entry, std::size_t) {
    total += std::remove_cvref_t<decltype(entry)>::doubles;
  });
  return total;
}

/// The array an entry names in the state: its Particles' or its own.
template <class Entry, class S>
auto& arrayOf(const Entry& entry, S& state) {
  if constexpr (std::is_same_v<typename Entry::Of, Particles>) {
    return entry.get(state.particles);
  } else {
    return entry.get(state);
  }
}

/// Whether `state` holds the field (one entry per particle) by its FieldNeeds.
inline bool holds(const SimulationState& s, unsigned needs) {
  return ((needs & kFriction) == 0 || s.frictional) &&
         ((needs & kGear5) == 0 || s.config.integrator == Integrator::Gear5) &&
         ((needs & kSplit) == 0 || s.split.domains != nullptr);
}

/// A value's doubles at `to` (Vec3: 3, double: 1) and back.
inline void storeDoubles(double* to, const Vec3& v) {
  to[0] = v[0], to[1] = v[1], to[2] = v[2];
}
inline void storeDoubles(double* to, double v) {
  to[0] = v;
}
template <class T>
T loadDoubles(const double* from) {
  static_assert(std::is_same_v<T, Vec3> || std::is_same_v<T, double>);
  if constexpr (std::is_same_v<T, Vec3>) {
    return Vec3(from[0], from[1], from[2]);
  } else {
    return from[0];
  }
}

}  // namespace granular
