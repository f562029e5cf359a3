#pragma once
/// The contact law's loops on a chunk of contacts (contact_law.hpp), in the process's vector
/// build (granular/simd_build.hpp), and the dispatch from a scene's material to the law's
/// compile-time build (friction, normal law, optional terms).
#include <cstddef>
#include <utility>

#include "contact_constants.hpp"
#include "contact_law.hpp"
#include "simulation_state.hpp"

namespace granular {

/// The geometry of the chunk's m pairs from their raw columns (pairGeometry).
void geometry(ContactChunk& c, std::size_t m, bool friction);
/// The law on the chunk's m contacts (contactLaw) in the build of (friction, normalLaw,
/// optional); with `advance` the history is advanced.
void law(const ContactConstants& constants, ContactChunk& c, std::size_t m, bool friction,
         NormalLaw normalLaw, bool advance, unsigned optional);

/// Every mask of the model's optional terms: 2^kOptionalTerms builds of the law.
using OptionalMasks = std::make_integer_sequence<unsigned, (1u << kOptionalTerms)>;

template <bool kFriction, NormalLaw kLaw, class F, unsigned... kMasks>
void withMask(std::integer_sequence<unsigned, kMasks...>, unsigned optional, F&& f) {
  ((optional == kMasks ? f.template operator()<kFriction, kLaw, kMasks>() : void()), ...);
}

/// Calls f<kFriction, kLaw, kOptional>() for the scene's friction, normal law and optional terms.
template <class F>
void withLaw(const SimulationState& s, F&& f) {
  const bool hertz = s.config.material.normalLaw == NormalLaw::Hertz;
  const unsigned optional = optionalMask(s.config.material);
  if (s.frictional) {
    hertz ? withMask<true, NormalLaw::Hertz>(OptionalMasks{}, optional, f)
          : withMask<true, NormalLaw::Hooke>(OptionalMasks{}, optional, f);
  } else {
    hertz ? withMask<false, NormalLaw::Hertz>(OptionalMasks{}, optional, f)
          : withMask<false, NormalLaw::Hooke>(OptionalMasks{}, optional, f);
  }
}

}  // namespace granular
