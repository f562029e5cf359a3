#pragma once
/// Where a particle centre is against a wall of any shape (docs/physics.md §2.19): its distance
/// from the wall's surface and the unit normal from the surface towards it. The force pass, the
/// measuring pass, the neighbour list and the step bound all ask this one function.
#include <algorithm>
#include <cmath>

#include "granular/wall.hpp"
#include "granular/wall_mesh.hpp"
#include "triangle_grid.hpp"

namespace granular {

/// A centre x against a wall: x = closest point + distance · normal. An infinite plane's
/// distance is signed (negative behind it); a shell's is ≥ 0, the normal then pointing to the
/// side x is on.
struct WallTouch {
  double distance = 0;  ///< [m]
  Vec3 normal;          ///< unit, from the surface towards x [-]
};

namespace wall_detail {

/// A unit vector normal to the unit `axis` (for a centre on a frustum's axis, where every
/// radial direction is as good).
inline Vec3 anyNormalTo(const Vec3& axis) {
  const Vec3 helper = std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return axis.cross(helper).normalized();
}

/// The closest point of a rectangle: inside its outline, straight across the plane; outside,
/// on its rim (an edge or a corner).
inline WallTouch rectangleTouch(const Wall& w, const Vec3& x) {
  const Vec3 r = x - w.point;
  const Vec3 side = w.normal.cross(w.edge);
  const double u = r.dot(w.edge), v = r.dot(side), across = r.dot(w.normal);
  const double a = w.halfSide[0], b = w.halfSide[1];
  if (std::abs(u) <= a && std::abs(v) <= b) {
    return {std::abs(across), across < 0.0 ? Vec3(-w.normal) : w.normal};
  }
  const Vec3 d = r - std::clamp(u, -a, a) * w.edge - std::clamp(v, -b, b) * side;
  const double distance = d.norm();
  return {distance, distance > 0.0 ? Vec3(d / distance) : w.normal};
}

/// The closest point of a surface of revolution lies in the centre's meridian half-plane: in
/// coordinates (z along the axis, ρ from it) the closest point of the segment from
/// (0, radiusStart) to (length, radiusEnd). Across the segment, straight along its meridian
/// normal; beyond either end, on that end's rim.
inline WallTouch frustumTouch(const Wall& w, const Vec3& x) {
  const Vec3 r = x - w.point;
  const double z = r.dot(w.normal);
  const Vec3 radial = r - z * w.normal;
  const double rho = radial.norm();
  const Vec3 out = rho > 0.0 ? Vec3(radial / rho) : anyNormalTo(w.normal);
  const double dz = w.length, dr = w.radiusEnd - w.radiusStart;
  const double along = z * dz + (rho - w.radiusStart) * dr;  // t · |segment|²
  const double length2 = dz * dz + dr * dr;
  if (along >= 0.0 && along <= length2) {
    const double length = std::sqrt(length2);
    // The meridian normal (−dr, dz)/|segment|, towards larger ρ along the segment.
    const double mz = -dr / length, mr = dz / length;
    const double across = z * mz + (rho - w.radiusStart) * mr;
    const Vec3 m = mz * w.normal + mr * out;
    return {std::abs(across), across < 0.0 ? Vec3(-m) : m};
  }
  const bool start = along < 0.0;
  const double ez = start ? z : z - dz;
  const double er = rho - (start ? w.radiusStart : w.radiusEnd);
  const double distance = std::hypot(ez, er);
  return {distance, distance > 0.0 ? Vec3((ez * w.normal + er * out) / distance) : out};
}

/// A mesh's nearest point, over all its triangles: for the few callers outside the force pass
/// that hold no grid of its triangles (the force pass's picks use the grid, mesh_gather.hpp).
inline WallTouch meshTouch(const Wall& w, const Vec3& x) {
  const MeshNearest nearest =
      nearestAmong(w.mesh->world, w.mesh->topology, AllTriangles{w.mesh->world.triangle.size()}, x);
  return {nearest.distance, nearest.normal};
}

}  // namespace wall_detail

inline WallTouch touchOf(const Wall& w, const Vec3& x) {
  switch (w.shape) {
    case WallShape::Rectangle:
      return wall_detail::rectangleTouch(w, x);
    case WallShape::Frustum:
      return wall_detail::frustumTouch(w, x);
    case WallShape::Mesh:
      return wall_detail::meshTouch(w, x);
    case WallShape::Plane:
      break;
  }
  return {(x - w.point).dot(w.normal), w.normal};
}

}  // namespace granular
