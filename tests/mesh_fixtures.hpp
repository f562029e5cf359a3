#pragma once
/// Meshes the mesh tests share.
#include <cstdint>

#include "granular/triangle_mesh.hpp"

namespace granular::testing {

/// The square [0, side]² at z = 0 cut into n × n squares of two triangles each (2 n²),
/// counter-clockwise seen from +z.
inline TriangleMesh flatGrid(int n, double side = 1.0) {
  TriangleMesh m;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) m.vertex.push_back(Vec3(side * i / n, side * j / n, 0.0));
  }
  auto at = [n](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      m.triangle.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangle.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return m;
}

}  // namespace granular::testing
