/// Binning a mesh's triangles into cells (triangle_grid.hpp).
#include "triangle_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh_contact.hpp"

namespace granular {

std::span<const std::uint32_t> TriangleGrid::near(const Vec3& x) const {
  if (cellStart.empty()) return {};
  int at[3];
  for (int k = 0; k < 3; ++k) {
    const double u = std::floor((x[k] - origin[k]) / cell);
    if (!(u >= 0.0 && u < dims[k])) return {};
    at[k] = int(u);
  }
  const std::size_t c = (std::size_t(at[2]) * dims[1] + at[1]) * dims[0] + at[0];
  return {triangles.data() + cellStart[c], cellStart[c + 1] - cellStart[c]};
}

TriangleGrid binTriangles(const TriangleMesh& mesh, double reach, double cell) {
  TriangleGrid grid;
  grid.reach = reach;
  grid.cellAsked = cell;
  if (mesh.triangle.empty()) return grid;
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (const Vec3& v : mesh.vertex) {
    low = low.cwiseMin(v);
    high = high.cwiseMax(v);
  }
  low.array() -= reach;
  high.array() += reach;
  // Cells of at least `cell`, and not more than 2²¹ of them in all (a huge mesh with small
  // particles gets larger cells, each listing more triangles).
  const Vec3 size = high - low;
  grid.cell = std::max(cell, std::cbrt(size.prod() / double(1 << 21)));
  for (int k = 0; k < 3; ++k) grid.dims[k] = std::max(1, int(std::ceil(size[k] / grid.cell)));
  grid.origin = low;
  const std::size_t cells = std::size_t(grid.dims[0]) * grid.dims[1] * grid.dims[2];
  // Two passes, count then fill, in triangle order within each cell.
  auto cellRange = [&](std::size_t t, int lo[3], int hi[3]) {
    Vec3 a = mesh.vertex[mesh.triangle[t][0]], b = a;
    for (int k = 1; k < 3; ++k) {
      a = a.cwiseMin(mesh.vertex[mesh.triangle[t][k]]);
      b = b.cwiseMax(mesh.vertex[mesh.triangle[t][k]]);
    }
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::clamp(int(std::floor((a[k] - reach - low[k]) / grid.cell)), 0, grid.dims[k] - 1);
      hi[k] = std::clamp(int(std::floor((b[k] + reach - low[k]) / grid.cell)), 0, grid.dims[k] - 1);
    }
  };
  grid.cellStart.assign(cells + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::uint32_t> fill;
    if (pass == 1) {
      for (std::size_t c = 0; c < cells; ++c) grid.cellStart[c + 1] += grid.cellStart[c];
      grid.triangles.resize(grid.cellStart[cells]);
      fill.assign(grid.cellStart.begin(), grid.cellStart.end() - 1);
    }
    for (std::size_t t = 0; t < mesh.triangle.size(); ++t) {
      int lo[3], hi[3];
      cellRange(t, lo, hi);
      for (int z = lo[2]; z <= hi[2]; ++z) {
        for (int y = lo[1]; y <= hi[1]; ++y) {
          for (int x = lo[0]; x <= hi[0]; ++x) {
            const std::size_t c = (std::size_t(z) * grid.dims[1] + y) * grid.dims[0] + x;
            if (pass == 0) {
              ++grid.cellStart[c + 1];
            } else {
              grid.triangles[fill[c]++] = std::uint32_t(t);
            }
          }
        }
      }
    }
  }
  return grid;
}

MeshNearest nearestOnMesh(const TriangleMesh& mesh, const MeshTopology& topology,
                          const TriangleGrid& grid, const Vec3& x) {
  return nearestAmong(mesh, topology, grid.near(x), x);
}

void trianglesWithin(const TriangleMesh& mesh, const MeshTopology& topology,
                     const TriangleGrid& grid, const Vec3& x, double limit,
                     std::vector<std::uint32_t>& out) {
  for (const std::uint32_t t : grid.near(x)) {
    if (triangleWithin(mesh, topology, t, x, limit)) out.push_back(t);
  }
}

}  // namespace granular
