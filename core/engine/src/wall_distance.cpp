/// surfaceDistance (granular/wall.hpp): the force pass's own measure of a wall, for callers
/// outside the engine.
#include "granular/wall.hpp"
#include "wall_contact.hpp"

namespace granular {

double surfaceDistance(const Wall& w, const Vec3& x) {
  return touchOf(w, x).distance;
}

}  // namespace granular
