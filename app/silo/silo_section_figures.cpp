/// The settled silo's section figures (silo_section_figures.hpp). Sections: 1. the cut-away
/// view; 2. the midsection's stress; 3. files.
#include "silo_section_figures.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "granular/render/axes.hpp"
#include "granular/render/colorbar.hpp"
#include "granular/render/contour.hpp"
#include "granular/render/gl_context.hpp"
#include "granular/render/particle_view.hpp"
#include "granular/stress.hpp"
#include "run_header.hpp"

namespace granular::app {

namespace {

constexpr double kDpi = 150.0;  // at the full width, as the other figures

/// The style of a figure `width` px wide: the full-width figure's proportions.
render::FigureStyle figureStyle(int width) {
  return render::FigureStyle::forDpi(kDpi * width / kSectionFigureWidth);
}

/// The image's height for a frame of the given extent: the silo's own proportions once the
/// title, labels and colour bar take their room, within what a page holds.
int figureHeight(int width, double across, double up) {
  const double scale = double(width) / kSectionFigureWidth;
  return static_cast<int>(
      std::clamp(0.78 * width * up / across + 170.0 * scale, 700.0 * scale, 1800.0 * scale));
}

// ---- 1. The cut-away view -------------------------------------------------------------------

/// The value at fraction q of the sorted values (nearest rank); 0 for none.
double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const auto k = static_cast<std::ptrdiff_t>(std::floor(q * double(values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[std::size_t(k)];
}

/// The silo wall's far half from the floor to `zTop` (the hopper's cone, then the cylinder), as
/// the translucent back wall seen between the particles [m].
std::vector<render::Triangle> backWall(const SiloSectionGeometry& g, double zTop) {
  constexpr int kFacets = 48;
  std::vector<double> heights{g.floorZ};
  if (g.hasHopper() && g.transition < zTop) heights.push_back(g.transition);
  heights.push_back(zTop);
  std::vector<render::Triangle> triangles;
  for (std::size_t ring = 0; ring + 1 < heights.size(); ++ring) {
    const double z0 = heights[ring], z1 = heights[ring + 1];
    const double r0 = g.wallRadius(z0), r1 = g.wallRadius(z1);
    for (int s = 0; s < kFacets; ++s) {
      const double a = std::numbers::pi * s / kFacets, b = std::numbers::pi * (s + 1) / kFacets;
      const auto at = [](double r, double angle, double z) {
        return Vec3(r * std::cos(angle), r * std::sin(angle), z);
      };
      triangles.push_back({at(r0, a, z0), at(r0, b, z0), at(r1, b, z1)});
      triangles.push_back({at(r0, a, z0), at(r1, b, z1), at(r1, a, z1)});
    }
  }
  return triangles;
}

/// The silo wall's outline in the plane y = 0, one side (+1 or −1): from the top down the
/// cylinder, then the hopper's cone to the outlet, as (x, z) points [m].
std::vector<std::pair<double, double>> wallOutline(const SiloSectionGeometry& g, double zTop,
                                                   double side) {
  std::vector<std::pair<double, double>> points{{side * g.radius, zTop}};
  if (g.hasHopper()) points.emplace_back(side * g.radius, g.transition);
  points.emplace_back(side * g.wallRadius(g.floorZ), g.floorZ);
  return points;
}

}  // namespace

render::Image cutawayFigure(const Simulation& sim, const SiloSectionGeometry& g, int width) {
  const Particles& p = sim.particles();
  const std::vector<std::size_t> behind = particlesBehindCut(sim);
  const std::vector<double> sums = particleForceSums(sim);
  std::vector<Vec3> centres;
  std::vector<double> radii, values;
  double highest = g.top;
  for (std::size_t i : behind) {
    centres.push_back(p.position[i]);
    radii.push_back(p.radius[i]);
    values.push_back(sums[i]);
    highest = std::max(highest, p.position[i].z() + p.radius[i]);
  }
  const double clip = percentile(values, 0.99);
  const render::ColorScale scale{0.0, clip > 0 ? clip : 1.0, render::viridis};
  std::vector<render::Rgba> colours;
  for (double v : values) colours.push_back(scale(v));

  const render::FigureStyle style = figureStyle(width);
  const double pad = 0.08 * g.radius;
  render::AxesSpec a;
  a.title = "Σ|F_ij| per particle, the far half (y ≥ 0) seen from −y";
  a.xLabel = "x [m]";
  a.yLabel = "z [m]";
  a.xMin = -g.radius - pad;
  a.xMax = g.radius + pad;
  a.yMin = g.floorZ - pad;
  a.yMax = highest + pad;
  a.equalAspect = true;
  a.style = style;
  render::ColorBarSpec bar;
  bar.title = "Σ|F_ij| [N]";
  bar.style = style;
  const int height = figureHeight(width, a.xMax - a.xMin, a.yMax - a.yMin);
  const double barGap = std::round(1.2 * style.px(style.fontSize));
  a.reserveRight = barGap + render::colorBarExtent(scale, bar, 0.8 * height);
  render::Canvas canvas(width, height, style.background);
  const render::Axes axes(render::Rect{0, 0, double(width), double(height)}, a);
  const render::Rect& area = axes.area();

  // Nearly orthographic: the eye fifty frames away along −y sees the far wall 1 % smaller than
  // the cut face, and the cut face y = 0, square to the view, maps onto the axes exactly.
  const std::vector<render::Triangle> wall = backWall(g, a.yMax);
  render::ParticleScene scene;
  scene.centres = centres;
  scene.radii = radii;
  scene.colours = colours;
  scene.background = style.background;
  scene.surfaces = wall;
  scene.surfaceColour = {150, 150, 150, 40};
  render::Camera camera;
  camera.target = Vec3(0.5 * (a.xMin + a.xMax), 0.0, 0.5 * (a.yMin + a.yMax));
  const double distance = 50.0 * std::max(a.xMax - a.xMin, a.yMax - a.yMin);
  camera.eye = camera.target - distance * Vec3::UnitY();
  camera.up = Vec3::UnitZ();
  camera.fovYDegrees =
      2.0 * std::atan(0.5 * (a.yMax - a.yMin) / distance) * 180.0 / std::numbers::pi;
  {
    render::GlContext context;
    render::ParticleRenderer spheres(render::GlContext::procLoader());
    canvas.blit(spheres.render(scene, camera, static_cast<int>(area.w), static_cast<int>(area.h)),
                render::Point{area.x, area.y});
  }

  // The silo's sides and the floor, over the particles that press against them.
  render::Stroke walls;
  walls.color = {40, 40, 40, 255};
  walls.width = style.px(2.0);
  canvas.pushClip(area);
  for (const double side : {-1.0, 1.0}) {
    const auto outline = wallOutline(g, a.yMax, side);
    for (std::size_t k = 0; k + 1 < outline.size(); ++k) {
      canvas.line(axes.toPixel(outline[k].first, outline[k].second),
                  axes.toPixel(outline[k + 1].first, outline[k + 1].second), walls);
    }
  }
  const double floorHalf = g.wallRadius(g.floorZ);
  canvas.line(axes.toPixel(-floorHalf, g.floorZ), axes.toPixel(floorHalf, g.floorZ), walls);
  canvas.popClip();
  axes.drawFrame(canvas);
  const double x = area.right() + axes.lineWidth() + barGap;
  render::drawColorBarAt(
      canvas, render::Rect{x, area.top(), std::round(style.px(bar.thickness)), area.h}, scale, bar);
  return canvas.takeImage();
}

// ---- 2. The midsection's stress -------------------------------------------------------------

render::Image midsectionStressFigure(const Simulation& sim, const SiloSectionGeometry& g,
                                     int width) {
  const MidsectionStress m = midsectionStress(sim, g);
  const PlaneField& plane = m.plane;
  render::ContourSpec spec;
  spec.values.assign(plane.nz, std::vector<double>(plane.nx));
  for (int k = 0; k < plane.nz; ++k) {
    for (int i = 0; i < plane.nx; ++i) spec.values[k][i] = m.verticalStress(i, k);
  }
  spec.xMin = plane.xMin;
  spec.xMax = plane.xMax;
  spec.yMin = plane.zMin;
  spec.yMax = plane.zMax;
  spec.title = "Vertical stress and σ₁ trajectories, midsection y = 0";
  spec.xLabel = "x [m]";
  spec.yLabel = "z [m]";
  spec.colorBarTitle =
      "−σ₃₃, compression positive [Pa] (coarse-grained, c = " + format("%.2g", m.width) + " m)";
  spec.levelCount = 9;
  spec.labelIsolines = false;
  spec.isolineWidth = 0.6;
  spec.style = figureStyle(width);
  spec.width = width;
  spec.height = figureHeight(width, plane.xMax - plane.xMin, plane.zMax - plane.zMin);
  // Each trajectory white on a dark casing, so it reads on the bands' dark and light colours.
  for (const double lineWidth : {3.2, 1.6}) {
    for (const std::vector<Vec3>& line : m.sigma1) {
      render::PolylineOverlay overlay;
      for (const Vec3& point : line) overlay.points.push_back({point.x(), point.z()});
      overlay.color =
          lineWidth > 2 ? render::Rgba{30, 30, 30, 255} : render::Rgba{255, 255, 255, 255};
      overlay.width = lineWidth;
      spec.polylines.push_back(std::move(overlay));
    }
  }
  // A hopper's cone, where the plane leaves the material.
  if (g.hasHopper()) {
    for (const double side : {-1.0, 1.0}) {
      render::PolylineOverlay overlay;
      for (const auto& [x, z] : wallOutline(g, g.transition, side))
        overlay.points.push_back({x, z});
      overlay.color = render::Rgba{230, 230, 230, 255};
      overlay.width = 2.0;
      spec.polylines.push_back(std::move(overlay));
    }
  }
  return render::drawContour(spec);
}

// ---- 3. Files -------------------------------------------------------------------------------

std::vector<std::filesystem::path> writeSiloSectionFigures(const Simulation& settled,
                                                           const SiloSectionGeometry& geometry,
                                                           const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> written;
  auto save = [&](const render::Image& image, const std::string& name) {
    render::writePng(image, dir / name, kDpi);
    written.push_back(dir / name);
  };
  save(cutawayFigure(settled, geometry), "cutaway.png");
  save(midsectionStressFigure(settled, geometry), "midsection_stress.png");
  return written;
}

}  // namespace granular::app
