/// Building a runnable simulation from a Scene: particles from the generators, walls from the box.
/// Sections: 1. grid generator; 2. particle checks (inside the box, no spin without friction, no
/// overlap); 3. buildParticles, buildWalls, buildSimulation.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "granular/error.hpp"
#include "granular/memory_estimate.hpp"
#include "granular/scene.hpp"
#include "grid_sampling.hpp"
#include "number_format.hpp"
#include "particle_csv.hpp"
#include "unit_uniform.hpp"

namespace granular {

namespace {

std::string formatPoint(const Vec3& x) {
  return "(" + formatNumber(x.x()) + ", " + formatNumber(x.y()) + ", " + formatNumber(x.z()) + ")";
}

// 1. Grid generator -------------------------------------------------------------------------------

void checkGrid(const GridGenerator& g, std::size_t index) {
  const std::string where = "particle generator " + std::to_string(index) + " (grid): ";
  const double capacity = double(g.cells[0]) * double(g.cells[1]) * double(g.cells[2]);
  if (!(g.cellSize > 0.0) || !std::isfinite(g.cellSize)) {
    throw ConfigError(where + "cell size must be > 0, got " + formatNumber(g.cellSize));
  }
  if (g.cells[0] < 1 || g.cells[1] < 1 || g.cells[2] < 1) {
    throw ConfigError(where + "every cell count must be >= 1");
  }
  if (g.count < 1 || double(g.count) > capacity) {
    throw ConfigError(where + "count " + std::to_string(g.count) + " must be in [1, " +
                      formatNumber(capacity) + "]");
  }
  if (!(g.radiusMin > 0.0) || !(g.radiusMax >= g.radiusMin) || !(2.0 * g.radiusMax <= g.cellSize)) {
    throw ConfigError(where + "radii [" + formatNumber(g.radiusMin) + ", " +
                      formatNumber(g.radiusMax) + "] must satisfy 0 < min <= max <= cell size/2");
  }
  if (!(g.speedMax >= 0.0) || !std::isfinite(g.speedMax)) {
    throw ConfigError(where + "speed max must be >= 0, got " + formatNumber(g.speedMax));
  }
}

/// Cell k (k < count) is filled x fastest, then y, then z; its centre is origin + (i+½, j+½,
/// l+½)·a. Each particle takes exactly four draws from std::mt19937_64(seed), in this order:
///   u_r → radius R = R_min + (R_max − R_min)·u_r
///   u_s → speed  s = speedMax·u_s
///   u_z → direction's z component c = 1 − 2·u_z (uniform in c is uniform on the sphere,
///         Archimedes' hat-box theorem)
///   u_φ → azimuth φ = 2π·u_φ; direction = (√(1−c²) cos φ, √(1−c²) sin φ, c)
/// with u = (draw >> 11)·2⁻⁵³. The draws do not depend on speedMax, so changing the speed keeps
/// the radii.
void sampleGrid(const GridGenerator& g,
                const std::function<void(std::size_t, const CsvParticle&)>& visit) {
  std::mt19937_64 rng(g.seed);
  const std::size_t nx = std::size_t(g.cells[0]), ny = std::size_t(g.cells[1]);
  for (std::size_t k = 0; k < g.count; ++k) {
    const Vec3 cell(double(k % nx), double((k / nx) % ny), double(k / (nx * ny)));
    const double uRadius = unitUniform(rng);
    const double uSpeed = unitUniform(rng);
    const double uCos = unitUniform(rng);
    const double uAzimuth = unitUniform(rng);
    const double c = 1.0 - 2.0 * uCos;
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    const double phi = 2.0 * std::numbers::pi * uAzimuth;
    CsvParticle p;
    p.position = g.origin + (cell + Vec3::Constant(0.5)) * g.cellSize;
    p.radius = g.radiusMin + (g.radiusMax - g.radiusMin) * uRadius;
    p.velocity = g.speedMax * uSpeed * Vec3(s * std::cos(phi), s * std::sin(phi), c);
    visit(k, p);
  }
}

// 2. Particle checks ------------------------------------------------------------------------------

/// Whether a particle is a saved state's (CsvGenerator::savedState): only those carry a mass.
bool fromSavedState(const CsvParticle& p) {
  return p.mass > 0.0;
}

/// The x and y faces and the floor always bound the particles; the top only when it is a wall,
/// because the paper's particles start in a grid above an open box. A saved state's particle
/// may press into a wall (a settled bed does): its centre must be inside.
void checkInsideBox(const std::vector<CsvParticle>& particles, const BoxSpec& box) {
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const CsvParticle& p = particles[i];
    const double reach = fromSavedState(p) ? 0.0 : p.radius;
    for (std::size_t face = 0; face < kBoxWallNames.size(); ++face) {
      if (face == 5 && !box.walls[5]) continue;
      const int axis = int(face / 2);
      const bool lower = face % 2 == 0;
      const double x = p.position[axis];
      const bool outside = lower ? x - reach < box.min[axis] : x + reach > box.max[axis];
      if (outside) {
        throw ConfigError("particle " + std::to_string(i) + " at " + formatPoint(p.position) +
                          " with radius " + formatNumber(p.radius) + " m " +
                          (fromSavedState(p) ? "has its centre beyond" : "crosses") +
                          " the box face " + kBoxWallNames[face] + " at " + "xyz"[axis] + " = " +
                          formatNumber(lower ? box.min[axis] : box.max[axis]) + " m");
      }
    }
  }
}

/// A saved state keeps its masses, and the run's density must be theirs: the contact scale,
/// the step's limits and every particle added beside them use it.
void checkSavedMasses(const std::vector<CsvParticle>& particles, double density,
                      const std::function<std::string(std::size_t)>& describe) {
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const CsvParticle& p = particles[i];
    if (!fromSavedState(p)) continue;
    const double own = p.mass / (4.0 / 3.0 * std::numbers::pi * std::pow(p.radius, 3));
    if (!(std::abs(own - density) <= 1e-9 * density)) {
      throw ConfigError(describe(i) + ": its mass " + formatNumber(p.mass) + " kg and radius " +
                        formatNumber(p.radius) + " m give a density of " + formatNumber(own) +
                        " kg/m³, and the run's is " + formatNumber(density) +
                        " kg/m³: a saved state keeps its masses, so set material.density (or "
                        "total_mass) to what the run that saved it had");
    }
  }
}

/// Without friction nothing turns a particle and the engine keeps no rotation: a spin given to
/// a frictionless scene would be dropped without a word, so it is refused instead.
void checkNoSpin(const std::vector<CsvParticle>& particles) {
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if ((particles[i].angularVelocity.array() != 0.0).any()) {
      throw ConfigError("particle " + std::to_string(i) + " spins at " +
                        formatPoint(particles[i].angularVelocity) +
                        " rad/s in a frictionless scene (friction = 0), which has no rotation");
    }
  }
}

/// Cell search: cells of edge 2·R_max, so overlapping particles are in the same or adjacent cells.
/// Sorting by cell and looking neighbours up by binary search is O(N log N) with no grid to size.
void checkNoOverlap(const std::vector<CsvParticle>& particles,
                    const std::function<std::string(std::size_t)>& describe) {
  if (particles.empty()) return;
  using Cell = std::array<long long, 3>;
  double maxRadius = 0.0;
  Vec3 lo = particles[0].position;
  for (const CsvParticle& p : particles) {
    maxRadius = std::max(maxRadius, p.radius);
    lo = lo.cwiseMin(p.position);
  }
  const double edge = 2.0 * maxRadius;
  auto cellOf = [&](const Vec3& x) {
    const Vec3 c = ((x - lo) / edge).array().floor();
    return Cell{(long long)c.x(), (long long)c.y(), (long long)c.z()};
  };
  std::vector<std::pair<Cell, std::size_t>> sorted;
  sorted.reserve(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i)
    sorted.emplace_back(cellOf(particles[i].position), i);
  std::sort(sorted.begin(), sorted.end());

  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Cell home = cellOf(particles[i].position);
    std::size_t partner = particles.size();  // smallest overlapping j > i: a stable report
    for (long long dx = -1; dx <= 1; ++dx) {
      for (long long dy = -1; dy <= 1; ++dy) {
        for (long long dz = -1; dz <= 1; ++dz) {
          const Cell c{home[0] + dx, home[1] + dy, home[2] + dz};
          auto first =
              std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(c, std::size_t(0)));
          for (auto it = first; it != sorted.end() && it->first == c; ++it) {
            const std::size_t j = it->second;
            if (j <= i || j >= partner) continue;
            // A saved state's own contacts are part of it.
            if (fromSavedState(particles[i]) && fromSavedState(particles[j])) continue;
            const double gap = (particles[j].position - particles[i].position).norm();
            if (gap < particles[i].radius + particles[j].radius) partner = j;
          }
        }
      }
    }
    if (partner < particles.size()) {
      const double gap = (particles[partner].position - particles[i].position).norm();
      throw ConfigError(describe(i) + " and " + describe(partner) + " overlap at start: centres " +
                        formatPoint(particles[i].position) + " and " +
                        formatPoint(particles[partner].position) + " are " + formatNumber(gap) +
                        " m apart, radii sum " +
                        formatNumber(particles[i].radius + particles[partner].radius) + " m");
    }
  }
}

// 3. Building -------------------------------------------------------------------------------------

struct BuiltParticles {
  Particles particles;
  double density = 0.0;  ///< the density used: the material's, or scaled to the total mass [kg/m³]
};

BuiltParticles build(const Scene& scene) {
  std::vector<CsvParticle> all;
  std::vector<std::size_t> firstOf;  // index in `all` of each generator's first particle
  for (std::size_t index = 0; index < scene.generators.size(); ++index) {
    firstOf.push_back(all.size());
    if (const auto* grid = std::get_if<GridGenerator>(&scene.generators[index])) {
      checkGrid(*grid, index);
      forEachGridParticle(*grid, [&all](std::size_t, const CsvParticle& p) { all.push_back(p); });
    } else {
      const CsvGenerator& csv = std::get<CsvGenerator>(scene.generators[index]);
      const ParticleCsv file =
          readParticleCsv(csv.path, csv.savedState ? CsvKind::SavedState : CsvKind::Particles);
      if (csv.contentHash && file.contentHash != *csv.contentHash) {
        // The run's fingerprint names what loadScene read; building from other bytes would
        // run particles the checkpoints do not describe.
        throw ConfigError(csv.path.string() + ": changed since the scene was loaded");
      }
      all.insert(all.end(), file.rows.begin(), file.rows.end());
    }
  }
  if (all.empty() && !(scene.simulation.smallestRadius > 0)) {
    throw ConfigError("the scene has no particles");  // and no stage inserts any
  }
  // Two generators may overlap each other: name the scene, its entry and the CSV line.
  const std::string prefix = scene.sourceFile.empty() ? "" : scene.sourceFile.string() + ": ";
  try {
    checkInsideBox(all, scene.box);
    if (!scene.simulation.material.hasFriction()) checkNoSpin(all);
  } catch (const ConfigError& e) {
    throw ConfigError(prefix + e.what());
  }
  auto describe = [&](std::size_t i) {
    const std::size_t entry =
        std::size_t(std::upper_bound(firstOf.begin(), firstOf.end(), i) - firstOf.begin()) - 1;
    const std::string particle =
        "particle " + std::to_string(i) + " (particles[" + std::to_string(entry) + "], ";
    if (const auto* csv = std::get_if<CsvGenerator>(&scene.generators[entry])) {
      return particle + csv->path.string() + ":" + std::to_string(all[i].line) + ")";
    }
    return particle + "grid particle " + std::to_string(i - firstOf[entry]) + ")";
  };
  try {
    checkNoOverlap(all, describe);
  } catch (const ConfigError& e) {
    throw ConfigError(prefix + e.what());
  }

  BuiltParticles out;
  out.density = scene.simulation.material.density;
  if (scene.totalMass) {
    if (!(*scene.totalMass > 0.0) || !std::isfinite(*scene.totalMass)) {
      throw ConfigError("total mass must be > 0, got " + formatNumber(*scene.totalMass));
    }
    double volume = 0.0;  // Σ (4/3)π R³ [m³]
    for (const CsvParticle& p : all) volume += 4.0 / 3.0 * std::numbers::pi * std::pow(p.radius, 3);
    out.density = *scene.totalMass / volume;
  }
  try {
    checkSavedMasses(all, out.density, describe);
  } catch (const ConfigError& e) {
    throw ConfigError(prefix + e.what());
  }
  for (const CsvParticle& p : all) {
    out.particles.add(p.position, p.radius, out.density, p.velocity);
    out.particles.angularVelocity.back() = p.angularVelocity;
    if (fromSavedState(p)) out.particles.mass.back() = p.mass;  // as it was, to the bit
  }
  return out;
}

}  // namespace

Particles buildParticles(const Scene& scene) {
  return build(scene).particles;
}

std::vector<Wall> buildWalls(const BoxSpec& box) {
  if ((box.max.array() <= box.min.array()).any()) {
    throw ConfigError("box max " + formatPoint(box.max) + " must exceed box min " +
                      formatPoint(box.min) + " in every component");
  }
  std::vector<Wall> walls;
  const Vec3 centre = 0.5 * (box.min + box.max);
  for (std::size_t face = 0; face < kBoxWallNames.size(); ++face) {
    if (!box.walls[face]) continue;
    const int axis = int(face / 2);
    const bool lower = face % 2 == 0;
    Wall wall;
    wall.name = kBoxWallNames[face];
    wall.point = centre;  // the face's centre: a point of the plane near the particles
    wall.point[axis] = lower ? box.min[axis] : box.max[axis];
    wall.normal = Vec3::Zero();
    wall.normal[axis] = lower ? 1.0 : -1.0;  // into the box
    walls.push_back(wall);
  }
  return walls;
}

Simulation buildSimulation(const Scene& scene) {
  requireMemoryFor(scene);  // before anything per particle is allocated
  BuiltParticles built = build(scene);
  // The scaled density goes into the configuration so that sim.config().material.density tells
  // the density the particles really have.
  SimulationConfig config = scene.simulation;
  config.material.density = built.density;
  try {
    std::vector<Wall> walls = buildWalls(scene.box);
    walls.insert(walls.end(), scene.walls.begin(), scene.walls.end());
    return Simulation(std::move(built.particles), std::move(walls), config);
  } catch (const TimeStepError& e) {
    // A packed start's step, refused against its contact network: name the file, line and key.
    const auto at = scene.keyLocations.find("simulation.time_step");
    if (at != scene.keyLocations.end()) throw TimeStepError(at->second + e.what());
    const std::string file = scene.sourceFile.empty() ? "the scene" : scene.sourceFile.string();
    throw TimeStepError(file + ": simulation.time_step: " + e.what());
  }
}

void forEachGridParticle(const GridGenerator& grid,
                         const std::function<void(std::size_t, const CsvParticle&)>& visit) {
  sampleGrid(grid, visit);
}

}  // namespace granular
