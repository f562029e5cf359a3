#pragma once
/// Tangential dashpot γt m v_t (docs/physics.md §1, Eq. (4)): part of the trial tangential force
/// before the Coulomb cap, so it acts while the contact sticks.
#include <cmath>
#include <cstddef>
#include <tuple>

#include "granular/contact_terms/normal_elastic.hpp"
#include "granular/contact_terms/term.hpp"

namespace granular {

struct TangentialDamping {
  static constexpr std::string_view name = "tangential_damping";
  struct Parameters {
    double tangentialDamping = 10.0;  ///< tangential viscous damping γt [1/s]
  };
  static constexpr auto parameters = std::tuple{
      NumberParameter<Parameters>{"tangential_damping", "γt", "1/s", ValueRange::atLeast(0),
                                  "tangential viscous damping; with friction at most "
                                  "0.163/(21 Δt) (gear5) or 2/(21 Δt) (verlet)",
                                  &Parameters::tangentialDamping},
  };
  static constexpr std::span<const std::string_view> history{};
  static constexpr EnergyTerm kEnergy[] = {{"dissipated_tangential_J", EnergyKind::Dissipated,
                                            "tangential", "by the dashpot while sticking"}};
  static constexpr std::span<const EnergyTerm> energy{kEnergy};
  static constexpr bool needsFriction = true;
  static constexpr std::string_view stableStep =
      "γt <= z/(21 Δt): a sticking contact's dashpot acts at 3.5 γt, up to 6 at once, and the "
      "integrator holds a damper only for rate·Δt <= z (0.163 gear5, 2 verlet)";

  struct Constants {
    double damping;  ///< γt [1/s]
  };
  static Constants constants(const Parameters& p) { return {p.tangentialDamping}; }

  template <NormalLaw kLaw, bool kAdvance, class ModelConstants, class Chunk>
  [[gnu::always_inline]] static void first(const ModelConstants& k, Chunk& c, std::size_t e,
                                           ContactLane& lane) {
    double ux, uy, uz;  // the powers' lead
    leadTangential(c, e, lane, ux, uy, uz);
    c.template energy<TangentialDamping>(0)[e] =
        addForce(k.template of<TangentialDamping>().damping, lane.mass, lane.vtx, lane.vty,
                 lane.vtz, ux, uy, uz, lane.tx, lane.ty, lane.tz);
  }
  /// A sliding contact's dashpot is part of the capped force: its power is in the slip.
  template <bool kAdvance, class Constants, class Chunk>
  [[gnu::always_inline]] static void second(const Constants&, Chunk& c, std::size_t e,
                                            ContactLane& lane) {
    double* power = c.template energy<TangentialDamping>(0);
    const double sticking = power[e];
    power[e] = lane.sliding ? 0.0 : sticking;
  }

  /// Its dashpot in the network's linearisation (where the spring acts), and the damping ratio
  /// of the tangential mode.
  template <class ModelConstants>
  static void linearise(const ModelConstants& k, LinearContact& c) {
    if (!(c.stiffness.tangential > 0.0)) return;
    c.damping.tangential += k.template of<TangentialDamping>().damping * c.mass;
    c.leastDampingRatio(0.5 * c.damping.tangential / std::sqrt(c.stiffness.tangential * c.mass));
  }

  /// Adds the dashpot −γt m v_t to the trial force t; returns the power it takes, γt m |v_t|².
  [[gnu::always_inline]] static double addForce(double damping, double mass, double vtx, double vty,
                                                double vtz, double ux, double uy, double uz,
                                                double& tx, double& ty, double& tz) {
    const double c = damping * mass;
    tx -= c * vtx;
    ty -= c * vty;
    tz -= c * vtz;
    return c * (vtx * (vtx + ux) + vty * (vty + uy) + vtz * (vtz + uz));
  }
};

}  // namespace granular
