#include "figure_export.hpp"

#include <algorithm>
#include <string>

#include "granular/render/particle_figure.hpp"
#include "granular/render/plot.hpp"
#include "wall_drawing.hpp"

namespace granular::gui {

namespace {

namespace fs = std::filesystem;
using render::Series;

Series line(const std::vector<float>& t, const std::vector<float>& y, const std::string& label,
            int colour, Series::Dash dash = Series::Solid) {
  Series s;
  s.x.assign(t.begin(), t.end());
  s.y.assign(y.begin(), y.end());
  s.label = label;
  s.color = render::categorical(colour);
  s.dash = dash;
  return s;
}

}  // namespace

std::vector<fs::path> exportFigures(const Snapshot& snap, const fs::path& folder) {
  fs::create_directories(folder);
  std::vector<fs::path> written;
  const std::string when =
      "t = " + std::to_string(snap.time).substr(0, 6) + " s, stage " + std::to_string(snap.stage);

  render::FigureRenderer figures;
  render::ParticleFigureSpec spec;
  spec.centres = snap.centres;
  spec.radii = snap.radii;
  spec.boxMin = snap.boxMin;
  spec.boxMax = snap.boxMax;
  if (snap.topWallZ) spec.boxMax.z() = *snap.topWallZ;
  spec.openTop = !snap.topWallZ;
  const WallDrawing walls = wallDrawing(snap.walls);
  spec.surfaces = walls.triangles;
  spec.outlines = walls.outlines;
  spec.values = snap.forceSum;
  spec.title = "Σ|F_ij| per particle, " + when;
  spec.colorBarTitle = "Σ|F_ij| [N]";
  written.push_back(folder / "particles_force.png");
  render::writePng(figures.particleFigure(spec), written.back());
  spec.values = snap.stress33;
  spec.title = "σ33 per particle, " + when;
  spec.colorBarTitle = "σ33 [Pa] (compression < 0)";
  written.push_back(folder / "particles_sigma33.png");
  render::writePng(figures.particleFigure(spec), written.back());

  const LiveSeries& s = snap.series;
  auto plot = [&](const std::string& file, const std::string& title, const std::string& yLabel,
                  std::vector<Series> series) {
    // A series without points is one the scene does not have (the box's, in a silo).
    if (std::all_of(series.begin(), series.end(), [](const Series& s) { return s.y.empty(); })) {
      return;
    }
    render::PlotSpec p;
    p.title = title;
    p.xLabel = snap.stage == 2 ? "t (stage 2) [s]" : "t [s]";
    p.yLabel = yLabel;
    p.series = std::move(series);
    p.grid = true;
    written.push_back(folder / file);
    render::writePng(render::drawPlot(p), written.back());
  };
  plot("sigma33.png", "σ33 by Eq. (1) and Eq. (2)", "σ33 [Pa]",
       {line(s.time, s.eq1[2], "Eq. (1)", 0), line(s.time, s.eq2[2], "Eq. (2)", 1)});
  plot("sigma11_22.png", "σ11 and σ22 by Eq. (1) and Eq. (2)", "σ [Pa]",
       {line(s.time, s.eq1[0], "σ11 Eq. (1)", 0), line(s.time, s.eq2[0], "σ11 Eq. (2)", 1),
        line(s.time, s.eq1[1], "σ22 Eq. (1)", 0, Series::Dashed),
        line(s.time, s.eq2[1], "σ22 Eq. (2)", 1, Series::Dashed)});
  plot("reactions.png", "Wall reactions R33", "R33 [N]",
       {line(s.time, s.bottomForce, "bottom", 0), line(s.time, s.topForce, "top", 1)});
  plot("kinetic_energy.png", "Kinetic energy", "E_k [J]", {line(s.time, s.kinetic, "E_k", 0)});
  return written;
}

}  // namespace granular::gui
