/// snapshot_figure.hpp.
#include "snapshot_figure.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "force_sums.hpp"
#include "granular/error.hpp"
#include "granular/render/plot.hpp"
#include "run_header.hpp"
#include "wall_cell_drawing.hpp"
#include "wall_pressure.hpp"

namespace granular::app {

namespace {

constexpr double kDpi = 150.0;  // as the paper's figures

/// A column's cells, each a finite number; IoError naming the file and line otherwise.
const std::vector<double>& finiteColumn(const CsvTable& t, const std::string& name) {
  const std::vector<double>& values = t.column(name);
  for (std::size_t r = 0; r < values.size(); ++r) {
    if (!std::isfinite(values[r])) {
      throw IoError(t.file.string() + ":" + std::to_string(t.lines[r]) + ": " + name +
                    " is not a number");
    }
  }
  return values;
}

/// The box's top face: at the top wall's height where the run has one (a lid that moves).
std::optional<double> topWallHeight(const SnapshotWalls& walls) {
  for (const WallCells& w : walls.walls) {
    if (w.name != "top" || !w.plane() || w.cells.empty() || w.cells[0].empty()) continue;
    return w.cells[0][0].z();
  }
  return std::nullopt;
}

double meanDiameter(const CsvTable& particles) {
  const std::vector<double>& r = particles.column("radius");
  double sum = 0;
  for (double x : r) sum += 2.0 * x;
  return r.empty() ? 0.0 : sum / double(r.size());
}

}  // namespace

SnapshotData readSnapshot(const SnapshotFiles& files) {
  SnapshotData s;
  s.files = files;
  s.particles = readCsv(files.particles);
  for (const char* name : {"id", "x", "y", "z", "radius"}) finiteColumn(s.particles, name);
  if (std::filesystem::exists(files.contacts)) s.contacts = readCsv(files.contacts, {"wall"});
  if (std::filesystem::exists(files.walls)) s.walls = readSnapshotWalls(files.walls);
  const std::string stage = files.name.substr(0, files.name.rfind('_'));
  s.when = "stage " + stage;
  const std::vector<double>& time = s.particles.column("time_s");
  if (!time.empty() && std::isfinite(time[0])) s.when += ", t = " + format("%.6g", time[0]) + " s";
  s.when += " (step " + std::to_string(files.step) + ")";
  return s;
}

DrawnFigure particleFigure(render::FigureRenderer& renderer, const SnapshotData& s) {
  DrawnFigure out;
  const CsvTable& t = s.particles;
  const std::vector<double>&x = t.column("x"), &y = t.column("y"), &z = t.column("z"),
        &radius = t.column("radius");
  std::vector<Vec3> centres;
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
  for (std::size_t i = 0; i < t.rows(); ++i) {
    centres.emplace_back(x[i], y[i], z[i]);
    lo = lo.cwiseMin(centres.back() - Vec3::Constant(radius[i]));
    hi = hi.cwiseMax(centres.back() + Vec3::Constant(radius[i]));
  }
  std::vector<double> sums;
  render::ParticleFigureSpec spec;
  spec.title = "Σ|F_ij| per particle, " + s.when;
  if (s.contacts) {
    sums = forceSums(*s.contacts, t.column("id"));
    spec.values = sums;
    spec.colorBarTitle = "Σ|F_ij| [N]";
    spec.minValue = 0.0;
  } else {
    spec.title = "Particles, " + s.when;
    out.notes.push_back("particles in one colour: " + s.files.contacts.filename().string() +
                        " is missing");
  }
  CellDrawing walls;
  if (s.walls) {
    walls = cellDrawing(s.walls->walls);
    spec.boxMin = s.walls->boxMin;
    spec.boxMax = s.walls->boxMax;
    const std::optional<double> top = topWallHeight(*s.walls);
    if (top) spec.boxMax.z() = *top;
    spec.openTop = !top;
    // Particles that have left the box (falling through an outlet, or above an open top as the
    // paper's start) stay in the frame: the box's edges reach out to them.
    spec.boxMin = spec.boxMin.cwiseMin(lo);
    spec.boxMax = spec.boxMax.cwiseMax(hi);
  } else {
    spec.boxMin = lo;
    spec.boxMax = hi;
    out.notes.push_back("no walls drawn, the box is the particles' bounding box: paraview/" +
                        s.files.walls.filename().string() + " is missing");
  }
  spec.surfaces = walls.triangles;
  spec.outlines = walls.outlines;
  spec.centres = centres;
  spec.radii = radius;
  spec.style = render::FigureStyle::forDpi(kDpi);
  // As tall as the framed scene asks (the view of a tall silo is tall), within reason.
  const auto [framedMin, framedMax] =
      render::boundsWith(spec.boxMin, spec.boxMax, walls.triangles, walls.outlines);
  const Vec3 size = framedMax - framedMin;
  const double across = std::max({size.x(), size.y(), 1e-12});
  spec.width = 1100;
  spec.height = int(std::clamp(1100 * size.z() / across * 0.75, 900.0, 1800.0));
  out.image = renderer.particleFigure(spec);
  return out;
}

bool hasShellWalls(const SnapshotData& s) {
  if (!s.walls) return false;
  return std::any_of(s.walls->walls.begin(), s.walls->walls.end(),
                     [](const WallCells& w) { return !w.plane() && !w.cells.empty(); });
}

render::Image pressureFigure(const SnapshotData& s) {
  if (!s.walls || !s.contacts) throw IoError(s.files.name + ": no walls or no contacts");
  const CsvTable& c = *s.contacts;
  const std::vector<std::string>& wallOf = c.text("wall");
  const std::vector<double>& z = c.column("point_z_m");
  const std::vector<double>& push = c.column("normal_force_N");
  // Two diameters: a band holds a ring of contacts or more, and the profile still follows a
  // Janssen-like rise over a bed tens of diameters deep.
  const double band = 2.0 * meanDiameter(s.particles);
  render::PlotSpec p;
  p.title = "Mean wall pressure against height, " + s.when;
  p.xLabel = "mean normal pressure in bands " + format("%.3g", band) + " m high [Pa]";
  p.yLabel = "z [m]";
  p.style = render::FigureStyle::forDpi(kDpi);
  p.width = 1200;
  p.height = 900;
  p.grid = true;
  int index = 0;
  for (const WallCells& wall : s.walls->walls) {
    if (wall.plane() || wall.cells.empty()) continue;
    WallContacts mine;
    for (std::size_t r = 0; r < c.rows(); ++r) {
      if (wallOf[r] != wall.name) continue;
      mine.z.push_back(z[r]);
      mine.force.push_back(push[r]);
    }
    render::Series line;
    for (const PressureBand& b : pressureProfile(wall, mine, band)) {
      line.x.push_back(b.pressure);
      line.y.push_back(b.z);
    }
    line.label = wall.name;
    line.color = render::categorical(index);
    line.marker = render::Marker(1 + index % 4);  // a flat wall is one band: a marker alone
    line.width = 1.8;
    ++index;
    p.series.push_back(std::move(line));
  }
  return render::drawPlot(p);
}

}  // namespace granular::app
