#pragma once
/// The grid generator's sampling, in one place: the builder places the particles with it and
/// the scene loader checks them with it (against the box, for the time-step limit) before the
/// run, so the two can never disagree.
#include <cstddef>
#include <functional>

#include "granular/scene.hpp"
#include "particle_csv.hpp"

namespace granular {

/// Calls `visit(k, particle)` for the grid's particles k = 0 .. count-1 in order, without
/// storing them (the loader checks grids of up to 1e8 particles this way).
void forEachGridParticle(const GridGenerator& grid,
                         const std::function<void(std::size_t, const CsvParticle&)>& visit);

}  // namespace granular
