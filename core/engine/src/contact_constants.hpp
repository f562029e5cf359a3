#pragma once
/// The constants the contact law reads, computed once a pass from the material: the step, and
/// each term's own (`struct Constants` and `constants(material)` in the term's file). Nothing
/// here names a term: a term's constants are reached as `k.template of<Term>()`.
#include "granular/contact_model.hpp"
#include "granular/material.hpp"

namespace granular {

/// A term's own constants, or nothing for a term that declares none.
template <class T>
struct TermConstantsOf {
  struct type {};
  static type of(const Material&) { return {}; }
};
template <class T>
requires requires {
  typename T::Constants;
}
struct TermConstantsOf<T> {
  using type = typename T::Constants;
  static type of(const Material& m) { return T::constants(m); }
};
template <class T>
struct TermConstantsSlot {
  typename TermConstantsOf<T>::type value;
};
template <class List>
struct ModelConstants;
/// Every term's own constants.
template <class... Terms>
struct ModelConstants<TermList<Terms...>> : TermConstantsSlot<Terms>... {
  explicit ModelConstants(const Material& m)
      : TermConstantsSlot<Terms>{TermConstantsOf<Terms>::of(m)}... {}
};

/// Constants of the law for a scene and step.
struct ContactConstants {
  double dt;                           ///< the step [s]
  ModelConstants<ContactModel> terms;  ///< each term's own constants
  double reach;  ///< how far beyond touch the terms act [m] (reachBeyondTouch)

  ContactConstants(const Material& material, double step)
      : dt(step), terms(material), reach(reachBeyondTouch(material)) {}

  /// Term T's own constants (its `Constants`).
  template <class T>
  const typename TermConstantsOf<T>::type& of() const {
    return static_cast<const TermConstantsSlot<T>&>(terms).value;
  }
};

}  // namespace granular
