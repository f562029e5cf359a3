#pragma once
/// A cache-friendly particle order. The force pass reads, for every candidate pair (i, j), the
/// state of both particles; when particles that are close in space also have close indices,
/// those reads hit memory the pass has just touched. Packings built layer by layer put a
/// particle's upper neighbours a whole layer of indices away (10⁴ to 10⁵ on large beds), which
/// measured 2.4× slower than this order on a 10⁵-particle bed (bench/RESULTS.md).
#include <cstddef>
#include <vector>

#include "granular/particles.hpp"
#include "granular/vec3.hpp"

namespace granular {

/// The permutation that lists particles cell by cell along a Morton (Z-order) curve through
/// cubic cells of side `cell` [m] (> 0; a particle diameter is a good choice): new index k holds
/// old particle order[k]. Z-order keeps space close to memory at every scale, from a cell to
/// the whole bed. Ties (same cell) keep their old order, so the result is deterministic.
std::vector<std::size_t> spatialOrder(const std::vector<Vec3>& positions, double cell);

/// The particles in the order `order` (a permutation of 0..n-1, as spatialOrder returns).
Particles reordered(const Particles& particles, const std::vector<std::size_t>& order);

}  // namespace granular
