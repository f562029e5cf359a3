/// The contact law's loops on a chunk, in the process's vector build (chunk_kernels.hpp).
#include "chunk_kernels.hpp"

#include "granular/simd_build.hpp"

namespace granular {
namespace {

/// The law's loops (contact_law.hpp) run in the process's vector build (simdDispatch,
/// granular/simd_build.hpp): each body below inlines the kernels, so the whole loop is compiled
/// for that target; tests/test_force_kernels.cpp checks that the builds give the same bits.
[[gnu::always_inline]] inline void geometryBody(ContactChunk& c, std::size_t m, bool friction) {
  friction ? pairGeometry<true>(c, m) : pairGeometry<false>(c, m);
}

/// The law's build for one mask of optional terms (contact_law.hpp, kOptional).
template <unsigned kOptional>
[[gnu::always_inline]] inline void lawOf(const ContactConstants& constants, ContactChunk& c,
                                         std::size_t m, bool friction, NormalLaw law,
                                         bool advance) {
  const bool hertz = law == NormalLaw::Hertz;
  if (friction) {
    if (hertz) {
      advance ? contactLaw<true, kOptional, NormalLaw::Hertz, true>(constants, c, m)
              : contactLaw<true, kOptional, NormalLaw::Hertz, false>(constants, c, m);
    } else {
      advance ? contactLaw<true, kOptional, NormalLaw::Hooke, true>(constants, c, m)
              : contactLaw<true, kOptional, NormalLaw::Hooke, false>(constants, c, m);
    }
  } else {  // no spring: advancing or not is the same
    hertz ? contactLaw<false, kOptional, NormalLaw::Hertz, true>(constants, c, m)
          : contactLaw<false, kOptional, NormalLaw::Hooke, true>(constants, c, m);
  }
}

/// Each mask's build is a function of its own in each vector build: a scene runs one mask, whose
/// loops then sit in a small function rather than among every mask's.
template <unsigned... kMasks>
void lawOfMask(std::integer_sequence<unsigned, kMasks...>, const ContactConstants& constants,
               ContactChunk& c, std::size_t m, bool friction, NormalLaw law, bool advance,
               unsigned optional) {
  ((optional == kMasks ? simdDispatch<lawOf<kMasks>>(constants, c, m, friction, law, advance)
                       : void()),
   ...);
}

}  // namespace

void geometry(ContactChunk& c, std::size_t m, bool friction) {
  simdDispatch<geometryBody>(c, m, friction);
}
void law(const ContactConstants& constants, ContactChunk& c, std::size_t m, bool friction,
         NormalLaw normalLaw, bool advance, unsigned optional) {
  lawOfMask(OptionalMasks{}, constants, c, m, friction, normalLaw, advance, optional);
}

}  // namespace granular
