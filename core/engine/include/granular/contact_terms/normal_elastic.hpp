#pragma once
/// Normal elastic force F = (2/3) E/(1-ν²) R^(2-α) h^α, α = 1 (Hooke) or 3/2 (Hertz)
/// (docs/physics.md §1, Eq. (3)), and the elastic energy it stores, ∫F dh.
#include <cmath>
#include <cstddef>
#include <tuple>

#include "granular/contact_terms/term.hpp"

namespace granular {

/// Normal elastic law: F = (2/3) E/(1-ν²) R^(2-α) h^α with α = 1 (Hooke) or α = 3/2 (Hertz).
enum class NormalLaw { Hooke, Hertz };

struct NormalElastic {
  static constexpr std::string_view name = "normal_elastic";
  static constexpr std::string_view kLawNames[] = {"hooke", "hertz"};

  struct Parameters {
    NormalLaw normalLaw = NormalLaw::Hooke;  ///< α = 1 (Hooke) or 3/2 (Hertz)
    double youngModulus = 0.3e6;             ///< elastic modulus E [Pa]
    double poissonRatio = 0.30;              ///< Poisson's ratio ν [-]

    /// (2/3) E/(1-ν²): multiplies R^(2-α) h^α in the normal elastic force [Pa].
    double normalCoefficient() const {
      return 2.0 / 3.0 * youngModulus / (1.0 - poissonRatio * poissonRatio);
    }
    /// α of the normal law [-].
    double exponent() const { return normalLaw == NormalLaw::Hooke ? 1.0 : 1.5; }
  };
  /// The modulus' upper bound catches a unit slip (MPa written as Pa × 1e6 twice).
  static constexpr auto parameters = std::tuple{
      ChoiceParameter<Parameters, NormalLaw>{"normal_law", "α", kLawNames,
                                             "α = 1 (hooke) or 3/2 (hertz) in "
                                             "F = (2/3)E/(1−ν²)·R^(2−α)·h^α",
                                             &Parameters::normalLaw},
      NumberParameter<Parameters>{"youngs_modulus", "E", "Pa", ValueRange::aboveUpTo(0, 1e12),
                                  "elastic modulus", &Parameters::youngModulus},
      NumberParameter<Parameters>{"poisson_ratio", "ν", "-", ValueRange::halfOpen(0, 0.5),
                                  "Poisson's ratio", &Parameters::poissonRatio},
  };
  static constexpr std::span<const std::string_view> history{};
  static constexpr EnergyTerm kEnergy[] = {
      {"elastic_normal_J", EnergyKind::Stored, "normal", "Σ over contacts of ∫ F_n^e dh"}};
  static constexpr std::span<const EnergyTerm> energy{kEnergy};
  static constexpr bool needsFriction = false;
  static constexpr std::string_view stableStep =
      "the contact's duration: the step is at most 1/50 (gear5) or 1/10 (verlet) of the stiffest "
      "contact's";

  struct Constants {
    double coefficient;  ///< (2/3) E/(1-ν²) [Pa]
    NormalLaw law;
  };
  static Constants constants(const Parameters& p) { return {p.normalCoefficient(), p.normalLaw}; }

  /// The elastic force, added to the normal force, and the energy it stores.
  template <NormalLaw kLaw, bool kAdvance, class ModelConstants, class Chunk>
  [[gnu::always_inline]] static void first(const ModelConstants& k, Chunk& c, std::size_t e,
                                           ContactLane& lane) {
    double stored;
    force<kLaw>(k.template of<NormalElastic>().coefficient, lane.radius, lane.h, lane.elastic,
                stored);
    lane.normal += lane.elastic;
    c.template energy<NormalElastic>(0)[e] = stored;
  }

  /// Its spring in the network's linearisation: k_n = dF/dh.
  template <class ModelConstants>
  static void linearise(const ModelConstants& k, LinearContact& c) {
    const Constants& own = k.template of<NormalElastic>();
    c.stiffness.normal += own.law == NormalLaw::Hooke
                              ? stiffness<NormalLaw::Hooke>(own.coefficient, c.radius, c.overlap)
                              : stiffness<NormalLaw::Hertz>(own.coefficient, c.radius, c.overlap);
  }

  /// dF/dh of the elastic force: k R (Hooke), (3/2) k √(R h) (Hertz) [N/m].
  template <NormalLaw kLaw>
  [[gnu::always_inline]] static double stiffness(double coefficient, double radius, double h) {
    if constexpr (kLaw == NormalLaw::Hooke) {
      return coefficient * radius;
    } else {
      return 1.5 * coefficient * std::sqrt(radius * h);
    }
  }

  /// Elastic force k R^(2-α) h^α and the energy it stores (k: the normal coefficient).
  template <NormalLaw kLaw>
  [[gnu::always_inline]] static void force(double coefficient, double radius, double h,
                                           double& force, double& stored) {
    if constexpr (kLaw == NormalLaw::Hooke) {
      force = coefficient * radius * h;
      stored = 0.5 * force * h;
    } else {
      force = coefficient * std::sqrt(radius * h) * h;
      stored = 0.4 * force * h;
    }
  }
};

}  // namespace granular
