#pragma once
/// Reading a stage's particle exchange (private to the core): its [[stages.inserts]] and
/// [[stages.outlets]], the walls it takes away and its exchange interval.
#include <cstddef>
#include <string>
#include <vector>

#include "granular/scene.hpp"
#include "toml_table_reader.hpp"

namespace granular {

/// Fills `stage`'s removeWalls, inserts, outlets and exchangeInterval from its table `r`.
/// `sources` counts the inserts of the stages before (InsertSpec::source) and is advanced;
/// regions must lie in the box, walls named must exist (`walls`) and be removed only once
/// (`removed`, the walls earlier stages took away, is advanced).
void readStageExchange(const TomlTableReader& r, const std::string& file, const BoxSpec& box,
                       const std::vector<Wall>& walls, std::size_t& sources,
                       std::vector<std::string>& removed, StageSpec& stage);

}  // namespace granular
