#pragma once
/// The mean pressure on a wall against height, from a snapshot's contacts and the wall's cells.
///
/// The pressure of a band of height is the normal push of the wall's contacts whose contact
/// points lie in it over the wall's area inside it: the area-weighted mean of the local pressure
/// there. The forces come from the contacts and not from the cells' own loads because a
/// frustum's facets run its whole length: a cylinder's cells all have their centroids at mid
/// height, and their loads say nothing of where along it the particles push.
#include <string>
#include <vector>

#include "granular/vec3.hpp"
#include "wall_cells.hpp"

namespace granular::app {

/// A wall's contacts at a snapshot.
struct WallContacts {
  std::vector<double> z;      ///< each contact point's height [m]
  std::vector<double> force;  ///< each one's normal push (normal_force_N of contact_csv.hpp) [N]
};

struct PressureBand {
  double z = 0;         ///< the band's middle [m]
  double pressure = 0;  ///< Σ normal push / area of the wall in the band [Pa]
  int contacts = 0;     ///< contacts in the band
};

/// The area of `polygon` [m²] between the heights zLow and zHigh [m].
double areaBetween(const std::vector<Vec3>& polygon, double zLow, double zHigh);

/// The wall's bands of about `bandHeight` [m] from its lowest corner to its highest (as many
/// as fit, at most 200, each of the same height), bottom first; a wall flatter than a thousandth
/// of a band is one band at its height. Bands where the wall has no area are left out.
std::vector<PressureBand> pressureProfile(const WallCells& wall, const WallContacts& contacts,
                                          double bandHeight);

}  // namespace granular::app
