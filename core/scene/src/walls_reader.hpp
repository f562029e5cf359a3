#pragma once
/// Reading the scene's [[walls]] array (private to the core): walls of any shape beside the
/// box's faces, each with its geometry and prescribed motion.
#include <string>
#include <vector>

#include "granular/scene.hpp"
#include "toml_table_reader.hpp"

namespace granular {

/// The walls in file order (none without the array). Names must be unique and differ from the
/// box's face names. A mesh whose size is out of all proportion to the box (its file in other
/// units than its `scale` says) is refused, as is a wall's friction > 0 with frictionless
/// particles (`material`).
std::vector<Wall> readWalls(const TomlTableReader& root, const std::string& file,
                            const BoxSpec& box, const Material& material);

}  // namespace granular
