#pragma once
/// Triangle meshes from STL files (ASCII or binary), read with VTK's vtkSTLReader.
#include <filesystem>

#include "granular/triangle_mesh.hpp"

namespace granular {

/// The file's triangles, in its order (triangle k is the file's k-th, counted from 0), their
/// corners welded where they coincide exactly, in the file's units. Refused (SceneError
/// "file: what", "file: triangle k: what") when the file is missing, empty, truncated or padded
/// against its binary header's triangle count, unreadable to VTK, or holds no triangle, and for
/// the defects meshTopology finds (an open edge only where `closed` is asked), the first few
/// named with their count.
TriangleMesh readStlMesh(const std::filesystem::path& file, bool closed);

}  // namespace granular
