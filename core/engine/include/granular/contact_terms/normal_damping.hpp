#pragma once
/// Normal dashpot γn m ḣ (docs/physics.md §1, Eq. (3)), and the clamp that keeps the normal force
/// from pulling: F_n = max(0, F_e + γn m ḣ).
#include <algorithm>
#include <cstddef>
#include <tuple>

#include "granular/contact_terms/normal_elastic.hpp"
#include "granular/contact_terms/term.hpp"

namespace granular {

struct NormalDamping {
  static constexpr std::string_view name = "normal_damping";
  struct Parameters {
    double normalDamping = 60.0;  ///< normal viscous damping γn [1/s]
    /// The normal force is clamped at zero, F_n = max(0, k h^α + γn m ḣ): it never pulls. False,
    /// for comparison with codes that allow a pull: F_n = k h^α + γn m ḣ, which the dashpot makes
    /// negative while overlapping spheres separate fast enough.
    bool noPull = true;
  };
  static constexpr auto parameters = std::tuple{
      NumberParameter<Parameters>{"normal_damping", "γn", "1/s", ValueRange::atLeast(0),
                                  "normal viscous damping; the stiffest contact stays under-damped",
                                  &Parameters::normalDamping},
      FlagParameter<Parameters>{"no_pull", "",
                                "the normal force is clamped at zero and never pulls; false "
                                "lets the dashpot pull while overlapping spheres separate",
                                &Parameters::noPull},
  };
  static constexpr std::span<const std::string_view> history{};
  static constexpr EnergyTerm kEnergy[] = {{"dissipated_normal_J", EnergyKind::Dissipated, "normal",
                                            "by the dashpot, as applied after the clamp"}};
  static constexpr std::span<const EnergyTerm> energy{kEnergy};
  static constexpr bool needsFriction = false;
  static constexpr std::string_view stableStep =
      "must leave the stiffest contact under-damped; its duration then sets the step";

  template <NormalLaw kLaw, bool kAdvance, class Constants, class Chunk>
  [[gnu::always_inline]] static void first(const Constants& k, Chunk& c, std::size_t e,
                                           ContactLane& lane) {
    const double rate = c.vx[e] * lane.nx + c.vy[e] * lane.ny + c.vz[e] * lane.nz;  // ḣ
    double power;
    force(k.normalDamping, k.normalForceFloor, lane.mass, lane.elastic, rate, lane.normal, power);
    c.template energy<NormalDamping>(0)[e] = power;
  }

  /// The normal force F_n = max(floor, F_e + γn m ḣ) (floor 0, or −∞ with a pull allowed) and
  /// the power the dashpot takes, (F_n − F_e) ḣ.
  [[gnu::always_inline]] static void force(double damping, double floor, double mass,
                                           double elastic, double rate, double& normal,
                                           double& power) {
    normal = std::max(floor, elastic + damping * mass * rate);
    power = (normal - elastic) * rate;
  }
};

}  // namespace granular
