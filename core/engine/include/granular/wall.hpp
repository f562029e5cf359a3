#pragma once
/// Plane walls. A wall is a body of infinite radius and mass (docs/physics.md §2.3).
#include <string>

#include "granular/vec3.hpp"

namespace granular {

/// An infinite plane through `point` with unit `normal` pointing into the granular domain.
struct Wall {
  std::string name;              ///< "x-", "x+", "y-", "y+", "bottom", "top" or user's
  Vec3 point = Vec3::Zero();     ///< a point of the plane [m]
  Vec3 normal = Vec3::UnitZ();   ///< unit normal into the domain [-]
  Vec3 velocity = Vec3::Zero();  ///< prescribed translation velocity [m/s]
  Vec3 reaction = Vec3::Zero();  ///< force of the particles on the wall at the last step [N]
  /// ∫ reaction dt since the start [N s]: the mean reaction over any interval is the difference
  /// of two readings over its length (Eq. 2 asks for averaged reactions).
  Vec3 impulse = Vec3::Zero();
};

}  // namespace granular
