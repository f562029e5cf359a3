#pragma once
/// ParaView files through VTK's own XML writers (Debian's libvtk9: data and I/O modules only,
/// nothing that draws): grids as image data (.vti), lines as poly data (.vtp).
#include <array>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "granular/vec3.hpp"

namespace granular::app {

/// A named field on a regular grid, x fastest: `components` values per node.
struct GridArray {
  std::string name;            ///< with units, e.g. "sigma33_Pa"
  int components = 1;          ///< 1 scalar, 3 vector, 9 tensor (row-major)
  std::vector<double> values;  ///< nodes × components
};

/// Writes image data: nodes at origin + (i, j, k)·spacing [m].
void writeVti(const std::filesystem::path& file, const Vec3& origin, const Vec3& spacing,
              std::array<int, 3> counts, const std::vector<GridArray>& arrays);

/// Writes polylines [m], each with an integer "line" id.
void writeVtpLines(const std::filesystem::path& file, const std::vector<std::vector<Vec3>>& lines);

}  // namespace granular::app
