/// A stage's inserts and outlets (stage_exchange.hpp). Insertion checks a candidate against
/// the particles near the region through a hash of cells two largest radii wide, so that a
/// bed of any size costs only the particles near the region.
#include "granular/stage_exchange.hpp"
#include "unit_uniform.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <unordered_map>

namespace granular {

namespace {

/// SplitMix64's finaliser: the seed of an insert's exchange from its seed and number.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

/// A centre where a sphere of radius r lies in the region, uniform over those (drawn one
/// coordinate a statement: argument order is unspecified).
Vec3 drawCentre(const Region& region, double r, std::mt19937_64& rng) {
  if (region.shape == Region::Shape::Box) {
    Vec3 x;
    for (int k = 0; k < 3; ++k) {
      const double lo = region.min[k] + r, hi = region.max[k] - r;
      x[k] = lo + unitUniform(rng) * (hi - lo);
    }
    return x;
  }
  const double along = r + unitUniform(rng) * (region.length - 2.0 * r);
  const double rho = (region.radius - r) * std::sqrt(unitUniform(rng));
  const double angle = 2.0 * std::numbers::pi * unitUniform(rng);
  const Vec3 helper = std::abs(region.axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 u = region.axis.cross(helper).normalized();
  const Vec3 v = region.axis.cross(u);
  return region.base + along * region.axis + rho * (std::cos(angle) * u + std::sin(angle) * v);
}

/// Particles near a region, hashed by cell.
class CellHash {
 public:
  explicit CellHash(double cell) : cell_(cell) {}
  void add(const Vec3& x, double r) {
    cells_[key(cellOf(x))].push_back(centres_.size());
    centres_.push_back(x);
    radii_.push_back(r);
  }
  /// Whether a sphere (x, r) overlaps any sphere held (r + their radius ≤ cell).
  bool overlaps(const Vec3& x, double r) const {
    const std::array<std::int64_t, 3> c = cellOf(x);
    for (std::int64_t dz = -1; dz <= 1; ++dz) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dx = -1; dx <= 1; ++dx) {
          const auto it = cells_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == cells_.end()) continue;
          for (std::size_t k : it->second) {
            const double reach = r + radii_[k];
            if ((centres_[k] - x).squaredNorm() < reach * reach) return true;
          }
        }
      }
    }
    return false;
  }

 private:
  std::array<std::int64_t, 3> cellOf(const Vec3& x) const {
    std::array<std::int64_t, 3> c{};
    for (int k = 0; k < 3; ++k) {
      c[std::size_t(k)] =
          static_cast<std::int64_t>(std::clamp(std::floor(x[k] / cell_), -1e15, 1e15));
    }
    return c;
  }
  static std::uint64_t key(const std::array<std::int64_t, 3>& c) {
    return mix(std::uint64_t(c[0]) ^ mix(std::uint64_t(c[1]) ^ mix(std::uint64_t(c[2]))));
  }
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
  std::vector<Vec3> centres_;
  std::vector<double> radii_;
};

}  // namespace

Particles placeInserted(const InsertSpec& insert, std::uint64_t wanted, std::uint64_t first,
                        std::uint64_t event, const Particles& whole, const std::vector<Wall>& walls,
                        double density) {
  Particles placed;
  if (wanted == 0) return placed;
  double rMax = insert.radiusMax;
  for (double r : whole.radius) rMax = std::max(rMax, r);
  // A cell two largest radii wide holds every partner of a sphere within its 27 cells.
  CellHash hash(2.0 * rMax);
  const Vec3 lo = insert.region.lower().array() - 2.0 * rMax;
  const Vec3 hi = insert.region.upper().array() + 2.0 * rMax;
  for (std::size_t i = 0; i < whole.size(); ++i) {
    const Vec3& x = whole.position[i];
    if ((x.array() >= lo.array()).all() && (x.array() <= hi.array()).all()) {
      hash.add(x, whole.radius[i]);
    }
  }
  std::mt19937_64 rng(mix(insert.seed ^ mix(event)));
  // The radii's own stream, a different function of the seed than the centres'.
  const std::uint64_t radiusSeed = mix(insert.seed ^ 0x9e3779b97f4a7c15ULL);
  for (std::uint64_t k = 0; k < wanted; ++k) {
    const double u = double(mix(radiusSeed ^ mix(first + k)) >> 11) * 0x1.0p-53;
    const double r = insert.radiusMin + u * (insert.radiusMax - insert.radiusMin);
    bool found = false;
    for (int t = 0; t < 100 && !found; ++t) {
      const Vec3 x = drawCentre(insert.region, r, rng);
      if (hash.overlaps(x, r)) continue;
      const bool touchesWall = std::any_of(walls.begin(), walls.end(), [&](const Wall& w) {
        return !w.removed && surfaceNearer(w, x, r);
      });
      if (touchesWall) continue;
      hash.add(x, r);
      placed.add(x, r, density, insert.velocity);
      found = true;
    }
    if (!found) break;
  }
  return placed;
}

std::vector<std::size_t> particlesInOutlets(const std::vector<OutletSpec>& outlets,
                                            const Particles& whole) {
  std::vector<std::size_t> inside;
  for (std::size_t i = 0; i < whole.size(); ++i) {
    for (const OutletSpec& outlet : outlets) {
      if (outlet.region.holds(whole.position[i])) {
        inside.push_back(i);
        break;
      }
    }
  }
  return inside;
}

StageExchange::StageExchange(const StageSpec& stage, double tolerance)
    : stage_(stage),
      tolerance_(tolerance),
      active_(!stage.inserts.empty() || !stage.outlets.empty()) {}

void StageExchange::resumeAt(double t) {
  next_ = std::uint64_t(std::floor((t + tolerance_) / stage_.exchangeInterval)) + 1;
}

double StageExchange::next() const {
  return active_ ? double(next_) * stage_.exchangeInterval
                 : std::numeric_limits<double>::infinity();
}

bool StageExchange::due(double t) const {
  return active_ && t + tolerance_ >= next();
}

void StageExchange::apply(Simulation& sim, double t) {
  if (!due(t)) return;
  const std::uint64_t event = std::uint64_t(std::floor((t + tolerance_) / stage_.exchangeInterval));
  next_ = event + 1;
  const double density = sim.config().material.density;
  // An exchange with nothing to insert and nothing in an outlet is skipped: a split run would
  // gather the whole state for it.
  std::vector<std::uint64_t> wanted;
  for (const InsertSpec& insert : stage_.inserts) {
    const double due = std::floor(insert.rate * t + 1e-9);
    const std::uint64_t total = std::min<std::uint64_t>(insert.count, std::uint64_t(due));
    const std::uint64_t in = sim.insertedBy(insert.source);
    wanted.push_back(total > in ? total - in : 0);
  }
  const bool inserts = std::any_of(wanted.begin(), wanted.end(), [](auto n) { return n > 0; });
  const bool removes = !stage_.outlets.empty() && sim.anyParticleWhere([&](const Vec3& x) {
    return std::any_of(stage_.outlets.begin(), stage_.outlets.end(),
                       [&](const OutletSpec& o) { return o.region.holds(x); });
  });
  if (!inserts && !removes) return;
  bool outletsDone = !removes;
  for (std::size_t k = 0; k < stage_.inserts.size(); ++k) {
    const InsertSpec& insert = stage_.inserts[k];
    if (wanted[k] == 0 && outletsDone) continue;
    const std::vector<Wall>& walls = sim.walls();
    sim.exchangeParticles([&](const Particles& whole) {
      ParticleExchange x;
      if (!outletsDone) x.remove = particlesInOutlets(stage_.outlets, whole);
      x.insert = placeInserted(insert, wanted[k], sim.insertedBy(insert.source), event, whole,
                               walls, density);
      x.source = insert.source;
      return x;
    });
    outletsDone = true;
  }
  if (!outletsDone) {
    sim.exchangeParticles([&](const Particles& whole) {
      ParticleExchange x;
      x.remove = particlesInOutlets(stage_.outlets, whole);
      return x;
    });
  }
}

bool StageExchange::insertsDone(const Simulation& sim) const {
  return std::all_of(stage_.inserts.begin(), stage_.inserts.end(),
                     [&](const InsertSpec& i) { return sim.insertedBy(i.source) >= i.count; });
}

}  // namespace granular
