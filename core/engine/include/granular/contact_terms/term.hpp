#pragma once
/// What a term of the contact model declares about itself (docs/architecture.md, "The contact
/// model"). A term is a struct with
///   - `Parameters`: its material parameters with their defaults (Material derives from every
///     term's Parameters, so `material.friction` is the tangential spring's);
///   - `parameters`: a tuple of NumberParameter / ChoiceParameter / FlagParameter, one per
///     field: scene key, symbol, unit, allowed range, one-line doc;
///   - `history`: the names of its per-contact history slots (none for a memoryless term);
///   - `energy`: the energy terms it stores or dissipates (the ledger's columns);
///   - `stableStep`: how it limits the time step, in words (the check lives with the engine);
///   - optionally `rule`: a rule between its parameters that no single range states, returning
///     a RuleProblem (validateMaterial and the scene loader apply it);
///   - its kernel, inline functions on one contact of a chunk (contact_law.hpp composes them).
/// Everything that lists material parameters (the scene loader, the one validation, the state
/// checks, the checkpoint, the scene fingerprint, the GUI, the docs test) reads these
/// declarations through granular/contact_model.hpp, so a new term is one file and a line in the
/// model's list.
#include <span>
#include <string_view>

#include "granular/value_range.hpp"

namespace granular {

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

/// An energy term in the ledger: stored (springs) or dissipated (dashpots, slip).
enum class EnergyKind { Stored, Dissipated };
struct EnergyTerm {
  std::string_view column;  ///< the energy time series' column (J)
  EnergyKind kind;
  std::string_view doc;
};

}  // namespace granular
