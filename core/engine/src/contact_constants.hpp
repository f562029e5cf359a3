#pragma once
/// The constants the contact law reads, computed once a pass from the material: the step, and
/// each term's own (`struct Constants` and `constants(material)` in the term's file). Nothing
/// here names a term: a term's constants are reached as `k.template of<Term>()`.
#include <vector>

#include "granular/contact_model.hpp"
#include "granular/material.hpp"
#include "granular/wall.hpp"

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

/// Each wall's contact constants: the particles' (`shared`), or for a wall with its own friction
/// those of the particles' material with that friction. Scenes of walls without their own
/// friction build nothing.
class WallConstants {
 public:
  WallConstants(const std::vector<Wall>& walls, const Material& material, double dt,
                const ContactConstants& shared)
      : of_(walls.size(), &shared) {
    std::size_t own = 0;
    for (const Wall& w : walls) own += w.friction ? 1 : 0;
    if (own == 0) return;
    own_.reserve(own);  // of_ points into own_: no reallocation after this
    for (std::size_t w = 0; w < walls.size(); ++w) {
      if (!walls[w].friction) continue;
      Material m = material;
      m.friction = *walls[w].friction;
      own_.emplace_back(m, dt);
      of_[w] = &own_.back();
    }
  }
  WallConstants(const WallConstants&) = delete;
  WallConstants& operator=(const WallConstants&) = delete;

  const ContactConstants& of(std::size_t w) const { return *of_[w]; }

 private:
  std::vector<ContactConstants> own_;
  std::vector<const ContactConstants*> of_;
};

}  // namespace granular
