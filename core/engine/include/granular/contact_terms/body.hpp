#pragma once
/// The bodies' own material: not a contact term, but declared the same way so that its
/// parameter reaches the loader, checks, checkpoint and docs by the same path.
#include <tuple>

#include "granular/contact_terms/term.hpp"

namespace granular {

struct Body {
  static constexpr std::string_view name = "body";
  struct Parameters {
    double density = 500.0;  ///< particle density ρ [kg/m³]
  };
  /// The upper bound catches a unit slip (g/cm³ written as kg/m³ × 1e3 twice); even a density
  /// scaled up to allow a longer step is far below it.
  static constexpr auto parameters = std::tuple{
      NumberParameter<Parameters>{"density", "ρ", "kg/m³", ValueRange::aboveUpTo(0, 1e12),
                                  "particle density (scaled if total_mass is given)",
                                  &Parameters::density},
  };
  static constexpr std::span<const std::string_view> history{};
  static constexpr std::span<const EnergyTerm> energy{};
  static constexpr bool needsFriction = false;
  static constexpr std::string_view stableStep = "the mass in every contact's frequency";
};

}  // namespace granular
