/// Neighbour (Verlet) lists on a uniform cell grid, with the contact history carried across
/// rebuilds. Sections: cell grid, history merge, particle blocks, rebuild, staleness.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "granular/wall_mesh.hpp"
#include "pair_springs.hpp"
#include "simulation_state.hpp"
#include "wall_contact.hpp"

namespace granular {
namespace {

// ---- Cell grid ----------------------------------------------------------------------------

/// Particles binned into cubic cells at least as large as the reach of the largest pair, so
/// that every candidate of a particle lies in its own or the 26 adjacent cells.
struct CellGrid {
  Vec3 origin;
  double cellSize = 1.0;
  std::array<long, 3> dims = {1, 1, 1};
  std::vector<std::uint32_t> cellStart;  ///< prefix sums, size cells + 1
  std::vector<std::uint32_t> items;      ///< particle indices ordered by cell

  double inverseCellSize = 1.0;

  /// Clamped before the cast, so that no position, however far out, overflows a long. A
  /// product and a truncation, not a division and a floor: both ran for every particle twice
  /// a rebuild. (Truncation is the floor here, as the clamp leaves only c ≥ 1.)
  long cellCoord(double x, int axis) const {
    const double c = (x - origin[axis]) * inverseCellSize;
    if (!(c >= 1.0)) return 0;  // also NaN
    return c < double(dims[axis] - 1) ? static_cast<long>(c) : dims[axis] - 1;
  }
  long cellIndex(long cx, long cy, long cz) const { return (cz * dims[1] + cy) * dims[0] + cx; }
};

CellGrid binParticles(const Particles& p, double reach) {
  CellGrid grid;
  const std::size_t n = p.size();
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max());
  Vec3 hi = -lo;
  for (std::size_t i = 0; i < n; ++i) {
    lo = lo.cwiseMin(p.position[i]);
    hi = hi.cwiseMax(p.position[i]);
  }
  grid.origin = lo;
  // A hair larger than the reach: two particles within it then never lie two cells apart, the
  // rounding of cellCoord's product included (the list does not depend on the grid otherwise).
  grid.cellSize = reach * (1.0 + 1e-9);
  // A particle far from the others must not blow up the cell count: cap it at ~2 cells/particle.
  const double maxCells = 2.0 * static_cast<double>(n) + 64.0;
  // The count is formed in floating point and cast only once it is small: a particle thrown
  // 1e300 m away must cost a larger cell, not an integer overflow.
  // Half extents, which cannot overflow for finite positions.
  const Vec3 half = hi * 0.5 - lo * 0.5;
  // A NaN coordinate (a broken state on its way to being reported) counts as one cell.
  auto cellsAlong = [&](int a) {
    const double c = std::floor(half[a] / (0.5 * grid.cellSize)) + 1.0;
    return c >= 1.0 ? c : 1.0;
  };
  for (;;) {
    const double cells = cellsAlong(0) * cellsAlong(1) * cellsAlong(2);
    if (cells <= maxCells) break;
    grid.cellSize *= cells < 1e6 * maxCells ? 1.5 : 1e3;  // big leaps for absurd extents
  }
  for (int a = 0; a < 3; ++a) grid.dims[a] = static_cast<long>(cellsAlong(a));
  grid.inverseCellSize = 1.0 / grid.cellSize;
  const std::size_t cellCount =
      static_cast<std::size_t>(grid.dims[0] * grid.dims[1] * grid.dims[2]);
  // A counting sort with no array beside the grid's own (a rebuild's transient memory): each
  // cell's count, their running sums (cellStart[c] = the end of cell c), then the particles
  // placed from the end of their cell backwards, which leaves cellStart[c] at its start and
  // each cell in ascending index. The cell of a particle is computed twice rather than kept.
  auto cellOf = [&](std::size_t i) {
    const Vec3& x = p.position[i];
    return static_cast<std::size_t>(
        grid.cellIndex(grid.cellCoord(x[0], 0), grid.cellCoord(x[1], 1), grid.cellCoord(x[2], 2)));
  };
  grid.cellStart.assign(cellCount + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++grid.cellStart[cellOf(i)];
  for (std::size_t c = 1; c <= cellCount; ++c) grid.cellStart[c] += grid.cellStart[c - 1];
  grid.items.resize(n);
  for (std::size_t i = n; i-- > 0;) {
    grid.items[--grid.cellStart[cellOf(i)]] = static_cast<std::uint32_t>(i);
  }
  return grid;
}

/// Writes the partners j > i of particle i, those within R_i + R_j + margin (the skin and any reach
/// beyond touch), to found[0, count) in ascending order (growing `found` as needed) and returns
/// their count. The 3 × 3 × 3 cells around i are read as nine rows of three cells, each a
/// contiguous range of the grid's items; the test appends every particle and keeps it by advancing
/// the count, so that the loop does not branch on the ≈ 1 in 14 that are kept.
std::size_t partnersOf(const CellGrid& grid, const Particles& p, double margin, std::size_t i,
                       std::vector<std::uint32_t>& found) {
  const Vec3& xi = p.position[i];
  const double ri = p.radius[i];
  const long cx = grid.cellCoord(xi[0], 0), cy = grid.cellCoord(xi[1], 1),
             cz = grid.cellCoord(xi[2], 2);
  const long x0 = std::max(cx - 1, 0L), x1 = std::min(cx + 1, grid.dims[0] - 1);
  std::size_t count = 0;
  for (long z = std::max(cz - 1, 0L); z <= std::min(cz + 1, grid.dims[2] - 1); ++z) {
    for (long y = std::max(cy - 1, 0L); y <= std::min(cy + 1, grid.dims[1] - 1); ++y) {
      const std::uint32_t begin = grid.cellStart[grid.cellIndex(x0, y, z)];
      const std::uint32_t end = grid.cellStart[grid.cellIndex(x1, y, z) + 1];
      if (found.size() < count + (end - begin)) found.resize(2 * (count + end - begin));
      std::uint32_t* out = found.data();
      for (std::uint32_t k = begin; k < end; ++k) {
        const std::uint32_t j = grid.items[k];
        const double reach = ri + p.radius[j] + margin;
        const bool near = (p.position[j] - xi).squaredNorm() < reach * reach;
        out[count] = j;
        count += static_cast<std::size_t>(near & (j > i));
      }
    }
  }
  // Rows come in cell order, not index order: an insertion sort, as the partners are few.
  std::uint32_t* out = found.data();
  for (std::size_t a = 1; a < count; ++a) {
    const std::uint32_t j = out[a];
    std::size_t b = a;
    for (; b > 0 && out[b - 1] > j; --b) out[b] = out[b - 1];
    out[b] = j;
  }
  return count;
}

// ---- History merge ------------------------------------------------------------------------

/// Each entry of the new candidate list takes the old list's entry of the same particle (the
/// k-th of a particle's entries the old k-th: a mesh lists a particle several times).
template <class T>
void carryWallHistory(const std::vector<std::uint32_t>& oldList, const std::vector<T>& oldHistory,
                      const std::vector<std::uint32_t>& newList, std::vector<T>& newHistory) {
  if constexpr (std::is_same_v<T, Vec3>) {
    newHistory.assign(newList.size(), Vec3::Zero());
  } else {
    newHistory.assign(newList.size(), T{});
  }
  std::size_t a = 0;
  for (std::size_t b = 0; b < newList.size() && a < oldList.size(); ++b) {
    while (a < oldList.size() && oldList[a] < newList[b]) ++a;
    if (a < oldList.size() && oldList[a] == newList[b]) newHistory[b] = oldHistory[a++];
  }
}

// ---- Particle blocks ----------------------------------------------------------------------

/// A particle block closes at this many pairs or particles: the unit of the force pass's
/// ordered power sums (fixed, so the sums do not depend on the thread count), of its split among
/// threads and of the springs' storage.
constexpr std::size_t kBlockPairs = 512, kBlockParticles = 512;

/// Particle blocks for n particles and the list's rows (n + 1 entries).
void pairBlocks(const std::vector<std::uint32_t>& rowStart, std::size_t n,
                std::vector<std::uint32_t>& blockParticle, std::vector<std::uint32_t>& blockPair,
                std::vector<std::uint32_t>& blockWord) {
  blockParticle.assign(1, 0);
  blockPair.assign(1, 0);
  blockWord.assign(1, 0);
  for (std::size_t i = 0, k = 0; i < n;) {
    const std::size_t particleBegin = i, pairBegin = k;
    while (i < n && i - particleBegin < kBlockParticles && k - pairBegin < kBlockPairs) {
      ++i;
      k = rowStart[i];
    }
    blockParticle.push_back(static_cast<std::uint32_t>(i));
    blockPair.push_back(static_cast<std::uint32_t>(k));
    blockWord.push_back(static_cast<std::uint32_t>(blockWord.back() + (k - pairBegin + 63) / 64));
  }
}

}  // namespace

void buildPairBlocks(NeighbourList& list, std::size_t n) {
  pairBlocks(list.rowStart, n, list.blockParticle, list.blockPair, list.blockWord);
}

bool rowsFromFirst(NeighbourList& list, const std::vector<std::uint32_t>& first, std::size_t n) {
  list.rowStart.clear();
  std::vector<std::uint32_t> rows(n + 1, 0);
  for (std::size_t k = 0; k < first.size(); ++k) {
    if (first[k] >= n || (k > 0 && first[k] < first[k - 1])) return false;
    ++rows[first[k] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) rows[i + 1] += rows[i];
  list.rowStart = std::move(rows);
  return true;
}

std::vector<std::uint32_t> firstOfPairs(const NeighbourList& list) {
  std::vector<std::uint32_t> first(list.second.size());
  for (std::size_t i = 0; i + 1 < list.rowStart.size(); ++i) {
    std::fill(first.begin() + list.rowStart[i], first.begin() + list.rowStart[i + 1],
              static_cast<std::uint32_t>(i));
  }
  return first;
}

// ---- Rebuild ------------------------------------------------------------------------------

namespace {

/// Below this many particles several threads search the pairs once (searchOnce), at and above
/// it count first (searchCountingFirst): the threads' buffers of a search made once add about
/// 11 B a particle to a rebuild's peak at 2 threads (more at more), which a 10⁶-particle bed
/// cannot spare within its 400 B (bench/RESULTS.md, "Issue 6 targets"); below it the bed's memory
/// is small whatever the list's.
constexpr std::size_t kSearchOnceBelow = std::size_t{1} << 17;

/// The pair search of a first build, twice over the same search, count then fill, so that the
/// list is allocated once at its exact size: with no list before it, buffers growing by
/// doubling would be the transient peak of the run's memory (at 10⁶ particles they were).
void searchCountingFirst(const CellGrid& grid, const Particles& p, double margin, int teams,
                         std::vector<std::uint32_t>& rowStart, std::vector<std::uint32_t>& second) {
  const std::size_t n = p.size();
#pragma omp parallel num_threads(teams)
  {
    std::vector<std::uint32_t> found;
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      rowStart[i + 1] = static_cast<std::uint32_t>(partnersOf(grid, p, margin, i, found));
    }
#pragma omp single
    {
      for (std::size_t i = 0; i < n; ++i) rowStart[i + 1] += rowStart[i];
      second.resize(rowStart[n]);
    }
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t count = partnersOf(grid, p, margin, i, found);
      std::copy_n(found.begin(), count, second.begin() + rowStart[i]);
    }
  }
}

/// The pair search of a later build, once: each thread searches a run of consecutive particles
/// into its part of the list, the first thread's straight into `second`, reserved at the last
/// list's size (`lastPairs`) + 1/8, the others' into buffers reserved at their share of that and
/// copied behind it. A list changes little between two builds: an array grows by doubling (a
/// transient the peak memory would show) only if it outgrows that. A search counted first would
/// search twice, which two threads do in the time one takes once.
void searchOnce(const CellGrid& grid, const Particles& p, double margin, std::size_t lastPairs,
                int teams, std::vector<std::uint32_t>& rowStart,
                std::vector<std::uint32_t>& second) {
  const std::size_t n = p.size();
  std::vector<std::vector<std::uint32_t>> parts(std::size_t(std::max(teams, 1)));
  std::vector<std::size_t> partBegin(parts.size() + 1, n);
#pragma omp parallel num_threads(teams)
  {
    const std::size_t t = std::size_t(omp_get_thread_num());
    const std::size_t used = std::size_t(omp_get_num_threads());
    const std::size_t begin = n * t / used, end = n * (t + 1) / used;
    partBegin[t] = begin;
    std::vector<std::uint32_t>& out = t == 0 ? second : parts[t];
    const std::size_t share =
        t == 0 ? lastPairs : lastPairs * (end - begin) / std::max<std::size_t>(n, 1);
    out.reserve(share + share / 8 + 16);
    std::vector<std::uint32_t> found;
    for (std::size_t i = begin; i < end; ++i) {
      const std::size_t count = partnersOf(grid, p, margin, i, found);
      out.insert(out.end(), found.begin(), found.begin() + std::ptrdiff_t(count));
      rowStart[i + 1] = static_cast<std::uint32_t>(count);
    }
  }
  for (std::size_t i = 0; i < n; ++i) rowStart[i + 1] += rowStart[i];
  second.resize(rowStart[n]);
  for (std::size_t t = 1; t < parts.size(); ++t) {
    if (partBegin[t] >= n) continue;
    std::copy(parts[t].begin(), parts[t].end(), second.begin() + rowStart[partBegin[t]]);
  }
}

/// Mesh wall w's grid for a build of reach rMax + margin: the last build's where the mesh has
/// kept its pose and the reach is the same, else binned anew (a silo's fixed walls binned at
/// every build took 8 % of its run).
void keepOrBinMeshGrid(NeighbourList& list, const Wall& wall, std::size_t w, double rMax,
                       double margin) {
  const TriangleGrid& kept = list.meshGrid[w];
  if (list.meshGridPose[w] == wall.mesh && !kept.empty() && kept.reach == rMax + margin &&
      kept.cellAsked == 2.0 * rMax + margin) {
    return;
  }
  list.meshGrid[w] = listGrid(wall.mesh->world, rMax, margin);
  list.meshGridPose[w] = wall.mesh;
}

/// Mesh wall w's candidates: the particles within their radius plus `margin` of a triangle,
/// each listed kMeshContacts times, with those triangles (NeighbourList::meshTriangles). Runs
/// of consecutive particles are searched by whichever thread is free (the particles near a wall
/// are not spread evenly over the indices) and joined in order.
void listMeshCandidates(const WallMesh& mesh, const TriangleGrid& grid, const Particles& p,
                        double margin, int teams, std::vector<std::uint32_t>& candidates,
                        std::vector<std::uint32_t>& triangleStart,
                        std::vector<std::uint32_t>& triangles) {
  struct Part {
    std::vector<std::uint32_t> particle, count, triangle;
  };
  constexpr std::size_t kRun = 256;
  const std::size_t n = p.size();
  std::vector<Part> parts((n + kRun - 1) / kRun);
#pragma omp parallel for schedule(dynamic) num_threads(teams)
  for (std::size_t r = 0; r < parts.size(); ++r) {
    Part& part = parts[r];
    for (std::size_t i = r * kRun; i < std::min(n, (r + 1) * kRun); ++i) {
      const std::size_t before = part.triangle.size();
      trianglesWithin(mesh.world, mesh.topology, grid, p.position[i], p.radius[i] + margin,
                      part.triangle);
      if (part.triangle.size() == before) continue;
      part.particle.push_back(static_cast<std::uint32_t>(i));
      part.count.push_back(static_cast<std::uint32_t>(part.triangle.size() - before));
    }
  }
  triangleStart.assign(1, 0);
  for (const Part& part : parts) {
    for (std::size_t c = 0; c < part.particle.size(); ++c) {
      candidates.insert(candidates.end(), kMeshContacts, part.particle[c]);
      triangleStart.push_back(triangleStart.back() + part.count[c]);
    }
    triangles.insert(triangles.end(), part.triangle.begin(), part.triangle.end());
  }
}

/// The analytic walls' candidates (those not removed): the particles whose surface is within
/// `margin` of the wall's surface (or beyond a plane), ascending. Each thread searches a run of
/// consecutive particles for every wall, and the runs are joined in order.
void listAnalyticCandidates(const std::vector<Wall>& walls, const Particles& p, double margin,
                            int teams, std::vector<std::vector<std::uint32_t>>& wallParticles) {
  const std::size_t n = p.size();
  std::vector<std::vector<std::vector<std::uint32_t>>> parts(std::size_t(std::max(teams, 1)));
#pragma omp parallel num_threads(teams)
  {
    const std::size_t t = std::size_t(omp_get_thread_num());
    const std::size_t used = std::size_t(omp_get_num_threads());
    std::vector<std::vector<std::uint32_t>>& part = parts[t];
    part.resize(walls.size());
    for (std::size_t w = 0; w < walls.size(); ++w) {
      const Wall& wall = walls[w];
      if (wall.removed || wall.shape == WallShape::Mesh) continue;
      for (std::size_t i = n * t / used; i < n * (t + 1) / used; ++i) {
        const double distance = wall.shell() ? touchOf(wall, p.position[i]).distance
                                             : (p.position[i] - wall.point).dot(wall.normal);
        if (distance < p.radius[i] + margin) part[w].push_back(static_cast<std::uint32_t>(i));
      }
    }
  }
  for (std::size_t w = 0; w < walls.size(); ++w) {
    for (const std::vector<std::vector<std::uint32_t>>& part : parts) {
      if (w < part.size()) {
        wallParticles[w].insert(wallParticles[w].end(), part[w].begin(), part[w].end());
      }
    }
  }
}

}  // namespace

void rebuildNeighbourList(NeighbourList& list, const Particles& p, const std::vector<Wall>& walls,
                          bool keepHistory, double beyond, int threads) {
  const std::size_t n = p.size();
  const double rMax = n ? *std::max_element(p.radius.begin(), p.radius.end()) : 0.0;
  // The margin over touch: the skin, and the contact model's reach beyond touch.
  const double margin = list.skin + beyond;

  // Each particle's partners land in its row, sorted by j: the list is the same for any thread
  // count.
  std::vector<std::uint32_t> rowStart(n + 1, 0), second;
  const int teams = threads > 0 ? threads : omp_get_max_threads();
  if (n > 1) {
    const CellGrid grid = binParticles(p, 2.0 * rMax + margin);
    // Once where that holds no more memory than counting first (one thread), or where the
    // threads' buffers are small beside the bed's arrays; a large bed counts first.
    if (!list.second.empty() && (teams == 1 || n < kSearchOnceBelow)) {
      searchOnce(grid, p, margin, list.second.size(), teams, rowStart, second);
    } else {
      searchCountingFirst(grid, p, margin, teams, rowStart, second);
    }
  }

  // Wall candidates: particles whose surface is within the margin of the wall's surface (or
  // beyond a plane); a mesh's through its binned triangles, each listed kMeshContacts times.
  std::vector<std::vector<std::uint32_t>> wallParticles(walls.size());
  list.meshGrid.resize(walls.size());
  list.meshGridPose.resize(walls.size());
  list.meshTriangleStart.assign(walls.size(), {});
  list.meshTriangles.assign(walls.size(), {});
  for (std::size_t w = 0; w < walls.size(); ++w) {
    if (walls[w].removed) {  // a gate opened touches nothing
      list.meshGrid[w] = TriangleGrid{};
      list.meshGridPose[w] = nullptr;
      continue;
    }
    if (walls[w].shape == WallShape::Mesh) {
      keepOrBinMeshGrid(list, walls[w], w, rMax, margin);
      listMeshCandidates(*walls[w].mesh, list.meshGrid[w], p, margin, teams, wallParticles[w],
                         list.meshTriangleStart[w], list.meshTriangles[w]);
      continue;
    }
    list.meshGrid[w] = TriangleGrid{};
    list.meshGridPose[w] = nullptr;
  }
  listAnalyticCandidates(walls, p, margin, teams, wallParticles);

  std::vector<std::uint32_t> blockParticle, blockPair, blockWord;
  pairBlocks(rowStart, n, blockParticle, blockPair, blockWord);
  if (keepHistory) {
    list.springs = carryPairSprings(list, rowStart, second, blockPair, blockWord, teams);
    list.wallHistory.resize(walls.size());
    std::vector<std::vector<ContactHistory>> wallHistory(walls.size());
    for (std::size_t w = 0; w < walls.size(); ++w) {
      if (w < list.wallParticles.size()) {
        carryWallHistory(list.wallParticles[w], list.wallHistory[w], wallParticles[w],
                         wallHistory[w]);
      } else {
        wallHistory[w].assign(wallParticles[w].size(), ContactHistory{});
      }
    }
    list.wallHistory = std::move(wallHistory);
    // A mesh's entries keep their contacts' normals with their springs.
    std::vector<std::vector<Vec3>> wallNormal(walls.size());
    for (std::size_t w = 0; w < walls.size(); ++w) {
      if (walls[w].shape != WallShape::Mesh) continue;
      if (w < list.wallParticles.size() && w < list.wallNormal.size() &&
          list.wallNormal[w].size() == list.wallParticles[w].size()) {
        carryWallHistory(list.wallParticles[w], list.wallNormal[w], wallParticles[w],
                         wallNormal[w]);
      } else {
        wallNormal[w].assign(wallParticles[w].size(), Vec3::Zero());
      }
    }
    list.wallNormal = std::move(wallNormal);
  } else {
    list.springs = PairSprings{};
    list.wallNormal.clear();
  }
  list.rowStart = std::move(rowStart);
  list.second = std::move(second);
  list.blockParticle = std::move(blockParticle);
  list.blockPair = std::move(blockPair);
  list.blockWord = std::move(blockWord);
  list.wallParticles = std::move(wallParticles);
  setReferencePositions(list, p.position);
  list.referenceWallPoint.resize(walls.size());
  for (std::size_t w = 0; w < walls.size(); ++w) list.referenceWallPoint[w] = walls[w].point;
  list.referenceWallTravel.resize(walls.size());
  for (std::size_t w = 0; w < walls.size(); ++w) list.referenceWallTravel[w] = walls[w].travel;
  list.valid = true;
  list.plan.valid = false;  // the force pass rebuilds it
}

// ---- Staleness ----------------------------------------------------------------------------

void setReferencePositions(NeighbourList& list, const std::vector<Vec3>& position) {
  const std::size_t n = position.size();
  resizeExactly(list.referencePosition, n);
  float largest = 0.0f;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f x = position[i].cast<float>();
    list.referencePosition[i] = x;
    largest = std::max(largest, x.cwiseAbs().maxCoeff());  // NaN ignored: the step reports it
  }
  // Rounding to nearest moves a coordinate by at most 2⁻²⁴ of its magnitude (its rounded one,
  // slightly more for safety), or 2⁻¹⁵⁰ below the normal range; three coordinates √3 times
  // that. A position beyond the float range rounds to infinity: every later move measures
  // infinite and the list is rebuilt each step, which is slow but never wrong.
  const double perCoordinate =
      std::ldexp(static_cast<double>(largest), -24) * (1.0 + 1e-6) + std::ldexp(1.0, -149);
  list.referenceRounding = std::sqrt(3.0) * perCoordinate;
}

LargestMoves largestMoves(const NeighbourList& list, const Particles& p, std::size_t begin,
                          std::size_t end, const std::vector<std::uint8_t>* owned) {
  LargestMoves moves;
  if (list.referencePosition.size() != p.size()) return moves;  // the list is stale anyway
  for (std::size_t i = begin; i < end; ++i) {
    if (owned && !(*owned)[i]) continue;
    moves.add((p.position[i] - list.referencePosition[i].cast<double>()).squaredNorm());
  }
  return moves;
}

bool neighbourListStale(const NeighbourList& list, const Particles& p,
                        const std::vector<Wall>& walls, const LargestMoves& moves) {
  if (!list.valid || list.referencePosition.size() != p.size() ||
      list.referenceWallPoint.size() != walls.size() ||
      list.referenceWallTravel.size() != walls.size()) {
    return true;
  }
  // Two particles approach by at most the sum of their displacements, at most the two largest;
  // a particle and a wall by the particle's displacement plus the wall's. Displacements are
  // measured from the rounded reference positions, so each may be short by their rounding.
  const double maxMove = std::sqrt(moves.first) + list.referenceRounding;
  const double nextMove = std::sqrt(moves.second) + list.referenceRounding;
  if (maxMove + nextMove >= list.skin) return true;
  for (std::size_t w = 0; w < walls.size(); ++w) {
    // A plane's move across itself; a shell's surface travel since the rebuild (moveWall).
    const double wallMove =
        walls[w].shell()
            ? walls[w].travel - list.referenceWallTravel[w]
            : std::abs((walls[w].point - list.referenceWallPoint[w]).dot(walls[w].normal));
    if (maxMove + wallMove >= list.skin) return true;
  }
  return false;
}

}  // namespace granular
