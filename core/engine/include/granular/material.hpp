#pragma once
/// Material of the particles: every contact term's parameters (granular/contact_model.hpp), with
/// the paper's Table as defaults (μ = 0 case), and the constants derived from them
/// (docs/physics.md §1).
#include "granular/contact_model.hpp"

namespace granular {

struct Material : ParametersOf<ContactModel> {
  /// (8/3) G/(2-ν): multiplies sqrt(R h) in the tangential spring stiffness [Pa].
  double tangentialCoefficient() const { return 8.0 / 3.0 * shearModulus / (2.0 - poissonRatio); }
};

}  // namespace granular
