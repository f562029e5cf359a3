#pragma once
/// Walls: bodies of infinite mass with a prescribed motion (docs/physics.md §2.3, §2.19). An
/// infinite plane bounds a half-space; the finite shapes are thin shells that particles touch
/// from either side, each giving a particle at most one contact: with its closest point.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "granular/vec3.hpp"

namespace granular {

/// The geometry of a wall.
enum class WallShape : std::uint8_t {
  /// An infinite plane through `point` with unit `normal` into the granular domain; a particle
  /// behind it presses into it however deep it is.
  Plane,
  /// A finite plane: the rectangle centred on `point` in the plane of `normal`, with half-sides
  /// `halfSide[0]` along the unit `edge` and `halfSide[1]` along normal × edge.
  Rectangle,
  /// The surface swept by the segment from radius `radiusStart` at `point` to `radiusEnd` at
  /// point + length · normal, about the axis through `point` along the unit `normal`: a cylinder
  /// (equal radii), a cone or frustum, a disc (length 0, radiusStart 0) or an annulus.
  Frustum,
  /// A triangle mesh (an STL file's): `mesh`, posed in the frame with origin `point`, z axis
  /// `normal` and x axis `edge`. Each triangle is touched from either side; a particle may
  /// touch the mesh at up to kMeshContacts places at once (docs/physics.md §2.20).
  Mesh,
};

struct WallMesh;

struct Wall {
  std::string name;           ///< "x-", "x+", "y-", "y+", "bottom", "top" or user's
  Vec3 point = Vec3::Zero();  ///< a point of the plane; a rectangle's centre; a frustum's base [m]
  Vec3 normal = Vec3::UnitZ();   ///< unit normal into the domain; a frustum's axis [-]
  Vec3 velocity = Vec3::Zero();  ///< prescribed translation velocity [m/s]
  Vec3 reaction = Vec3::Zero();  ///< force of the particles on the wall at the last step [N]
  /// ∫ reaction dt since the start [N s]: the mean reaction over any interval is the difference
  /// of two readings over its length (Eq. 2 asks for averaged reactions).
  Vec3 impulse = Vec3::Zero();

  WallShape shape = WallShape::Plane;
  Vec3 edge = Vec3::UnitX();    ///< a rectangle's unit direction of halfSide[0]; a mesh's x axis
  double halfSide[2] = {0, 0};  ///< a rectangle's half-sides [m]
  double length = 0;            ///< a frustum's extent along its axis [m]
  double radiusStart = 0;       ///< a frustum's radius at `point` [m]
  double radiusEnd = 0;         ///< a frustum's radius at point + length · normal [m]
  /// Prescribed angular velocity [rad/s] about the axis through `pivot` (a rotating drum, a
  /// stirrer). An infinite plane does not rotate.
  Vec3 angularVelocity = Vec3::Zero();
  Vec3 pivot = Vec3::Zero();  ///< a point of the rotation axis; it moves with `velocity` [m]
  /// How far any point of the surface can have moved since the start [m]: the sum of each
  /// step's bound (a shape turning about its own axis of symmetry moves no surface). The
  /// neighbour list is rebuilt when it has grown by the skin.
  double travel = 0;
  /// The Coulomb coefficient of the particles' contacts with this wall, μ_w [-], when it is
  /// not the particles' own (every other value of the contact law is the particles'). A
  /// wall's friction > 0 needs frictional particles.
  std::optional<double> friction = std::nullopt;
  /// Taken away (a gate opened, Simulation::removeWall): it touches nothing, draws nothing, and
  /// keeps its index and name so that the outputs keep their columns.
  bool removed = false;
  /// A mesh wall's triangles (shared by copies of the state; posed anew when it moves).
  std::shared_ptr<const WallMesh> mesh = nullptr;

  /// A finite shape (a shell touched from either side), not the infinite plane.
  bool shell() const { return shape != WallShape::Plane; }
  /// The velocity of the wall's material point at `at` [m/s].
  Vec3 velocityAt(const Vec3& at) const { return velocity + angularVelocity.cross(at - pivot); }
};

/// The distance of x from the wall's surface: signed for an infinite plane (negative behind
/// it), ≥ 0 for a shell [m]. A mesh's is found over all its triangles: for set-up work (placing
/// particles), not for every step.
double surfaceDistance(const Wall& w, const Vec3& x);
/// Whether the wall's surface lies nearer x than `r` (surfaceDistance(w, x) < r): a mesh's
/// triangles are looked at until one is, those whose plane is that far passed over (an insert
/// asks at every try to place a particle).
bool surfaceNearer(const Wall& w, const Vec3& x, double r);

}  // namespace granular
