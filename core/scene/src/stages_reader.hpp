#pragma once
/// Reading the scene's [[stages]] array (private to the core): each stage's end, its top wall
/// and its walls' velocities, checked against the box and against the other stages.
#include <string>
#include <vector>

#include "granular/scene.hpp"
#include "toml_table_reader.hpp"

namespace granular {

/// The stages in file order; their wall velocities may name the box's walls and `walls`. `timeStep`
/// bounds max_time (infinity for an automatic step, whose smallest value is not known at load).
std::vector<StageSpec> readStages(const TomlTableReader& root, const std::string& file,
                                  const BoxSpec& box, const std::vector<Wall>& walls,
                                  double timeStep);

}  // namespace granular
