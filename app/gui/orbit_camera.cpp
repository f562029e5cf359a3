#include "orbit_camera.hpp"

#include <algorithm>
#include <cmath>

namespace granular::gui {

void OrbitCamera::orbit(double dxPixels, double dyPixels) {
  azimuthDeg = std::fmod(azimuthDeg - 0.3 * dxPixels, 360.0);
  elevationDeg = std::clamp(elevationDeg + 0.3 * dyPixels, -89.0, 89.0);
}

void OrbitCamera::pan(double dxPixels, double dyPixels, int viewHeight) {
  const double perPixel = 1.0 / (zoom * std::max(1, viewHeight));
  panX -= dxPixels * perPixel;
  panY += dyPixels * perPixel;
}

void OrbitCamera::zoomBy(double wheelClicks) {
  zoom = std::clamp(zoom * std::pow(1.15, wheelClicks), 0.2, 20.0);
}

render::Camera OrbitCamera::camera(const Vec3& boxMin, const Vec3& boxMax, double aspect) const {
  render::Camera c = render::fitCamera(boxMin, boxMax, azimuthDeg, elevationDeg, 30.0, aspect);
  const Vec3 back = c.eye - c.target;
  const Vec3 forward = -back.normalized();
  Vec3 right = forward.cross(Vec3::UnitZ());
  right = right.norm() > 1e-9 ? right.normalized() : Vec3::UnitX();
  const Vec3 up = right.cross(forward);
  const double size = (boxMax - boxMin).norm();
  c.target += size * (panX * right + panY * up);
  c.eye = c.target + back / zoom;
  return c;
}

}  // namespace granular::gui
