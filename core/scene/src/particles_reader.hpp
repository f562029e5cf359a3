#pragma once
/// Reading the scene's [[particles]] sections (private to the core): each grid is sampled and
/// each CSV file read as the builder will place them, so that a particle outside the box, an
/// overlap of two CSV rows or a bad row is reported against the scene key. What the particles
/// tell about speeds and sizes comes back for the time-step checks (step_checks_at_load.hpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "granular/scene.hpp"
#include "toml_table_reader.hpp"

namespace granular {

/// What the particle sources tell about the expected impact speed and the time-step limit.
struct MotionBound {
  double highestTop = -std::numeric_limits<double>::infinity();     ///< max z + r [m]
  double fastest = 0.0;                                             ///< max initial speed [m/s]
  double smallestRadius = std::numeric_limits<double>::infinity();  ///< [m]
  double largestRadius = 0.0;                                       ///< [m]
  double volume = 0.0;  ///< Σ (4/3)π R³ in particle order, as the builder sums it [m³]
  void add(double radius) {
    smallestRadius = std::min(smallestRadius, radius);
    largestRadius = std::max(largestRadius, radius);
    volume += 4.0 / 3.0 * std::numbers::pi * std::pow(radius, 3);
  }
};

/// The generators of the [[particles]] array, in file order (none if it is absent); `bound`
/// takes in every particle.
std::vector<Generator> readParticles(const TomlTableReader& root, const std::string& file,
                                     const std::filesystem::path& folder, const BoxSpec& box,
                                     bool frictional, MotionBound& bound);

}  // namespace granular
