/// readParticles: the [[particles]] sections, grids and CSV files, each checked particle by
/// particle against the box (and a CSV file's rows against each other) before the run.
#include "particles_reader.hpp"

#include <array>
#include <cstdint>
#include <map>

#include "granular/error.hpp"
#include "grid_sampling.hpp"
#include "particle_csv.hpp"
#include "scene_schema.hpp"

namespace granular {

namespace {

constexpr std::int64_t kMaxCellsPerAxis = 100000;
constexpr std::int64_t kMaxParticles = 100000000;
constexpr std::int64_t kMaxInt = std::numeric_limits<std::int64_t>::max();

std::string formatPoint(const Vec3& x) {
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "(" + std::string + ...
  std::string out = "(";
  out += formatNumber(x.x());
  out += ", ";
  out += formatNumber(x.y());
  out += ", ";
  out += formatNumber(x.z());
  out += ')';
  return out;
}

/// "" if a sphere at `centre` lies inside the box, else which face it crosses. The x and y faces
/// and the floor always bound it; the top only when it is a wall (particles may start above an
/// open box). The same rule as the builder's.
std::string boxCrossing(const Vec3& centre, double radius, const BoxSpec& box,
                        bool savedState = false) {
  // A saved state's particle may press into a wall, as in the settled bed it was saved from.
  const double reach = savedState ? 0.0 : radius;
  for (std::size_t face = 0; face < kBoxWallNames.size(); ++face) {
    if (face == 5 && !box.walls[5]) continue;
    const int axis = int(face / 2);
    const bool lower = face % 2 == 0;
    const double x = centre[axis];
    if (lower ? x - reach < box.min[axis] : x + reach > box.max[axis]) {
      return std::string("is outside the box: ") +
             (savedState ? "its centre is beyond" : "crosses") + " the box face " +
             kBoxWallNames[face] + " at " + "xyz"[axis] + " = " +
             formatNumber(lower ? box.min[axis] : box.max[axis]) + " m";
    }
  }
  return {};
}

/// Samples the grid as the builder will (grid_sampling.hpp), to find each particle's radius and
/// centre: the smallest radius and total volume set the time-step limit,
/// and a particle outside the box is reported here, against the scene file. Cheap next to the
/// run: a few nanoseconds a particle.
void checkGridParticles(const TomlTableReader& r, const GridGenerator& g, const BoxSpec& box,
                        MotionBound& bound) {
  forEachGridParticle(g, [&](std::size_t k, const CsvParticle& p) {
    const std::string crossing = boxCrossing(p.position, p.radius, box);
    if (!crossing.empty()) {
      r.fail("origin", "grid particle " + std::to_string(k) + " at " + formatPoint(p.position) +
                           " with radius " + formatNumber(p.radius) + " m " + crossing +
                           " (check origin, cell_size and cells against box.min and box.max)");
    }
    bound.add(p.radius);
  });
}

GridGenerator readGrid(const TomlTableReader& r, const BoxSpec& box, MotionBound& bound) {
  r.expectOnly(scene_schema::list(scene_schema::kGridParticles));
  GridGenerator g;
  g.origin = r.vec3("origin", Range::any());
  g.cellSize = r.number("cell_size", Range::above(0));
  const auto cells = r.integers3("cells", 1, kMaxCellsPerAxis);
  const std::int64_t capacity = cells[0] * cells[1] * cells[2];  // <= 1e15: no overflow
  const std::int64_t count = r.integer("count", capacity, 1, capacity);
  if (count > kMaxParticles) {
    r.fail(r.has("count") ? "count" : "cells", "more than 1e8 particles");
  }
  g.cells = {int(cells[0]), int(cells[1]), int(cells[2])};
  g.count = std::size_t(count);
  g.radiusMin = r.number("radius_min", Range::above(0));
  g.radiusMax = r.number("radius_max", Range::above(0));
  if (g.radiusMax < g.radiusMin) {
    r.fail("radius_max", "must be >= radius_min = " + formatNumber(g.radiusMin));
  }
  if (2.0 * g.radiusMax > g.cellSize) {
    r.fail("radius_max", "must be <= cell_size/2 = " + formatNumber(g.cellSize / 2) +
                             " so that neighbouring grid particles cannot overlap");
  }
  g.speedMax = r.number("speed_max", 0.0, Range::atLeast(0));
  g.seed = std::uint64_t(r.integer("seed", 1, 0, kMaxInt));
  checkGridParticles(r, g, box, bound);

  // Highest particle top: the last filled layer (z fastest-varying last) plus the largest radius.
  const std::int64_t layers = (count + cells[0] * cells[1] - 1) / (cells[0] * cells[1]);
  bound.highestTop =
      std::max(bound.highestTop, g.origin.z() + (double(layers) - 0.5) * g.cellSize + g.radiusMax);
  bound.fastest = std::max(bound.fastest, g.speedMax);
  return g;
}

/// The first row (in file order) that overlaps an earlier row, reported with both. Rows are
/// binned into cells of edge 2·R_max, so overlapping rows are in the same or adjacent cells.
void checkNoOverlap(const TomlTableReader& r, const std::filesystem::path& path,
                    const std::vector<CsvParticle>& rows) {
  double maxRadius = 0.0;
  for (const CsvParticle& p : rows) maxRadius = std::max(maxRadius, p.radius);
  using Cell = std::array<long long, 3>;
  // Clamped before the cast: a row 1e54 m away is legal above an open box and must not
  // overflow the integer; rows sharing a clamped cell are still compared by their distance.
  auto cellOf = [&](const Vec3& x) {
    const Vec3 c = (x / (2.0 * maxRadius)).array().floor().cwiseMax(-0x1p60).cwiseMin(0x1p60);
    return Cell{(long long)c.x(), (long long)c.y(), (long long)c.z()};
  };
  std::map<Cell, std::vector<std::size_t>> cells;
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const Cell home = cellOf(rows[j].position);
    for (long long dx = -1; dx <= 1; ++dx) {
      for (long long dy = -1; dy <= 1; ++dy) {
        for (long long dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find(Cell{home[0] + dx, home[1] + dy, home[2] + dz});
          if (it == cells.end()) continue;
          for (const std::size_t i : it->second) {
            const double gap = (rows[j].position - rows[i].position).norm();
            const double reach = rows[i].radius + rows[j].radius;
            if (gap >= reach) continue;
            r.fail("file", path.string() + ":" + std::to_string(rows[j].line) + ": row " +
                               std::to_string(j + 1) + " overlaps row " + std::to_string(i + 1) +
                               " (line " + std::to_string(rows[i].line) + "): centres " +
                               formatPoint(rows[i].position) + " and " +
                               formatPoint(rows[j].position) + " are " + formatNumber(gap) +
                               " m apart, radii sum " + formatNumber(reach) + " m");
          }
        }
      }
    }
    cells[home].push_back(j);
  }
}

CsvGenerator readCsv(const TomlTableReader& r, const std::filesystem::path& folder,
                     const BoxSpec& box, bool frictional, bool savedState, MotionBound& bound) {
  r.expectOnly(scene_schema::list(scene_schema::kCsvParticles));
  const std::string name = r.string("file");
  if (name.empty()) r.fail("file", "must name a CSV file");
  CsvGenerator g;
  g.path = std::filesystem::path(name).is_absolute() ? std::filesystem::path(name) : folder / name;
  g.savedState = savedState;
  // Read it now, so a bad row is reported against the scene key that names the file.
  ParticleCsv file;
  try {
    file = readParticleCsv(g.path, savedState ? CsvKind::SavedState : CsvKind::Particles);
  } catch (const ConfigError& e) {
    r.fail("file", e.what());
  }
  g.contentHash = file.contentHash;
  const std::vector<CsvParticle>& rows = file.rows;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CsvParticle& p = rows[i];
    const std::string row =
        g.path.string() + ":" + std::to_string(p.line) + ": row " + std::to_string(i + 1);
    const std::string crossing = boxCrossing(p.position, p.radius, box, savedState);
    if (!crossing.empty()) {
      r.fail("file", row + " at " + formatPoint(p.position) + " with radius " +
                         formatNumber(p.radius) + " m " + crossing);
    }
    if (!frictional && (p.angularVelocity.array() != 0.0).any()) {
      r.fail("file", row + " spins at (wx, wy, wz) = " + formatPoint(p.angularVelocity) +
                         " rad/s, but material.friction = 0: without friction nothing turns a "
                         "particle and the run ignores rotation; set material.friction > 0, or "
                         "zero the spin");
    }
    bound.highestTop = std::max(bound.highestTop, p.position.z() + p.radius);
    bound.fastest = std::max(bound.fastest, p.velocity.norm());
    bound.add(p.radius);
  }
  if (!savedState) checkNoOverlap(r, g.path, rows);  // a saved state's contacts are its own
  return g;
}

}  // namespace

std::vector<Generator> readParticles(const TomlTableReader& root, const std::string& file,
                                     const std::filesystem::path& folder, const BoxSpec& box,
                                     bool frictional, MotionBound& bound) {
  const toml::array* array = root.tableArray("particles");
  std::vector<Generator> generators;
  if (!array) return generators;  // loadScene requires them unless a stage inserts particles
  for (std::size_t i = 0; i < array->size(); ++i) {
    const TomlTableReader r(*array->get(i)->as_table(), "particles[" + std::to_string(i) + "]",
                            file);
    // Keys of either type first, so that a misspelt "type" gets a suggestion, not "missing".
    std::vector<std::string_view> either = scene_schema::list(scene_schema::kGridParticles);
    either.push_back("file");
    r.expectOnly(either);
    const std::string type = r.choice("type", "", {"grid", "csv", "state"});
    if (type == "grid") {
      generators.emplace_back(readGrid(r, box, bound));
    } else {
      generators.emplace_back(readCsv(r, folder, box, frictional, type == "state", bound));
    }
  }
  return generators;
}

}  // namespace granular
