#pragma once
/// Normal dashpot γn m ḣ (docs/physics.md §1, Eq. (3)), and the clamp that keeps the normal force
/// from pulling: F_n = max(0, F_e + γn m ḣ).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
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

  struct Constants {
    double damping;  ///< γn [1/s]
    double floor;    ///< 0 (no pull: F_n = max(0, ·)) or −∞ (a pull allowed) [N]
  };
  static Constants constants(const Parameters& p) {
    return {p.normalDamping, p.noPull ? 0.0 : -std::numeric_limits<double>::infinity()};
  }

  template <NormalLaw kLaw, bool kAdvance, class ModelConstants, class Chunk>
  [[gnu::always_inline]] static void first(const ModelConstants& k, Chunk& c, std::size_t e,
                                           ContactLane& lane) {
    const Constants& own = k.template of<NormalDamping>();
    const double rate = c.vx[e] * lane.nx + c.vy[e] * lane.ny + c.vz[e] * lane.nz;  // ḣ
    const double elastic = lane.elastic;
    force(own.damping, own.floor, lane.mass, rate, lane.normal);
    c.template energy<NormalDamping>(0)[e] =
        (lane.normal - elastic) * (rate + leadRate(c, e, lane));
  }

  /// The normal force so far (the elastic force F_e) with the dashpot, floored:
  /// F_n = max(floor, F_e + γn m ḣ) (floor 0, or −∞ with a pull allowed); the dashpot's part
  /// is F_n − F_e, and its power that times the rate. Terms that may pull (mayPull) act after
  /// the floor.
  [[gnu::always_inline]] static void force(double damping, double floor, double mass, double rate,
                                           double& normal) {
    normal = std::max(floor, normal + damping * mass * rate);
  }

  /// Its dashpot in the network's linearisation, and the damping ratio of the normal mode.
  template <class ModelConstants>
  static void linearise(const ModelConstants& k, LinearContact& c) {
    c.damping.normal += k.template of<NormalDamping>().damping * c.mass;
    if (c.stiffness.normal > 0.0) {
      c.leastDampingRatio(0.5 * c.damping.normal / std::sqrt(c.stiffness.normal * c.mass));
    }
  }
};

}  // namespace granular
