#pragma once
/// A wall's prescribed motion over a step, and the refusals of a wall's shape and motion.
#include "granular/wall.hpp"

namespace granular {

/// Moves the wall by its translation and turn over dt: an infinite plane by its velocity; a
/// shell also turns its frame about the axis through its pivot (unless the turn is about its
/// own axis of symmetry, which leaves its surface in place) and adds the bound on its surface's
/// move to Wall::travel.
void moveWall(Wall& w, double dt);

/// ConfigError naming the wall and the value unless its shape and motion are well posed: unit
/// normal (and edge, normal to it), finite sizes > 0, a segment of nonzero length, and no turn
/// of an infinite plane.
void validateWall(const Wall& w);

}  // namespace granular
