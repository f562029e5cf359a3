#include "granular/spatial_order.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "particle_fields.hpp"

namespace granular {
namespace {

/// Spreads the low 21 bits of v so that two zero bits follow each: bit b moves to bit 3b.
std::uint64_t spreadBits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

}  // namespace

std::vector<std::size_t> spatialOrder(const std::vector<Vec3>& positions, double cell) {
  if (!(cell > 0.0) || !std::isfinite(cell)) {
    throw std::invalid_argument("spatialOrder: cell size must be a positive number of metres");
  }
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity());
  for (const Vec3& x : positions) {
    for (int axis = 0; axis < 3; ++axis) {
      if (std::isfinite(x[axis])) low[axis] = std::min(low[axis], x[axis]);
    }
  }
  std::vector<std::pair<std::uint64_t, std::size_t>> keyed(positions.size());
  constexpr double kMaxCell = 0x1fffff;  // 21 bits a coordinate
  for (std::size_t i = 0; i < positions.size(); ++i) {
    std::uint64_t code = 0;
    for (int axis = 0; axis < 3; ++axis) {
      // Clamped, so a far or non-finite position still gets a cell (the last one).
      const double c = std::floor((positions[i][axis] - low[axis]) / cell);
      const double clamped = c >= 0.0 ? std::min(c, kMaxCell) : kMaxCell;
      code |= spreadBits(static_cast<std::uint64_t>(clamped)) << axis;
    }
    keyed[i] = {code, i};
  }
  std::sort(keyed.begin(), keyed.end());  // (code, old index): ties keep their order
  std::vector<std::size_t> order(positions.size());
  for (std::size_t k = 0; k < keyed.size(); ++k) order[k] = keyed[k].second;
  return order;
}

Particles reordered(const Particles& p, const std::vector<std::size_t>& order) {
  if (order.size() != p.size()) {
    throw std::invalid_argument("reordered: the order has " + std::to_string(order.size()) +
                                " entries for " + std::to_string(p.size()) + " particles");
  }
  std::vector<bool> seen(p.size(), false);
  for (std::size_t i : order) {
    if (i >= p.size() || seen[i]) {
      throw std::invalid_argument("reordered: the order is not a permutation of 0.." +
                                  std::to_string(p.size() - 1));
    }
    seen[i] = true;
  }
  Particles out;
  forEachParticleFieldPair(p, out, [&](const FieldSpec&, const auto& from, auto& to) {
    to.reserve(from.size());
    for (std::size_t i : order) to.push_back(from[i]);
  });
  return out;
}

}  // namespace granular
