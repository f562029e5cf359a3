#pragma once
/// One contact linearised about its state: every term's springs and dashpots (their
/// `linearise`, granular/contact_terms/term.hpp) on the contact's modes, for the terms a scene's
/// law includes. The step bound (network_frequency.cpp) reads the modes and names no term.
#include "contact_constants.hpp"
#include "contact_law.hpp"

namespace granular {

template <class... Terms>
void lineariseIn(TermList<Terms...>, const ContactConstants& k, bool friction, unsigned optional,
                 LinearContact& c) {
  (
      [&] {
        if constexpr (requires { Terms::linearise(k, c); }) {
          bool included = friction || !Terms::needsFriction;
          if constexpr (kOptionalIndex<Terms> >= 0) {
            included = included && ((optional >> kOptionalIndex<Terms>)&1u) != 0;
          }
          if (included) Terms::linearise(k, c);
        }
      }(),
      ...);
}

/// Adds every included term's springs and dashpots to c (friction on or off; `optional`: the
/// optional terms the material uses, kOptional's bits).
inline void lineariseContact(const ContactConstants& k, bool friction, unsigned optional,
                             LinearContact& c) {
  lineariseIn(ContactModel{}, k, friction, optional, c);
}

}  // namespace granular
