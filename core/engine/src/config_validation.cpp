/// Refusals of a configuration and of a scene's particles and walls (ConfigError), before any
/// state is built from them.
#include "config_validation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "granular/error.hpp"
#include "particle_fields.hpp"
#include "wall_motion.hpp"

namespace granular {
namespace {

bool finite(double x) {
  return std::isfinite(x);
}
bool finite(const Vec3& v) {
  return v.allFinite();
}

}  // namespace

void requireConfig(bool ok, const std::string& what) {
  if (!ok) throw ConfigError(what);
}

std::string shortNumber(double x) {
  std::ostringstream o;
  o.precision(6);
  o << x;
  return o.str();
}

void validateStepControl(const StepControl& c) {
  requireConfig(std::isfinite(c.safety) && c.safety > 0 && c.safety <= 1,
                "step safety = " + shortNumber(c.safety) + ": must be in (0, 1]");
  requireConfig(std::isfinite(c.contactResolution) && c.contactResolution >= 1,
                "contact resolution = " + shortNumber(c.contactResolution) +
                    " steps per contact duration: must be >= 1");
  requireConfig(c.recheckSteps >= 1, "the step's check interval must be >= 1 step");
}

namespace {

/// (Nearly) coincident centres, closer than 1e-9 (R_i + R_j), have no line of centres and so
/// no contact normal: refused, naming both particles (a duplicated row is the usual cause).
/// Overlap as such is allowed: a restored packed state overlaps. Positions are binned into
/// cells of the largest such distance, sorted by cell (z, y, x), and each particle is compared
/// with those of its own and the 26 adjacent cells. For each of the 9 (dz, dy) rows the three
/// cells (cx - 1 .. cx + 1) are one contiguous run of the sorted list, and the run's start only
/// moves forward as the particles are visited in sorted order (adding a fixed offset keeps the
/// lexicographic order), so the search is a sort and one linear sweep.
void requireDistinctCentres(const Particles& p) {
  const std::size_t n = p.size();
  if (n == 0) return;
  const double rMax = *std::max_element(p.radius.begin(), p.radius.end());
  const double cell = std::max(2e-9 * rMax, 0x1p-1022);  // at least the smallest normal double
  struct Entry {
    long long z, y, x;  // cell coordinates, compared in this order
    std::size_t index;
  };
  auto before = [](const Entry& a, long long z, long long y, long long x) {
    return a.z != z ? a.z < z : a.y != y ? a.y < y : a.x < x;
  };
  auto coord = [cell](double x) {  // clamped before the cast: finite but absurd stays defined
    return static_cast<long long>(std::clamp(std::floor(x / cell), -0x1p60, 0x1p60));
  };
  std::vector<Entry> sorted(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& x = p.position[i];
    sorted[i] = Entry{coord(x.z()), coord(x.y()), coord(x.x()), i};
  }
  std::sort(sorted.begin(), sorted.end(), [&before](const Entry& a, const Entry& b) {
    return before(a, b.z, b.y, b.x) || (!before(b, a.z, a.y, a.x) && a.index < b.index);
  });
  std::size_t runStart[9] = {};
  for (const Entry& e : sorted) {
    const std::size_t i = e.index;
    std::size_t row = 0;
    for (long long dz = -1; dz <= 1; ++dz) {
      for (long long dy = -1; dy <= 1; ++dy, ++row) {
        const long long z = e.z + dz, y = e.y + dy;
        std::size_t& b = runStart[row];
        while (b < n && before(sorted[b], z, y, e.x - 1)) ++b;
        for (std::size_t c = b; c < n && before(sorted[c], z, y, e.x + 2); ++c) {
          const std::size_t j = sorted[c].index;
          if (j == i) continue;
          const double distance = (p.position[j] - p.position[i]).norm();
          if (distance < 1e-9 * (p.radius[i] + p.radius[j])) {
            const std::size_t a = std::min(i, j), k = std::max(i, j);
            std::ostringstream msg;
            msg.precision(17);
            msg << "particles " << a << " and " << k << " have (nearly) coincident centres ("
                << p.position[a].x() << ", " << p.position[a].y() << ", " << p.position[a].z()
                << ") and (" << p.position[k].x() << ", " << p.position[k].y() << ", "
                << p.position[k].z() << "), " << distance
                << " m apart, less than 1e-9 of their radii sum: the contact has no normal";
            throw ConfigError(msg.str());
          }
        }
      }
    }
  }
}

}  // namespace

void requireWallFrictionWithin(const std::vector<Wall>& walls, const Material& material) {
  for (const Wall& w : walls) {
    // Frictionless particles run without rotations or springs: no wall can grip them.
    if (w.friction && *w.friction > 0.0 && !material.hasFriction()) {
      throw ConfigError("wall " + w.name + ": friction = " + shortNumber(*w.friction) +
                        " needs frictional particles (material friction > 0); the particles are "
                        "frictionless");
    }
  }
}

void validateScene(const SimulationConfig& cfg, const Particles& p,
                   const std::vector<Wall>& walls) {
  validateMaterial(cfg.material);
  requireConfig(std::isfinite(cfg.timeStep) && cfg.timeStep > 0,
                "time step = " + shortNumber(cfg.timeStep) + " s: must be > 0");
  requireConfig(std::isfinite(cfg.skin) && cfg.skin >= 0,
                "skin = " + shortNumber(cfg.skin) + " m: must be >= 0");
  validateStepControl(cfg.step);
  requireConfig(cfg.gravity.allFinite(), "gravity must be finite");
  requireConfig(std::isfinite(cfg.smallestRadius) && cfg.smallestRadius >= 0,
                "smallest radius = " + shortNumber(cfg.smallestRadius) + " m: must be >= 0");
  requireConfig(p.size() > 0 || cfg.smallestRadius > 0,
                "the scene has no particles (a run that inserts them all needs the smallest "
                "radius it will hold)");
  forEachParticleField(p, [&](const FieldSpec& field, const auto& array) {
    requireConfig(array.size() == p.size(),
                  "particle arrays have different lengths: " + std::to_string(array.size()) + " " +
                      std::string(field.name) + "s for " + std::to_string(p.size()) + " positions");
  });
  for (std::size_t i = 0; i < p.size(); ++i) {
    requireConfig(std::isfinite(p.radius[i]) && p.radius[i] > 0,
                  "particle " + std::to_string(i) + ": radius " + shortNumber(p.radius[i]) +
                      " m must be > 0");
    requireConfig(
        std::isfinite(p.mass[i]) && p.mass[i] > 0,
        "particle " + std::to_string(i) + ": mass " + shortNumber(p.mass[i]) + " kg must be > 0");
    forEachParticleField(p, [&](const FieldSpec& field, const auto& array) {
      requireConfig(finite(array[i]), "particle " + std::to_string(i) + ": " +
                                          std::string(field.name) + " is not finite");
    });
  }
  for (const Wall& w : walls) validateWall(w);
  requireWallFrictionWithin(walls, cfg.material);
  requireDistinctCentres(p);
}

}  // namespace granular

namespace granular {

double smallestRadius(const Particles& p, const SimulationConfig& config) {
  double r = config.smallestRadius > 0 ? config.smallestRadius : HUGE_VAL;
  for (double radius : p.radius) r = std::min(r, radius);
  return r;
}

}  // namespace granular
