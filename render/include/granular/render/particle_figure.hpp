#pragma once
/// A 3-D particle figure for publication: the spheres seen in perspective inside their box,
/// coloured by one value per particle through a colour scale, with a title and a colour bar
/// (the paper's Figs. 2, 3 and 6), and the walls of other shapes, translucent, where a scene has
/// them.
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "granular/render/colormap.hpp"
#include "granular/render/image.hpp"
#include "granular/render/particle_view.hpp"
#include "granular/render/style.hpp"
#include "granular/vec3.hpp"

namespace granular::render {

struct ParticleFigureSpec {
  std::span<const Vec3> centres;  ///< [m]
  std::span<const double> radii;  ///< [m]
  /// One per particle, coloured through the scale [any unit]; empty: every sphere one grey
  /// (ParticleScene::defaultColour) and no colour bar.
  std::span<const double> values;
  Vec3 boxMin = Vec3::Zero();  ///< the box drawn as edges, and framed by the camera [m]
  Vec3 boxMax = Vec3::Ones();
  bool openTop = true;  ///< leave out the top face's edges
  /// Walls drawn translucent over the particles, with their outlines (ParticleScene's surfaces
  /// and outlines) [m]; the camera frames them together with the box.
  std::span<const Triangle> surfaces;
  std::span<const Segment> outlines;
  std::string title;
  std::string colorBarTitle;  ///< with units, e.g. "Σ|F_ij| [N]"
  ColorMap map = viridis;
  std::optional<double> minValue, maxValue;  ///< colour range; default: the data's range
  double azimuthDeg = -60.0;  ///< camera direction from the box centre (see fitCamera)
  double elevationDeg = 20.0;
  int width = 900;    ///< [px]
  int height = 1100;  ///< [px]
  FigureStyle style;
};

/// Owns a headless GL context and the sphere renderer, so that a run of figures pays for them
/// once. Not thread-safe.
class FigureRenderer {
 public:
  FigureRenderer();  ///< throws RenderError when no OpenGL 3.3 context can be had
  ~FigureRenderer();
  FigureRenderer(const FigureRenderer&) = delete;
  FigureRenderer& operator=(const FigureRenderer&) = delete;

  Image particleFigure(const ParticleFigureSpec& spec);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace granular::render
