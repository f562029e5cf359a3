/// The table of material parameters (contact_model.hpp), built once from the terms'
/// declarations.
#include "granular/contact_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tuple>
#include <type_traits>

#include "granular/error.hpp"
#include "granular/material.hpp"
#include "number_format.hpp"

namespace granular {
namespace {

/// The I-th parameter of term T as a ParameterSpec: its accessors reach the term's Parameters
/// inside a Material through the base class.
template <class T, std::size_t I>
ParameterSpec specOf() {
  using P = typename T::Parameters;
  constexpr auto d = std::get<I>(T::parameters);
  ParameterSpec s;
  s.term = T::name;
  s.key = d.key;
  s.symbol = d.symbol;
  s.doc = d.doc;
  s.kind = d.kind;
  if constexpr (d.kind == ParameterKind::Number) {
    s.unit = d.unit;
    s.range = d.range;
    s.defaultValue = P{}.*(d.field);
    s.get = [](const Material& m) {
      return static_cast<const P&>(m).*(std::get<I>(T::parameters).field);
    };
    s.set = [](Material& m, double v) {
      static_cast<P&>(m).*(std::get<I>(T::parameters).field) = v;
    };
  } else if constexpr (d.kind == ParameterKind::Choice) {
    using E = std::remove_cvref_t<decltype(P{}.*(d.field))>;
    s.unit = "-";
    s.names = d.names;
    s.range = ValueRange::closed(0, double(d.names.size() - 1));
    s.defaultValue = double(static_cast<int>(P{}.*(d.field)));
    s.get = [](const Material& m) {
      return double(static_cast<int>(static_cast<const P&>(m).*(std::get<I>(T::parameters).field)));
    };
    s.set = [](Material& m, double v) {
      // A value no choice has becomes −1, which validateMaterial refuses (never a cast of an
      // out-of-range double).
      static_cast<P&>(m).*(std::get<I>(T::parameters).field) =
          static_cast<E>(v >= 0 && v < 1e9 ? static_cast<int>(v) : -1);
    };
  } else {
    s.unit = "-";
    s.range = ValueRange::closed(0, 1);
    s.defaultValue = P{}.*(d.field) ? 1.0 : 0.0;
    s.get = [](const Material& m) {
      return static_cast<const P&>(m).*(std::get<I>(T::parameters).field) ? 1.0 : 0.0;
    };
    s.set = [](Material& m, double v) {
      static_cast<P&>(m).*(std::get<I>(T::parameters).field) = v != 0.0;
    };
  }
  return s;
}

template <class T, std::size_t... I>
void addTerm(std::vector<ParameterSpec>& out, std::index_sequence<I...>) {
  (out.push_back(specOf<T, I>()), ...);
}

template <class... Terms>
std::vector<ParameterSpec> tableOf(TermList<Terms...>) {
  std::vector<ParameterSpec> out;
  (addTerm<Terms>(out, std::make_index_sequence<std::tuple_size_v<decltype(Terms::parameters)>>{}),
   ...);
  return out;
}

template <class T>
TermSpec termSpecOf() {
  TermSpec t{T::name, T::history, kHistoryOffset<T>, nullptr, T::energy, T::stableStep};
  if constexpr (requires { T::historyProblem(nullptr); }) t.historyProblem = &T::historyProblem;
  if constexpr (requires(const Material& m) { T::active(m); }) {
    t.active = [](const Material& m) { return T::active(m); };
  }
  if constexpr (requires { T::mayPull; }) t.mayPull = T::mayPull;
  if constexpr (requires(const Material& m) { T::reach(m); }) {
    t.reach = [](const Material& m) { return T::reach(m); };
  }
  return t;
}

template <class... Terms>
RuleProblem rulesOf(TermList<Terms...>, const Material& m) {
  RuleProblem found;
  auto apply = [&]<class T>() {
    if constexpr (requires { T::rule(m); }) {
      if (found.key.empty()) found = T::rule(m);
    }
  };
  (apply.template operator()<Terms>(), ...);
  return found;
}

template <class... Terms>
std::vector<IdleParameter> idleOf(TermList<Terms...>, const Material& m) {
  std::vector<IdleParameter> found;
  auto collect = [&]<class T>() {
    if constexpr (requires { T::idle(m); }) {
      for (const IdleParameter& p : T::idle(m)) {
        if (!p.key.empty()) found.push_back(p);
      }
    }
  };
  (collect.template operator()<Terms>(), ...);
  return found;
}

template <class... Terms>
std::vector<TermSpec> termsOf(TermList<Terms...>) {
  return {termSpecOf<Terms>()...};
}

/// "name" with its quotes, appended piece by piece: GCC 12 warns falsely (-Wrestrict) on
/// "\"" + std::string + "\"".
std::string quoted(std::string_view name) {
  std::string out;
  out += '"';
  out += name;
  out += '"';
  return out;
}

}  // namespace

std::string ParameterSpec::valueText(double value) const {
  switch (kind) {
    case ParameterKind::Choice: {
      // Compared as doubles before the cast: a value from a corrupted file may be any double.
      if (value >= 0 && value < double(names.size()) && value == std::floor(value)) {
        return quoted(names[static_cast<std::size_t>(value)]);
      }
      return formatNumber(value);
    }
    case ParameterKind::Flag:
      return value == 1.0 ? "true" : value == 0.0 ? "false" : formatNumber(value);
    case ParameterKind::Number:
      break;
  }
  return formatNumber(value);
}

bool ParameterSpec::accepts(double value) const {
  if (!std::isfinite(value) || !range.contains(value)) return false;
  return kind == ParameterKind::Number || value == std::floor(value);
}

std::string ParameterSpec::requirement() const {
  switch (kind) {
    case ParameterKind::Choice: {
      std::string out = "must be one of ";
      for (std::size_t k = 0; k < names.size(); ++k) {
        if (k > 0) out += ", ";
        out += quoted(names[k]);
      }
      return out;
    }
    case ParameterKind::Flag:
      return "must be true or false";
    case ParameterKind::Number:
      break;
  }
  return range.describe();
}

std::span<const EnergyAccountSpec> energyAccounts() {
  static const std::vector<EnergyAccountSpec> accounts = [] {
    std::vector<EnergyAccountSpec> out;
    for (const TermSpec& t : contactTerms()) {
      for (const EnergyTerm& e : t.energy) out.push_back({e, out.size(), t.name});
    }
    return out;
  }();
  return accounts;
}

const EnergyAccountSpec* findEnergyAccount(std::string_view column) {
  for (const EnergyAccountSpec& a : energyAccounts()) {
    if (a.account.column == column) return &a;
  }
  return nullptr;
}

std::span<const EnergyAccountSpec> energyColumns() {
  static const std::vector<EnergyAccountSpec> columns = [] {
    std::vector<EnergyAccountSpec> out;
    for (EnergyKind kind :
         {EnergyKind::Stored, EnergyKind::Dissipated, EnergyKind::Slip, EnergyKind::Supplied}) {
      for (const EnergyAccountSpec& a : energyAccounts()) {
        if (a.account.kind == kind) out.push_back(a);
      }
    }
    return out;
  }();
  return columns;
}

std::vector<EnergyAccountSpec> energyColumns(const Material& material) {
  std::vector<EnergyAccountSpec> out;
  for (const EnergyAccountSpec& a : energyColumns()) {
    const auto terms = contactTerms();
    const auto term = std::find_if(terms.begin(), terms.end(),
                                   [&](const TermSpec& t) { return t.name == a.term; });
    if (term->active == nullptr || term->active(material)) out.push_back(a);
  }
  return out;
}

std::span<const ParameterSpec> materialParameters() {
  static const std::vector<ParameterSpec> table = tableOf(ContactModel{});
  return table;
}

std::span<const TermSpec> contactTerms() {
  static const std::vector<TermSpec> terms = termsOf(ContactModel{});
  return terms;
}

const ParameterSpec* findParameter(std::string_view key, std::span<const ParameterSpec> table) {
  for (const ParameterSpec& p : table) {
    if (p.key == key) return &p;
  }
  return nullptr;
}

void validateMaterial(const Material& material, std::span<const ParameterSpec> table) {
  for (const ParameterSpec& p : table) {
    const double value = p.get(material);
    if (p.accepts(value)) continue;
    std::string what = "material.";  // appended piece by piece (quoted() says why)
    what += p.key;
    what += " = ";
    what += p.valueText(value);
    if (p.unit != "-") {
      what += ' ';
      what += p.unit;
    }
    what += ": ";
    what += p.requirement();
    throw ConfigError(what);
  }
  const RuleProblem rule = materialRuleProblem(material);
  if (!rule.key.empty()) {
    const ParameterSpec& p = *findParameter(rule.key);
    std::string what = "material.";
    what += p.key;
    what += " = ";
    what += p.valueText(p.get(material));
    what += ": ";
    what += rule.requirement;
    throw ConfigError(what);
  }
}

double reachBeyondTouch(const Material& material) {
  double reach = 0.0;
  for (const TermSpec& t : contactTerms()) {
    if (t.reach == nullptr || (t.active != nullptr && !t.active(material))) continue;
    reach = std::max(reach, t.reach(material));
  }
  return reach;
}

RuleProblem materialRuleProblem(const Material& material) {
  return rulesOf(ContactModel{}, material);
}

std::vector<IdleParameter> idleParameters(const Material& material) {
  return idleOf(ContactModel{}, material);
}

std::vector<std::pair<std::string, double>> materialValues(const Material& material,
                                                           std::span<const ParameterSpec> table) {
  std::vector<std::pair<std::string, double>> out;
  out.reserve(table.size());
  for (const ParameterSpec& p : table) out.emplace_back(std::string(p.key), p.get(material));
  return out;
}

bool sameMaterial(const Material& a, const Material& b, std::span<const ParameterSpec> table) {
  for (const ParameterSpec& p : table) {
    const double x = p.get(a), y = p.get(b);
    if (std::memcmp(&x, &y, sizeof x) != 0) return false;
  }
  return true;
}

}  // namespace granular
