#pragma once
/// Export of the settled packing to the peer codes of bench/peer/ (LAMMPS and LIGGGHTS): the
/// particles, the box and the contact law written in each code's own input language, as close to
/// docs/physics.md §1 as that code can express it. bench/peer/README.md lists what remains
/// different.
#include <filesystem>

#include "granular/simulation.hpp"

namespace granular::peer {

/// What stage 2 of the paper adds to the settled state.
struct Stage2Setup {
  double topWallHeight = 0;             ///< the highest particle surface max(z + R) [m]
  Vec3 topWallVelocity = Vec3::Zero();  ///< [m/s]
};

/// Radius classes: LAMMPS and LIGGGHTS take a normal stiffness per pair of atom types, ours
/// is (2/3) E/(1-ν²) R_ij per contact, so the particles are put into `count` equal-width radius
/// classes and each class stands for its particles' mean radius.
struct RadiusClasses {
  std::vector<int> typeOf;      ///< class (atom type, from 1) of each particle
  std::vector<double> radius;   ///< mean radius of each class [m]; index 0 is type 1
  double maxRelativeError = 0;  ///< max |R_i - R_class| / R_i over the particles [-]
};

RadiusClasses classifyRadii(const Particles& particles, int count);

/// Writes `dir`/packing.data (atom_style sphere: id type diameter density x y z, velocities and
/// spins) and `dir`/model.lmp (pair_style granular coefficients per type pair, the five box
/// walls and the moving top wall, and the per-atom wall-force variables that
/// bench/peer/stage2.lmp reads). `perClassWalls` gives each radius class its own walls (wall
/// stiffness (2/3) E/(1-ν²) R_class); otherwise one set of walls uses the mean radius.
/// Throws std::runtime_error on an I/O error.
void writeLammps(const Simulation& sim, const Stage2Setup& setup, int radiusTypes,
                 bool perClassWalls, const std::filesystem::path& dir);

/// Writes `dir`/packing.data for LIGGGHTS (atom_style granular), `dir`/top_wall.stl (the
/// moving top plate as a mesh) and `dir`/model.liggghts (material properties per type pair and
/// the walls) for bench/peer/stage2.liggghts. Throws std::runtime_error on an I/O error.
void writeLiggghts(const Simulation& sim, const Stage2Setup& setup, int radiusTypes,
                   const std::filesystem::path& dir);

}  // namespace granular::peer
