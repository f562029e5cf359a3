#pragma once
/// A liquid bridge between two bodies, acting from touch out to its rupture distance
/// (docs/physics.md, "Liquid bridges"): Willett et al. (2000), Eqs. (12)-(13), the closed form
/// for a bridge of volume V, surface tension γ and contact angle θ between spheres,
///   F = 2π R γ cos θ / (1 + 2.1 Ŝ + 10 Ŝ²),   Ŝ = (S/2) √(R/V),
/// with R = 2 R_ij (a sphere's radius between equal spheres; 2 R_i against a wall) and S = −h the
/// gap. While the bodies overlap the bridge pulls as at touch, 2π R γ cos θ. It ruptures at
/// Lian et al.'s (1993) distance S_c = (1 + θ/2) V^(1/3) (θ in radians), which is its reach:
/// the neighbour list and the walls' candidates hold the pairs within it. A bridge stands
/// between every pair within S_c (the liquid wets every surface; no history of how the pair
/// came there), so its pull derives from a potential; its work on the bodies is its own
/// account, and the column `bridge_J` is what the bridges took from the particles. It softens
/// the contact (the pull falls with the gap), so it adds nothing to the network's stiffness:
/// the step bound stays an upper bound with it.
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <tuple>

#include "granular/contact_terms/normal_elastic.hpp"
#include "granular/contact_terms/term.hpp"

namespace granular {

struct LiquidBridge {
  static constexpr std::string_view name = "liquid_bridge";

  struct Parameters {
    double surfaceTension = 0.0;  ///< γ [N/m]; 0: no bridges
    double contactAngle = 0.0;    ///< θ [°] of the liquid on the solid
    double bridgeVolume = 0.0;    ///< V [m³], the liquid of one bridge
  };
  static constexpr auto parameters = std::tuple{
      NumberParameter<Parameters>{"surface_tension", "γ", "N/m", ValueRange::closed(0, 10),
                                  "liquid bridges: the liquid's surface tension (water 0.072); "
                                  "0 switches bridges off",
                                  &Parameters::surfaceTension},
      NumberParameter<Parameters>{"contact_angle", "θ", "°", ValueRange::closed(0, 90),
                                  "liquid bridges: the liquid's contact angle on the particles",
                                  &Parameters::contactAngle},
      NumberParameter<Parameters>{"bridge_volume", "V", "m³", ValueRange::closed(0, 1),
                                  "liquid bridges: the liquid volume of one bridge (> 0 with "
                                  "surface_tension); sets the rupture distance (1 + θ/2) V^(1/3)",
                                  &Parameters::bridgeVolume},
  };
  /// A bridge needs its liquid: γ without V would be a bridge of no size.
  static RuleProblem rule(const Parameters& p) {
    if (p.surfaceTension > 0.0 && !(p.bridgeVolume > 0.0)) {
      return {"surface_tension",
              "needs bridge_volume > 0 m³, the liquid of one bridge, with surface_tension > 0"};
    }
    return {};
  }
  /// Without surface tension there are no bridges, and their shape means nothing.
  static std::array<IdleParameter, 2> idle(const Parameters& p) {
    if (p.surfaceTension > 0.0) return {};
    constexpr std::string_view why =
        "applies with surface_tension > 0 only (surface_tension = 0 switches liquid bridges "
        "off); remove it, or set surface_tension";
    return {IdleParameter{"contact_angle", why}, IdleParameter{"bridge_volume", why}};
  }
  /// A scene without bridges runs the law's build without this term.
  static bool active(const Parameters& p) { return p.surfaceTension > 0.0; }
  /// The rupture distance S_c = (1 + θ/2) V^(1/3) [m]: the bridge acts out to this gap.
  static double reach(const Parameters& p) {
    return (1.0 + 0.5 * p.contactAngle * std::numbers::pi / 180.0) * std::cbrt(p.bridgeVolume);
  }

  static constexpr std::span<const std::string_view> history{};
  static constexpr EnergyTerm kEnergy[] = {
      {"bridge_J", EnergyKind::Slip, "bridge",
       "taken from the particles by the liquid bridges' pull (their potential energy)"},
      {"bridge_work_J", EnergyKind::Work, "bridge",
       "work of the bridges' pull on the bodies' relative motion"}};
  static constexpr std::span<const EnergyTerm> energy{kEnergy};
  static constexpr bool needsFriction = false;
  static constexpr bool mayPull = true;
  static constexpr std::string_view stableStep =
      "none of its own: its pull falls with the gap and is constant in contact, so it softens "
      "the contact, and the step bound ignores that";

  struct Constants {
    double pull;         ///< 2π γ cos θ [N/m]: the force at touch per unit R
    double inverseRoot;  ///< 1/(2 √V) [m^(-3/2)]: Ŝ = S √R / (2 √V)
    double rupture;      ///< S_c [m]
  };
  static Constants constants(const Parameters& p) {
    const double angle = p.contactAngle * std::numbers::pi / 180.0;
    return {2.0 * std::numbers::pi * p.surfaceTension * std::cos(angle),
            0.5 / std::sqrt(p.bridgeVolume > 0.0 ? p.bridgeVolume : 1.0), reach(p)};
  }

  template <NormalLaw kLaw, bool kAdvance, class ModelConstants, class Chunk>
  [[gnu::always_inline]] static void first(const ModelConstants& k, Chunk& c, std::size_t e,
                                           ContactLane& lane) {
    const Constants& own = k.template of<LiquidBridge>();
    const double gap = lane.h < 0.0 ? -lane.h : 0.0;
    const double pull = gap < own.rupture ? force(own, 2.0 * lane.radius, gap) : 0.0;
    lane.normal += -pull;
    // Its power on the bodies: the force on i, pull n, on v_i − v_other, pull ḣ.
    const double rate = c.vx[e] * lane.nx + c.vy[e] * lane.ny + c.vz[e] * lane.nz;  // ḣ
    c.template energy<LiquidBridge>(1)[e] = pull * (rate + leadRate(c, e, lane));
  }

  /// Willett's pull [N] of a bridge between bodies of radius R = 2 R_ij at the gap S ≥ 0.
  [[gnu::always_inline]] static double force(const Constants& own, double radius, double gap) {
    const double scaled = gap * std::sqrt(radius) * own.inverseRoot;  // Ŝ
    return own.pull * radius / (1.0 + scaled * (2.1 + 10.0 * scaled));
  }
};

}  // namespace granular
