#pragma once
/// Scene builders shared by the tests, the app and the benchmarks (docs/architecture.md: they live
/// in one place, like Box2D's `shared/`). Each builder is deterministic from its seed on every
/// platform: it draws raw 64-bit numbers from std::mt19937_64 (whose sequence the standard fixes)
/// and maps them to [0, 1) itself, because std::uniform_real_distribution is
/// implementation-defined.
#include <cstddef>
#include <cstdint>

#include "granular/particles.hpp"
#include "granular/scene.hpp"
#include "granular/vec3.hpp"

namespace granular {

/// Shape and spacing of a dense random packing.
struct PackingLayout {
  Vec3 origin = Vec3::Zero();  ///< lower corner of the box [m]
  /// Relative edge lengths x:y:z of the filled region [-]. The footprint follows it; the height
  /// is whatever the count needs, so the z ratio is met only approximately.
  Vec3 aspect = Vec3::Ones();
  /// Nearest-neighbour lattice spacing d = 2·radiusMax·(1 + gap) [-]; >= 0. Larger gaps give
  /// looser packings with more room for jitter.
  double gap = 0.02;
};

/// A dense, contact-free random packing of `n` spheres at rest, for tests and benchmarks.
///
/// The centres start on a face-centred cubic lattice in the [001] orientation (square layers
/// parallel to the floor, each layer shifted by half a diagonal) with nearest-neighbour spacing
/// d = 2·radiusMax·(1 + layout.gap) [m], filled x fastest, then y, then layer by layer upward, so
/// an incomplete last layer is on top. Each sphere gets a radius uniform in [radiusMin, radiusMax)
/// [m] and a centre displaced uniformly within a ball of radius 0.999·(d/2 − R_i) [m] around its
/// site, which keeps every pair and every box face strictly apart. Velocities and angular
/// velocities are zero; masses follow from `density` [kg/m³].
///
/// With gap = 0.02 and the paper's radii (0.030–0.035 m) the solid fraction is about 0.56 in the
/// bulk; the margins at the faces bring the whole box to 0.50 (2000 spheres) to 0.55 (10⁵).
///
/// `boxOut`, if given, receives the box enclosing the packing: its faces lie d/2 beyond the
/// outermost sites, so no sphere touches a face. Walls are on the four sides and the bottom; the
/// top is open (BoxSpec's default, as in the paper's stage 1). The top face is a valid place for a
/// lid: set `walls[5] = true` to close the box.
///
/// Throws ConfigError on radiusMin <= 0, radiusMax < radiusMin, density <= 0, a negative gap or
/// a non-positive aspect component. n = 0 gives no particles and a one-site box.
Particles denseRandomPacking(std::size_t n, double radiusMin, double radiusMax, double density,
                             std::uint64_t seed, BoxSpec* boxOut = nullptr,
                             const PackingLayout& layout = {});

}  // namespace granular
