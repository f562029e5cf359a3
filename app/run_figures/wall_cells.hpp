#pragma once
/// The walls of a snapshot as its ParaView file paraview/<stage>_<step>_walls.vtp holds them
/// (vtk_snapshot.hpp): each wall's name, shape and cells, and the scene's box.
///
/// The run figures take the walls from this file rather than from the scene or the checkpoint:
/// it holds each wall where it was at that snapshot (a turning drum, a gate that moved), it is
/// written by the same run as the particles beside it, and it needs neither the scene file (which
/// may have been edited or moved since, and is named relative to where the run started) nor a
/// checkpoint (which holds the last state only, and none with --checkpoint-every 0).
#include <filesystem>
#include <string>
#include <vector>

#include "granular/vec3.hpp"

namespace granular::app {

/// One wall of the file: its cells are polygons (a mesh's triangles, a frustum's facets, the one
/// quad of a rectangle or of an infinite plane spanning the box) [m].
struct WallCells {
  std::string name;
  int shape = 0;  ///< granular::WallShape as vtk_snapshot.hpp numbers it; 0 an infinite plane
  std::vector<std::vector<Vec3>> cells;
  bool plane() const { return shape == 0; }
};

struct SnapshotWalls {
  Vec3 boxMin = Vec3::Zero(), boxMax = Vec3::Ones();  ///< the scene's box [m]
  std::vector<WallCells> walls;                       ///< in the run's wall order
};

/// Reads a walls.vtp. IoError naming the file when it cannot be read or lacks the arrays the
/// figures need (wall, shape, box_min_m, box_max_m, wall_name).
SnapshotWalls readSnapshotWalls(const std::filesystem::path& file);

}  // namespace granular::app
