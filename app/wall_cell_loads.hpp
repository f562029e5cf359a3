#pragma once
/// The particles' force on each cell of a wall as walls.vtp draws it (vtk_snapshot.hpp): a
/// mesh's triangles, a frustum's facets around its axis, the one quad of a rectangle or an
/// infinite plane. Each wall contact goes to the cell under its contact point.
#include <cstddef>
#include <vector>

#include "granular/simulation.hpp"

namespace granular::app {

/// Facets of a drawn frustum around its axis.
inline constexpr int kFrustumFacets = 48;

/// Two unit vectors normal to a frustum's axis and to each other: facet k spans the angles
/// [k, k + 1] · 2π / kFrustumFacets from the first towards the second.
struct FrustumBasis {
  Vec3 e1, e2;
};
FrustumBasis frustumBasis(const Wall& wall);

/// How many cells the wall is drawn with.
std::size_t wallCellCount(const Wall& wall);

/// Per wall, per cell: the force of the particles on it [N] (Σ of −F over its contacts, F the
/// force on the particle); the cells of one wall sum to its reaction.
std::vector<std::vector<Vec3>> wallCellForces(const Simulation& sim);

}  // namespace granular::app
