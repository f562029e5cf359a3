#pragma once
/// Local stress fields inside the bed, the paper's last part (Section 3.3, Figs. 9 and 10):
/// Eq. (1) over representative spheres on a grid, interpolated by a tricubic spline onto a fine
/// midsection grid, with principal stresses and σ1 trajectories. Compression is negative.
#include <array>
#include <optional>
#include <vector>

#include "granular/simulation.hpp"

namespace granular {

/// A regular grid of nodes: node (i, j, k) at origin + (i, j, k)·spacing, x fastest.
struct GridSpec {
  Vec3 origin = Vec3::Zero();   ///< first node [m]
  Vec3 spacing = Vec3::Ones();  ///< node spacing [m]
  std::array<int, 3> counts = {1, 1, 1};
  std::size_t size() const { return std::size_t(counts[0]) * counts[1] * counts[2]; }
  std::size_t index(int i, int j, int k) const {
    return (std::size_t(k) * counts[1] + j) * counts[0] + i;
  }
  Vec3 node(int i, int j, int k) const {
    return origin + Vec3(i * spacing.x(), j * spacing.y(), k * spacing.z());
  }
};

/// Eq. (1) in each representative sphere of a grid (the paper's method).
struct RepresentativeStress {
  GridSpec grid;               ///< sphere centres
  double radius = 0;           ///< representative sphere radius [m]
  std::vector<Mat3> stress;    ///< σ per sphere [Pa] (zero where no particle belongs)
  std::vector<double> volume;  ///< V_s: the sphere's volume inside the box [m³]
  /// Material volume of the member particles (each particle's volume less half of each lens
  /// it shares with a contacting particle) over V_s [-].
  std::vector<double> solidFraction;
  std::vector<int> members;  ///< particles whose centre lies in the sphere
};

/// Covers the box [boxMin, boxMax] with cells×cells×... representative spheres centred in the
/// cells of a regular division of the box, of radius `radius`. A particle belongs to every
/// sphere that contains its centre; a sphere's stress is (1/V_s) Σ F⊗l over all contacts of its
/// members, V_s its volume inside the box (exact, cut by the walls).
RepresentativeStress representativeSphereStress(const Simulation& sim, const Vec3& boxMin,
                                                const Vec3& boxMax, std::array<int, 3> cells,
                                                double radius);

/// One component of a tensor field sampled on a grid (x fastest) [Pa].
std::vector<double> component(const std::vector<Mat3>& field, int row, int col);

/// A field on a plane y = const, sampled on an nx × nz grid from xMin..xMax, zMin..zMax.
struct PlaneField {
  double xMin = 0, xMax = 1, zMin = 0, zMax = 1, y = 0;  ///< [m]
  int nx = 2, nz = 2;
  std::vector<Mat3> stress;  ///< x fastest [Pa]
  Vec3 point(int i, int k) const {
    return Vec3(xMin + (xMax - xMin) * i / (nx - 1), y, zMin + (zMax - zMin) * k / (nz - 1));
  }
};

/// The representative-sphere field interpolated (tricubic not-a-knot spline of each component,
/// extrapolated from the outer spheres to the walls) onto the plane y = `y`.
PlaneField interpolateOnPlane(const RepresentativeStress& field, double y, double xMin, double xMax,
                              double zMin, double zMax, int nx, int nz);

/// Trajectories of the most compressive principal stress σ1 of the plane's in-plane stress
/// (σ11, σ13, σ33): lines everywhere tangent to its direction, started at `starts` and traced
/// in the direction `heading` (e.g. −z, downwards) with step `step` [m] until they leave the
/// plane's rectangle or reach a nearly isotropic point, where the direction is undefined
/// (|σ1 − σ3| below `minAnisotropy` times their mean magnitude).
std::vector<std::vector<Vec3>> principalTrajectories(const PlaneField& plane,
                                                     const std::vector<Vec3>& starts, double step,
                                                     const Vec3& heading,
                                                     double minAnisotropy = 0.05);

/// The in-plane (x-z) principal direction of σ1 at a tensor, or nullopt where it is nearly
/// isotropic in the plane.
std::optional<Vec3> inPlaneSigma1(const Mat3& stress, double minAnisotropy);

}  // namespace granular
