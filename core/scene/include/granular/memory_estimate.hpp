#pragma once
/// What a scene's simulation will need in memory, checked before anything per particle is
/// allocated, so that a scene too large for the machine is refused at once with the estimate and
/// what is available, rather than ending in std::bad_alloc part-way through.
#include <cstdint>

#include "granular/scene.hpp"

namespace granular {

struct MemoryEstimate {
  std::uint64_t particles = 0;  ///< grid counts plus CSV rows (an upper bound: lines)
  double bytesPerParticle = 0;  ///< at the peak of a neighbour-list rebuild [B]
  std::uint64_t bytes = 0;      ///< particles × bytesPerParticle + the program itself [B]
  const char* model = "";       ///< "frictional Gear5", ...
};

/// Bytes per particle at the peak, measured on settled beds of 10⁵–10⁶ spheres
/// (bench/CHANGELOG.md, 2026-11-25, "Peak through a rebuild"; bench/RESULTS.md, "The engine now"),
/// rounded up: a frictionless velocity-Verlet bed 310 B; friction (springs, spins, torques) adds 90
/// B; Gear5 keeps four more derivatives of each integrated vector, 96 B for the translations and 96
/// B for the rotations.
MemoryEstimate estimateMemory(const Scene& scene);

/// ConfigError naming the scene, the estimate and the memory available when the estimate
/// exceeds it (availableMemoryBytes); no check where the available memory cannot be read.
void requireMemoryFor(const Scene& scene);

}  // namespace granular
