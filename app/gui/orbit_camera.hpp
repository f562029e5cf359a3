#pragma once
/// The 3-D view's camera: orbit (azimuth, elevation), zoom and pan about the box, starting from
/// the same framing as the headless figures (render::fitCamera).
#include "granular/render/particle_view.hpp"

namespace granular::gui {

struct OrbitCamera {
  double azimuthDeg = -60.0, elevationDeg = 20.0;
  double zoom = 1.0;          ///< > 1 moves the eye closer
  double panX = 0, panY = 0;  ///< target offset along the image's right and up [box sizes]

  void reset() { *this = OrbitCamera{}; }
  void orbit(double dxPixels, double dyPixels);
  void pan(double dxPixels, double dyPixels, int viewHeight);
  void zoomBy(double wheelClicks);
  render::Camera camera(const Vec3& boxMin, const Vec3& boxMax, double aspect) const;
};

}  // namespace granular::gui
