/// memory_estimate.hpp.
#include "granular/memory_estimate.hpp"

#include <cstdio>
#include <fstream>
#include <string>
#include <variant>

#include "granular/error.hpp"
#include "granular/output_file.hpp"

namespace granular {

namespace {

constexpr double kFrictionlessVerlet = 310;  // [B/particle]
constexpr double kFriction = 90;             // springs, spins and torques
constexpr double kGearDerivatives = 96;      // four more 3-vectors per integrated vector
/// The program before any particle: code, libraries (VTK, OpenGL), buffers [B].
constexpr std::uint64_t kProgram = 200ull << 20;

/// Lines in a particle CSV: one more than its rows (the header), and blank or comment lines.
std::uint64_t lineCount(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::uint64_t lines = 0;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) lines += buffer[i] == '\n';
  }
  return lines + 1;
}

std::string gigabytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / 1e9);
  return text;
}

}  // namespace

MemoryEstimate estimateMemory(const Scene& scene) {
  MemoryEstimate e;
  for (const Generator& g : scene.generators) {
    if (const auto* grid = std::get_if<GridGenerator>(&g)) {
      e.particles += grid->count;
    } else {
      e.particles += lineCount(std::get<CsvGenerator>(g).path);
    }
  }
  const bool frictional = scene.simulation.material.friction > 0.0;
  const bool gear = scene.simulation.integrator == Integrator::Gear5;
  e.bytesPerParticle = kFrictionlessVerlet + (frictional ? kFriction : 0.0) +
                       (gear ? kGearDerivatives * (frictional ? 2 : 1) : 0.0);
  // An automatic velocity-Verlet step may come from the spectrum's estimate, whose checks keep
  // the state to return to: the arrays again (MemoryUse::rollback; docs/physics.md §2.16).
  const bool kept = scene.simulation.step.automatic && !gear;
  if (kept) e.bytesPerParticle *= 2.0;
  // [friction][integrator: Verlet, Gear5, Verlet at an automatic step]
  static constexpr const char* kModels[2][3] = {
      {"frictionless velocity-Verlet", "frictionless Gear5",
       "frictionless velocity-Verlet (automatic step: the state kept twice)"},
      {"frictional velocity-Verlet", "frictional Gear5",
       "frictional velocity-Verlet (automatic step: the state kept twice)"}};
  e.model = kModels[frictional ? 1 : 0][gear ? 1 : (kept ? 2 : 0)];
  e.bytes = std::uint64_t(double(e.particles) * e.bytesPerParticle) + kProgram;
  return e;
}

void requireMemoryFor(const Scene& scene) {
  const std::uint64_t available = availableMemoryBytes();
  if (available == 0) return;
  const MemoryEstimate e = estimateMemory(scene);
  if (e.bytes <= available) return;
  const std::string name = scene.sourceFile.empty() ? "the scene" : scene.sourceFile.string();
  throw ConfigError(
      name + ": " + std::to_string(e.particles) + " particles need about " + gigabytes(e.bytes) +
      " of memory (" + std::to_string(int(e.bytesPerParticle)) + " B each for a " + e.model +
      " bed, at a neighbour-list rebuild) but this machine has " + gigabytes(available) +
      " available: use fewer particles or a machine with more memory");
}

}  // namespace granular
