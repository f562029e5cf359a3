#pragma once
/// The contact model: the terms it is built from (granular/contact_terms/), and the table of
/// material parameters they declare, which every consumer reads: the scene loader, the one
/// validation (validateMaterial), the state checks, the checkpoint, the scene fingerprint, the
/// GUI's fields and the docs test. A new term is a file in contact_terms/ and a line in
/// ContactModel below; nothing else lists parameters.
#include <array>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "granular/contact_terms/body.hpp"
#include "granular/contact_terms/liquid_bridge.hpp"
#include "granular/contact_terms/normal_damping.hpp"
#include "granular/contact_terms/normal_elastic.hpp"
#include "granular/contact_terms/rolling_resistance.hpp"
#include "granular/contact_terms/sjkr_cohesion.hpp"
#include "granular/contact_terms/tangential_damping.hpp"
#include "granular/contact_terms/tangential_spring.hpp"

namespace granular {

template <class... Terms>
struct TermList {};

/// The terms, in the order they act on a contact (the bodies' own material first).
using ContactModel = TermList<Body, NormalElastic, NormalDamping, TangentialSpring,
                              TangentialDamping, RollingResistance, SjkrCohesion, LiquidBridge>;

/// A struct holding every term's Parameters (Material derives from it).
template <class List>
struct ParametersOf;
template <class... Terms>
struct ParametersOf<TermList<Terms...>> : Terms::Parameters... {};

struct Material;  // granular/material.hpp

/// Where term T's run begins when the terms, in order, each take `sizeOf(term)` places.
template <class T, class... Terms, class SizeOf>
constexpr std::size_t runOffset(SizeOf sizeOf) {
  std::size_t at = 0;
  bool found = false;
  ((found = found || std::is_same_v<T, Terms>,
    at += found ? 0 : sizeOf(std::type_identity<Terms>{})),
   ...);
  return at;
}

/// The per-contact history slots of all terms (doubles), and where term T's begin.
template <class List>
struct HistoryLayout;
template <class... Terms>
struct HistoryLayout<TermList<Terms...>> {
  static constexpr std::size_t slots = (Terms::history.size() + ...);
  template <class T>
  static constexpr std::size_t offset() {
    return runOffset<T, Terms...>([](auto t) { return decltype(t)::type::history.size(); });
  }
};
inline constexpr std::size_t kHistorySlots = HistoryLayout<ContactModel>::slots;
/// Where term T's history slots begin in a ContactHistory.
template <class T>
inline constexpr std::size_t kHistoryOffset = HistoryLayout<ContactModel>::template offset<T>();

/// The energy accounts of all terms, one slot each, and where term T's begin.
template <class List>
struct EnergyLayout;
template <class... Terms>
struct EnergyLayout<TermList<Terms...>> {
  static constexpr std::size_t slots = (Terms::energy.size() + ...);
  template <class T>
  static constexpr std::size_t offset() {
    return runOffset<T, Terms...>([](auto t) { return decltype(t)::type::energy.size(); });
  }
  /// Per slot: its kind.
  struct Slot {
    EnergyKind kind;
  };
  static constexpr std::array<Slot, slots> table() {
    std::array<Slot, slots> out{};
    std::size_t at = 0;
    (
        [&] {
          for (const EnergyTerm& e : Terms::energy) out[at++] = {e.kind};
        }(),
        ...);
    return out;
  }
};
inline constexpr std::size_t kEnergySlots = EnergyLayout<ContactModel>::slots;
/// Where term T's energy accounts begin (the force pass's per-contact values and sums).
template <class T>
inline constexpr std::size_t kEnergyOffset = EnergyLayout<ContactModel>::template offset<T>();
/// Each slot's kind, by slot.
inline constexpr auto kEnergySlotTable = EnergyLayout<ContactModel>::table();

/// The history one contact carries for its life: every term's slots, zero for a new contact.
/// Its size comes from the terms' declarations.
struct ContactHistory {
  double slot[kHistorySlots] = {};
  /// True when some slot is nonzero (a contact with nothing to remember is not stored).
  bool holdsSomething() const {
    for (double x : slot) {
      if (x != 0.0) return true;
    }
    return false;
  }
};

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
  std::size_t historyOffset = 0;  ///< where its slots begin in a ContactHistory
  /// The state checks' rule for its slots (nullptr: any finite values); returns why they are
  /// not a state the term can reach, or nullptr.
  const char* (*historyProblem)(const double* slot) = nullptr;
  std::span<const EnergyTerm> energy;
  std::string_view stableStep;
  /// An optional term's `active` (whether a material uses it); nullptr: the term always acts.
  bool (*active)(const Material&) = nullptr;
  /// Its normal force may be attractive (it then acts after the normal dashpot's no-pull floor).
  bool mayPull = false;
  /// How far beyond touch it acts for a material [m] (its `reach`); nullptr: it acts in contact
  /// only.
  double (*reach)(const Material&) = nullptr;
};

/// An energy account with its slot (the force pass's index for it) and term.
struct EnergyAccountSpec {
  EnergyTerm account;
  std::size_t slot;
  std::string_view term;
};
/// Every energy account, slot by slot (term by term in ContactModel's order).
std::span<const EnergyAccountSpec> energyAccounts();
/// The energy account with this column ("elastic_tangential_J"), or nullptr.
const EnergyAccountSpec* findEnergyAccount(std::string_view column);
/// The ledger's columns, as the time series prints them: the Stored accounts, the Dissipated,
/// the Slip, then the Supplied (Work accounts are not columns); each kind in term order.
std::span<const EnergyAccountSpec> energyColumns();
/// The columns of the terms this material uses: an optional term it leaves off (rolling
/// resistance at μ_r = 0) has no columns, so a scene's time series names only what acts in it.
std::vector<EnergyAccountSpec> energyColumns(const Material& material);

/// Every declared material parameter, term by term in ContactModel's order.
std::span<const ParameterSpec> materialParameters();
/// Every term of ContactModel.
std::span<const TermSpec> contactTerms();
/// The parameter with this key, or nullptr.
const ParameterSpec* findParameter(std::string_view key,
                                   std::span<const ParameterSpec> table = materialParameters());

/// How far beyond touch the contact model acts for this material [m]: the largest reach of the
/// terms it uses (a liquid bridge's rupture distance), 0 when every force needs contact.
double reachBeyondTouch(const Material& material);

/// The first broken rule between parameters (a term's `rule`, e.g. the constant tangential law
/// needs its k_t), or an empty key when every rule holds.
RuleProblem materialRuleProblem(const Material& material);

/// The parameters this material's other values leave without effect (the terms' `idle`), each
/// with the reason; a scene file that sets one is refused (the loader).
std::vector<IdleParameter> idleParameters(const Material& material);

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
