#pragma once
/// Cohesion of the simplified JKR type ("SJKR", as LIGGGHTS' `cohesion sjkr`): an attractive
/// normal force k_c A while two bodies touch, A the area of their contact circle, k_c the
/// cohesion energy density [J/m³] (docs/physics.md, "Cohesion"). For spheres of radii R_i, R_j at
/// overlap h (a wall: R_j = ∞, u_j = 1/R_j = 0)
///   A = π h (2R_i − h) (2 + (2R_i − h) u_j) (2 − h u_j) / (4 (1 + (R_i − h) u_j)²),
/// the circle where the two spheres' surfaces meet (π h (2R − h) against a wall, π (R h − h²/4)
/// between equal spheres); the bond's energy is the force's work from touch,
///   U = −k_c ∫₀ʰ A = −(π/4) k_c h² [(4R_i − h (1 + R_i u_j)) / (1 + (R_i − h) u_j) − h/3].
/// The force acts after the normal dashpot's no-pull floor, so the contact pulls; the Coulomb
/// and rolling caps see the contact's repulsion only (listed after them: LIGGGHTS'
/// tangential_reduce). It is conservative and softens the normal spring (dA/dh > 0), so it
/// adds nothing to the network's stiffness: the step bound stays an upper bound without it.
#include <cstddef>
#include <numbers>
#include <tuple>

#include "granular/contact_terms/normal_elastic.hpp"
#include "granular/contact_terms/term.hpp"

namespace granular {

struct SjkrCohesion {
  static constexpr std::string_view name = "sjkr_cohesion";

  struct Parameters {
    double cohesionEnergyDensity = 0.0;  ///< k_c [J/m³]: the pull is k_c A; 0: no cohesion
  };
  static constexpr auto parameters = std::tuple{
      NumberParameter<Parameters>{"cohesion_energy_density", "k_c", "J/m³",
                                  ValueRange::closed(0, 1e12),
                                  "SJKR cohesion: touching bodies attract with k_c times their "
                                  "contact circle's area; 0 switches cohesion off",
                                  &Parameters::cohesionEnergyDensity},
  };
  /// Under Hooke's law the pull grows with the overlap as the spring does (k_c A ≈ 2π R_ij k_c h
  /// against (2/3) E/(1−ν²) R_ij h): from k_c = E/(3π(1−ν²)) on, no overlap holds a contact and
  /// bodies pass through each other. Hertz's spring outgrows the pull at some overlap.
  template <class Material>
  static RuleProblem rule(const Material& m) {
    if (m.normalLaw == NormalLaw::Hooke &&
        2.0 * std::numbers::pi * m.cohesionEnergyDensity >= m.normalCoefficient()) {
      return {"cohesion_energy_density",
              "needs cohesion_energy_density < youngs_modulus / (3π (1 − poisson_ratio²)) with "
              "normal_law = \"hooke\": above it the pull outgrows the spring at every overlap "
              "and bodies pass through each other"};
    }
    return {};
  }
  /// A scene without cohesion runs the law's build without this term.
  static bool active(const Parameters& p) { return p.cohesionEnergyDensity > 0.0; }

  static constexpr std::span<const std::string_view> history{};
  static constexpr EnergyTerm kEnergy[] = {
      {"cohesion_J", EnergyKind::Stored, "cohesion",
       "Σ over contacts of the bond's energy −k_c ∫A dh (negative)"}};
  static constexpr std::span<const EnergyTerm> energy{kEnergy};
  static constexpr bool needsFriction = false;
  static constexpr bool mayPull = true;
  /// The contact circle needs each body's own radius.
  static constexpr bool readsBodies = true;
  static constexpr std::string_view stableStep =
      "none of its own: it softens the normal spring, and the step bound ignores that";

  struct Constants {
    double density;  ///< k_c [J/m³]
  };
  static Constants constants(const Parameters& p) { return {p.cohesionEnergyDensity}; }

  template <NormalLaw kLaw, bool kAdvance, class ModelConstants, class Chunk>
  [[gnu::always_inline]] static void first(const ModelConstants& k, Chunk& c, std::size_t e,
                                           ContactLane& lane) {
    const double kc = k.template of<SjkrCohesion>().density;
    double area, energy;
    bond(c.ri[e], 1.0 / c.rj[e], lane.h, area, energy);
    lane.normal += -kc * area;
    c.template energy<SjkrCohesion>(0)[e] = kc * energy;
  }

  /// The contact circle's area A [m²] and −∫₀ʰ A dh [m³] of bodies of radius ri and inverse
  /// radius uj (0: a wall) at overlap h.
  [[gnu::always_inline]] static void bond(double ri, double uj, double h, double& area,
                                          double& energy) {
    const double chord = 2.0 * ri - h;
    const double spread = 1.0 + (ri - h) * uj;
    area = std::numbers::pi * h * chord * (2.0 + chord * uj) * (2.0 - h * uj) /
           (4.0 * spread * spread);
    energy =
        -0.25 * std::numbers::pi * h * h * ((4.0 * ri - h * (1.0 + ri * uj)) / spread - h / 3.0);
  }
};

}  // namespace granular
