/// Scene builders shared by tests, app and benchmarks (packings.hpp).
#include "granular/packings.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "granular/error.hpp"
#include "unit_uniform.hpp"

namespace granular {
namespace {

/// A point uniform in the unit ball, by rejection from the cube [-1, 1)³ (accepts ~52 %).
Vec3 unitBall(std::mt19937_64& rng) {
  for (;;) {
    // Drawn one statement at a time: the order in which a call's arguments are evaluated is
    // unspecified (GCC goes right to left, clang left to right), and the seed must give the
    // same packing with every compiler. z, y, x keeps the values GCC has always given.
    const double z = 2.0 * unitUniform(rng) - 1.0;
    const double y = 2.0 * unitUniform(rng) - 1.0;
    const double x = 2.0 * unitUniform(rng) - 1.0;
    const Vec3 p(x, y, z);
    if (p.squaredNorm() <= 1.0) return p;
  }
}

void require(bool ok, const std::string& what) {
  if (!ok) throw ConfigError("denseRandomPacking: " + what);
}

}  // namespace

Particles denseRandomPacking(std::size_t n, double radiusMin, double radiusMax, double density,
                             std::uint64_t seed, BoxSpec* boxOut, const PackingLayout& layout) {
  require(std::isfinite(radiusMin) && radiusMin > 0.0, "radiusMin must be > 0");
  require(std::isfinite(radiusMax) && radiusMax >= radiusMin, "radiusMax must be >= radiusMin");
  require(std::isfinite(density) && density > 0.0, "density must be > 0");
  require(std::isfinite(layout.gap) && layout.gap >= 0.0, "layout.gap must be >= 0");
  require(layout.aspect.allFinite() && (layout.aspect.array() > 0.0).all(),
          "layout.aspect components must be > 0");
  require(layout.origin.allFinite(), "layout.origin must be finite");

  // FCC in the [001] orientation: the sites are the points (i, j, k)·h with i + j + k even, so
  // nearest neighbours (in a layer and between adjacent layers) are h·√2 = d apart.
  const double spacing = 2.0 * radiusMax * (1.0 + layout.gap);  // d [m]
  const double half = spacing / std::sqrt(2.0);                 // h [m]

  // Sites per column along x and y in proportion to the aspect, with about 2n lattice points in
  // an aspect-shaped block (half of them are sites). At least two per direction so every layer
  // holds sites.
  const Vec3& a = layout.aspect;
  const double scale =
      std::cbrt(2.0 * static_cast<double>(std::max<std::size_t>(n, 1)) / (a.x() * a.y() * a.z()));
  const long nx = std::max(2L, std::lround(a.x() * scale));
  const long ny = std::max(2L, std::lround(a.y() * scale));

  const Vec3 firstSite = layout.origin + Vec3::Constant(0.5 * spacing);
  std::mt19937_64 rng(seed);
  Particles particles;
  particles.position.reserve(n);
  particles.velocity.reserve(n);
  particles.angularVelocity.reserve(n);
  particles.radius.reserve(n);
  particles.mass.reserve(n);

  long layers = 0;  // layers holding at least one site
  for (long k = 0; particles.size() < n; ++k) {
    ++layers;
    for (long j = 0; j < ny && particles.size() < n; ++j) {
      for (long i = 0; i < nx && particles.size() < n; ++i) {
        if ((i + j + k) % 2 != 0) continue;
        // Per particle: one draw for the radius, then the jitter; the order is part of the
        // seed's meaning, keep it.
        const double r = radiusMin + (radiusMax - radiusMin) * unitUniform(rng);
        // 0.999 keeps a clear gap against round-off even for r close to radiusMax.
        const double jitter = 0.999 * std::max(0.0, 0.5 * spacing - r);
        const Vec3 site = firstSite + half * Vec3(static_cast<double>(i), static_cast<double>(j),
                                                  static_cast<double>(k));
        particles.add(site + jitter * unitBall(rng), r, density);
      }
    }
  }

  if (boxOut != nullptr) {
    BoxSpec box;  // side walls and bottom, open top
    box.min = layout.origin;
    const Vec3 sitesExtent(static_cast<double>(nx - 1), static_cast<double>(ny - 1),
                           static_cast<double>(std::max(layers, 1L) - 1));
    box.max = layout.origin + half * sitesExtent + Vec3::Constant(spacing);
    *boxOut = box;
  }
  return particles;
}

}  // namespace granular
