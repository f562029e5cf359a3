/// Walls' motion and the refusals of their shapes (wall_motion.hpp).
#include "wall_motion.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "config_validation.hpp"
#include "granular/wall_mesh.hpp"

namespace granular {

namespace {

/// The farthest any point of the shell's surface is from its `point` [m].
double extent(const Wall& w) {
  if (w.shape == WallShape::Rectangle) return std::hypot(w.halfSide[0], w.halfSide[1]);
  if (w.shape == WallShape::Mesh) return w.mesh ? w.mesh->extent : 0.0;
  return std::max(w.radiusStart, std::hypot(w.length, w.radiusEnd));
}

/// A frustum turning about its own axis: its surface stays where it is.
bool turnsInPlace(const Wall& w, const Vec3& axis) {
  if (w.shape != WallShape::Frustum) return false;
  const double scale = std::max({1.0, w.length, w.radiusStart, w.radiusEnd});
  return axis.cross(w.normal).norm() < 1e-12 &&
         (w.pivot - w.point).cross(w.normal).norm() < 1e-12 * scale;
}

std::string vectorText(const Vec3& v) {
  std::string text = "(";
  for (int k = 0; k < 3; ++k) text.append(shortNumber(v[k])).append(k < 2 ? ", " : ")");
  return text;
}

}  // namespace

void moveWall(Wall& w, double dt) {
  if (!w.shell()) {
    w.point += w.velocity * dt;
    return;
  }
  const Vec3 shift = w.velocity * dt;
  w.point += shift;
  w.pivot += shift;
  double travel = shift.norm();
  bool turned = false;
  const double spin = w.angularVelocity.norm();
  if (spin > 0.0) {
    const Vec3 axis = w.angularVelocity / spin;
    if (!turnsInPlace(w, axis)) {
      const double angle = spin * dt;
      travel += angle * ((w.point - w.pivot).norm() + extent(w));
      const Eigen::AngleAxisd turn(angle, axis);
      w.point = w.pivot + turn * (w.point - w.pivot);
      w.normal = (turn * w.normal).normalized();
      const Vec3 edge = turn * w.edge;
      w.edge = (edge - edge.dot(w.normal) * w.normal).normalized();
      turned = true;
    }
  }
  w.travel += travel;
  // A mesh's triangles follow its frame.
  if (w.shape == WallShape::Mesh && (turned || !shift.isZero(0.0))) {
    w.mesh = poseMesh(w.mesh->body, w.point, w.normal, w.edge);
  }
}

void validateWall(const Wall& w) {
  const std::string name = "wall " + w.name + ": ";
  requireConfig(w.point.allFinite() && w.velocity.allFinite() && w.normal.allFinite(),
                name + "not finite");
  requireConfig(std::abs(w.normal.norm() - 1.0) < 1e-12,
                name + (w.shape == WallShape::Frustum ? "axis" : "normal") + " " +
                    vectorText(w.normal) + " must be a unit vector");
  requireConfig(w.angularVelocity.allFinite() && w.pivot.allFinite(),
                name + "angular velocity and pivot must be finite");
  if (w.friction) {
    requireConfig(std::isfinite(*w.friction) && *w.friction >= 0.0 && *w.friction <= 10.0,
                  name + "friction = " + shortNumber(*w.friction) + ": must be in [0, 10]");
  }
  if (w.shape == WallShape::Plane) {
    requireConfig(w.angularVelocity.isZero(0.0),
                  name + "an infinite plane does not turn (angular velocity " +
                      vectorText(w.angularVelocity) + " rad/s); make it a rectangle");
    return;
  }
  auto positive = [&](double v, const char* what) {
    requireConfig(std::isfinite(v) && v > 0.0,
                  name + what + " = " + shortNumber(v) + " m: must be > 0");
  };
  auto notNegative = [&](double v, const char* what) {
    requireConfig(std::isfinite(v) && v >= 0.0,
                  name + what + " = " + shortNumber(v) + " m: must be >= 0");
  };
  if (w.shape == WallShape::Mesh) {
    requireConfig(w.mesh && w.mesh->body && !w.mesh->world.triangle.empty(),
                  name + "a mesh wall without triangles");
    requireConfig(std::abs(w.edge.norm() - 1.0) < 1e-12 && std::abs(w.edge.dot(w.normal)) < 1e-12,
                  name + "its frame's x axis " + vectorText(w.edge) +
                      " must be a unit vector normal to its z axis " + vectorText(w.normal));
    return;
  }
  if (w.shape == WallShape::Rectangle) {
    requireConfig(std::abs(w.edge.norm() - 1.0) < 1e-12 && std::abs(w.edge.dot(w.normal)) < 1e-12,
                  name + "edge " + vectorText(w.edge) +
                      " must be a unit vector in the plane (normal to the normal " +
                      vectorText(w.normal) + ")");
    positive(w.halfSide[0], "half side along the edge");
    positive(w.halfSide[1], "half side across the edge");
    return;
  }
  notNegative(w.length, "length");
  notNegative(w.radiusStart, "radius at the start");
  notNegative(w.radiusEnd, "radius at the end");
  requireConfig(w.length > 0.0 || w.radiusStart != w.radiusEnd,
                name +
                    "a surface of revolution needs a length > 0 or two different radii (a "
                    "disc or annulus)");
}

}  // namespace granular
