#pragma once
/// Stresses of a granular assembly in a rectangular box: Eq. (1), the volume average of contact
/// forces and branch vectors, and Eq. (2), the face reactions over the face areas. Compression
/// is negative, as in the paper.
#include <vector>

#include "granular/simulation.hpp"

namespace granular {

/// Eq. (1): σ_ij = (1/V) Σ_c F_i^c l_j^c over every contact of every particle (particle pairs seen
/// from both sides, particle-wall contacts included), F^c the force on the particle and
/// l^c = C - x_i the branch vector from its centre to the contact point [Pa].
Mat3 volumeAveragedStress(const Simulation& sim, double volume);

/// Eq. (1) per particle over its own volume: σ^i = (1/V_i) Σ_c F^c (l^c)ᵀ over the contacts of
/// particle i, V_i = 4/3 π R_i³ (rows = force component, as volumeAveragedStress) [Pa]. So
/// Σ_i V_i σ^i = V σ of Eq. (1). A local measure (the particle's volume, not a cell around it):
/// for a continuum field use stress_field.hpp.
std::vector<Mat3> particleStresses(const Simulation& sim);

/// Σ_j |F_ij| per particle over all its contacts, particles and walls (the paper's Figs. 3 and 6
/// colour the particles by it) [N].
std::vector<double> particleForceSums(const Simulation& sim);

/// Both per-particle measures above from one evaluation of the contacts, for a caller that
/// shows both (the GUI's colourings, the ParaView snapshots): the same values as the two calls,
/// at the cost of one.
struct ParticleMeasures {
  std::vector<Mat3> stresses;     ///< σ^i, as particleStresses [Pa]
  std::vector<double> forceSums;  ///< Σ_j |F_ij|, as particleForceSums [N]
};
ParticleMeasures particleMeasures(const Simulation& sim);

/// The contact sums a box measurement needs; linear in the contact forces, so they may be
/// averaged over time like the reactions.
struct BoxContactSums {
  Mat3 eq1 = Mat3::Zero();  ///< σ of Eq. (1) over the box volume [Pa]
  /// Σ over side-wall contacts of F_z (z_c - z_floor): the moment about the floor of the
  /// vertical (friction) forces the side walls put on the particles [N m].
  double sideFrictionMoment = 0;
};

/// The box and what its walls carry, for the paper's Figs. 4, 5, 7 and 8.
struct BoxStress {
  Vec3 lower = Vec3::Zero();  ///< corner at the x-, y- and bottom walls [m]
  Vec3 upper = Vec3::Zero();  ///< corner at x+, y+ and the top wall (or the highest particle) [m]
  double volume = 0;          ///< (upper - lower) product [m³]
  double weight = 0;          ///< Σ m |g| [N]
  double topForce = 0;        ///< R33 of the top wall: the particles' push on it, upward [N]
  double bottomForce = 0;     ///< R33 of the bottom wall: its support of the particles [N]
  double sideMeanForce = 0;   ///< ¼ Σ |R| over the four side walls [N]
  double sideVerticalForce = 0;  ///< upward (friction) support of the side walls [N]
  /// (R33_bottom - R33_top + side vertical support - W) / W [-]
  double balanceError = 0;
  Mat3 eq1 = Mat3::Zero();        ///< σ of Eq. (1) over the box volume [Pa]
  Vec3 eq2 = Vec3::Zero();        ///< σ11, σ22, σ33 of Eq. (2): opposite faces averaged [Pa]
  double centreOfMassHeight = 0;  ///< z_cm above the floor [m]
  /// The part of σ33(Eq. 1) - σ33(Eq. 2) a static frictionless bed has exactly,
  /// (W/A)(1/2 - z_cm/H) (docs/physics.md §2.12); the rest of the difference is the remainder [Pa].
  double sigma33CentreOfMassTerm = 0;
  /// The further part a static bed has when the side walls carry weight by friction: with S
  /// their upward force acting at mean height z_S, (S/A)(z_S/H - 1/2) = (M/H - S/2)/A, M the
  /// sideFrictionMoment. Zero for a frictionless bed [Pa].
  double sigma33SideFrictionTerm = 0;
  double sideFrictionMoment = 0;  ///< see BoxContactSums [N m]
};

/// Eq. (1) and the side-wall friction moment of the box of `sim` at the current state.
BoxContactSums boxContactSums(const Simulation& sim);

/// Measures the box of `sim`, whose walls are named as in kBoxWallNames. `reactions` are the wall
/// forces to use for Eq. (2) and the balance, one per wall of `sim.walls()` (instantaneous ones,
/// or means over an interval from Wall::impulse); empty means the instantaneous reactions.
/// `sums` are the contact sums to report (time averages); null evaluates them now.
BoxStress measureBox(const Simulation& sim, const std::vector<Vec3>& reactions = {},
                     const BoxContactSums* sums = nullptr);

/// The field-by-field mean of several measurements (all fields are linear in the forces, or
/// constant) [same units as BoxStress].
BoxStress meanBoxStress(const std::vector<BoxStress>& samples);

}  // namespace granular
