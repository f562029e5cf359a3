#pragma once
/// The contact model: the terms it is built from (granular/contact_terms/), and the table of
/// material parameters they declare, which every consumer reads: the scene loader, the one
/// validation (validateMaterial), the state checks, the checkpoint, the scene fingerprint, the
/// GUI's fields and the docs test. A new term is a file in contact_terms/ and a line in
/// ContactModel below; nothing else lists parameters.
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "granular/contact_terms/body.hpp"
#include "granular/contact_terms/normal_damping.hpp"
#include "granular/contact_terms/normal_elastic.hpp"
#include "granular/contact_terms/tangential_damping.hpp"
#include "granular/contact_terms/tangential_spring.hpp"

namespace granular {

template <class... Terms>
struct TermList {};

/// The terms, in the order they act on a contact (the bodies' own material first).
using ContactModel =
    TermList<Body, NormalElastic, NormalDamping, TangentialSpring, TangentialDamping>;

/// A struct holding every term's Parameters (Material derives from it).
template <class List>
struct ParametersOf;
template <class... Terms>
struct ParametersOf<TermList<Terms...>> : Terms::Parameters... {};

struct Material;  // granular/material.hpp

/// One material parameter as every consumer sees it, whatever its term and type. Values travel
/// as doubles: a choice as its name's position, a flag as 0 or 1.
struct ParameterSpec {
  std::string_view term;    ///< the declaring term's name
  std::string_view key;     ///< scene key under [material]
  std::string_view symbol;  ///< "γn"
  std::string_view unit;    ///< "1/s", "-"
  std::string_view doc;
  ParameterKind kind = ParameterKind::Number;
  ValueRange range;                         ///< Number: the allowed values
  std::span<const std::string_view> names;  ///< Choice: the names in order
  double defaultValue = 0;
  double (*get)(const Material&) = nullptr;
  void (*set)(Material&, double) = nullptr;

  /// The value as a scene file writes it: 0.3, "hertz", true.
  std::string valueText(double value) const;
  /// True when the value is one this parameter takes (finite and in range, a known choice, 0/1).
  bool accepts(double value) const;
  /// "must be in [0, 10]", "must be one of "hooke", "hertz"", "must be true or false".
  std::string requirement() const;
};

/// A term as the table sees it: name, history slots, energy terms, how it limits the step.
struct TermSpec {
  std::string_view name;
  std::span<const std::string_view> history;
  std::span<const EnergyTerm> energy;
  std::string_view stableStep;
};

/// Every declared material parameter, term by term in ContactModel's order.
std::span<const ParameterSpec> materialParameters();
/// Every term of ContactModel.
std::span<const TermSpec> contactTerms();
/// The parameter with this key, or nullptr.
const ParameterSpec* findParameter(std::string_view key,
                                   std::span<const ParameterSpec> table = materialParameters());

/// The first broken rule between parameters (a term's `rule`, e.g. the constant tangential law
/// needs its k_t), or an empty key when every rule holds.
RuleProblem materialRuleProblem(const Material& material);

/// The one validation of a material: every parameter accepted by its declaration, else
/// ConfigError "material.KEY = VALUE UNIT: must be ..."; then the terms' rules, else
/// ConfigError "material.KEY = VALUE: needs ...".
void validateMaterial(const Material& material,
                      std::span<const ParameterSpec> table = materialParameters());

/// The material as (key, value) pairs (the checkpoint's and the fingerprint's form).
std::vector<std::pair<std::string, double>> materialValues(
    const Material& material, std::span<const ParameterSpec> table = materialParameters());

/// True when every declared parameter of a and b has the same value (the same bits).
bool sameMaterial(const Material& a, const Material& b,
                  std::span<const ParameterSpec> table = materialParameters());

}  // namespace granular
