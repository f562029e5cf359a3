/// The 3-D particle figure (particle_figure.hpp): layout of title, view and colour bar, the view
/// rendered by ParticleRenderer (the walls' surfaces with it) and blitted into a 2-D canvas.
#include "granular/render/particle_figure.hpp"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "granular/render/canvas.hpp"
#include "granular/render/colorbar.hpp"
#include "granular/render/gl_context.hpp"
#include "granular/render/particle_view.hpp"

namespace granular::render {

struct FigureRenderer::Impl {
  GlContext context;
  ParticleRenderer spheres{GlContext::procLoader()};
};

FigureRenderer::FigureRenderer() : impl_(std::make_unique<Impl>()) {}
FigureRenderer::~FigureRenderer() = default;

Image FigureRenderer::particleFigure(const ParticleFigureSpec& spec) {
  if (spec.centres.size() != spec.radii.size() ||
      (!spec.values.empty() && spec.values.size() != spec.centres.size())) {
    throw std::invalid_argument("particleFigure: centres, radii and values differ in length");
  }
  const FigureStyle& style = spec.style;
  ColorScale scale{0.0, 1.0, spec.map};
  if (!spec.values.empty()) {
    const auto [lo, hi] = std::minmax_element(spec.values.begin(), spec.values.end());
    scale.min = spec.minValue.value_or(*lo);
    scale.max = spec.maxValue.value_or(*hi);
  }
  std::vector<Rgba> colours(spec.values.size());
  for (std::size_t i = 0; i < colours.size(); ++i) colours[i] = scale(spec.values[i]);

  // Layout: title on top, colour bar on the right, the view in what is left.
  Canvas canvas(spec.width, spec.height, style.background);
  const double margin = style.px(style.margin);
  double top = margin;
  if (!spec.title.empty()) {
    TextStyle title{style.px(style.titleFontSize), FontWeight::Bold, style.ink, HAlign::Center,
                    VAlign::Top};
    top = canvas.text({spec.width / 2.0, margin}, spec.title, title).bottom() + margin;
  }
  // Without values there is no scale to show: the view takes the colour bar's place.
  double viewRight = spec.width - margin;
  if (!spec.values.empty() || spec.centres.empty()) {
    ColorBarSpec bar;
    bar.title = spec.colorBarTitle;
    bar.style = style;
    const double barLength = 0.6 * (spec.height - top - margin);
    const double barExtent = colorBarExtent(scale, bar, barLength);
    const Rect barArea =
        Rect::fromEdges(spec.width - margin - barExtent, top + 0.2 * (spec.height - top - margin),
                        spec.width - margin, top + 0.2 * (spec.height - top - margin) + barLength);
    drawColorBar(canvas, barArea, scale, bar);
    viewRight = barArea.left() - margin;
  }
  const Rect view = Rect::fromEdges(margin, top, viewRight, spec.height - margin);

  const int viewWidth = std::max(1, static_cast<int>(view.w));
  const int viewHeight = std::max(1, static_cast<int>(view.h));
  ParticleScene scene;
  scene.centres = spec.centres;
  scene.radii = spec.radii;
  scene.colours = colours;
  scene.lines = boxEdges(spec.boxMin, spec.boxMax, spec.openTop);
  scene.lineWidth = std::max(1.0, style.px(1.5));
  scene.background = style.background;
  scene.surfaces = spec.surfaces;
  scene.outlines = spec.outlines;
  // Without walls this is the box itself, and the figure frames exactly as it always has.
  const auto [framedMin, framedMax] =
      boundsWith(spec.boxMin, spec.boxMax, spec.surfaces, spec.outlines);
  const Camera camera = fitCamera(framedMin, framedMax, spec.azimuthDeg, spec.elevationDeg, 30.0,
                                  double(viewWidth) / viewHeight, 0.04);
  canvas.blit(impl_->spheres.render(scene, camera, viewWidth, viewHeight), Point{view.x, view.y});
  return canvas.takeImage();
}

}  // namespace granular::render
