/// series_figures.hpp.
#include "series_figures.hpp"

#include <algorithm>
#include <cmath>

#include "granular/error.hpp"
#include "granular/render/plot.hpp"

namespace granular::app {

namespace {

using render::PlotSpec;
using render::Series;

constexpr double kDpi = 150.0;  // as the paper's figures

/// A column's name without its unit suffix and underscores: "kinetic_rotational_J" →
/// "kinetic rotational".
std::string labelOf(std::string name, const std::string& suffix) {
  if (name.ends_with(suffix)) name.resize(name.size() - suffix.size());
  std::replace(name.begin(), name.end(), '_', ' ');
  return name;
}

Series line(const RunSeries& s, std::vector<double> y, int index, const std::string& label) {
  Series line;
  line.x = s.time;
  line.y = std::move(y);
  line.color = render::categorical(index);
  // tab10 has ten colours: the next ten are dashed, the ten after dotted.
  line.dash = Series::Dash((index / 10) % 3);
  line.width = 1.8;
  line.label = label;
  return line;
}

PlotSpec basePlot(const RunSeries& s, const std::string& title, const std::string& yLabel) {
  PlotSpec p;
  p.title = title;
  p.xLabel = s.clockJoined ? "time since the run began [s]" : "t [s]";
  p.yLabel = yLabel;
  p.style = render::FigureStyle::forDpi(kDpi);
  p.width = 1200;
  p.height = 750;
  p.grid = true;
  return p;
}

/// The starts of the later stages as grey vertical lines across the data's range, each named
/// in the legend.
void markStages(const RunSeries& s, PlotSpec& p) {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (const Series& line : p.series) {
    for (double y : line.y) {
      if (!std::isfinite(y) || (p.yLog && y <= 0)) continue;
      lo = std::min(lo, y), hi = std::max(hi, y);
    }
  }
  if (!(lo <= hi)) return;
  for (const RunSeries::StageStart& start : s.stageStarts) {
    Series mark;
    mark.x = {start.time, start.time};
    mark.y = {lo, hi};
    mark.color = render::Rgba{120, 120, 120, 255};
    mark.width = 1.2;
    mark.dash = Series::Dotted;
    mark.label = "start of stage " + start.stage;
    p.series.push_back(mark);
  }
}

std::vector<std::string> columnsWith(const CsvTable& t, const std::string& prefix,
                                     const std::string& suffix) {
  std::vector<std::string> found;
  for (const std::string& name : t.header) {
    if (name.starts_with(prefix) && name.ends_with(suffix)) found.push_back(name);
  }
  return found;
}

}  // namespace

RunSeries readRunSeries(const std::filesystem::path& file) {
  RunSeries s;
  s.table = readCsv(file, {"stage"});
  const std::vector<double>& clock = s.table.column("time_s");
  const std::vector<std::string>& stage = s.table.text("stage");
  double offset = 0.0;
  for (std::size_t r = 0; r < clock.size(); ++r) {
    if (!std::isfinite(clock[r])) {
      throw IoError(file.string() + ":" + std::to_string(s.table.lines[r]) +
                    ": time_s is not a number");
    }
    if (r > 0 && stage[r] != stage[r - 1]) {
      // A stage that resets its clock starts where the stage before it left off.
      if (clock[r] < clock[r - 1]) {
        offset = s.time[r - 1] - clock[r];
        s.clockJoined = true;
      }
      s.stageStarts.push_back({stage[r], clock[r] + offset});
    }
    s.time.push_back(clock[r] + offset);
  }
  return s;
}

render::Image energyFigure(const RunSeries& s) {
  PlotSpec p = basePlot(s, "Energy ledger", "energy [J]");
  int index = 0;
  for (const std::string& name : columnsWith(s.table, "", "_J")) {
    Series l = line(s, s.table.column(name), index++, labelOf(name, "_J"));
    if (name == "energy_total_J") {
      l.width = 3.0;  // the balance the others add up to: bold black
      l.color = render::Rgba{0, 0, 0, 255};
      l.dash = Series::Solid;
    }
    p.series.push_back(std::move(l));
  }
  p.legend = render::LegendPosition::OutsideRight;
  markStages(s, p);
  return render::drawPlot(p);
}

std::optional<render::Image> kineticFigure(const RunSeries& s) {
  const std::vector<double>& translational = s.table.column("kinetic_translational_J");
  const std::vector<double>& rotational = s.table.column("kinetic_rotational_J");
  std::vector<double> total(translational.size());
  bool positive = false;
  for (std::size_t r = 0; r < total.size(); ++r) {
    total[r] = translational[r] + rotational[r];
    positive |= total[r] > 0;
  }
  if (!positive) return std::nullopt;
  PlotSpec p = basePlot(s, "Kinetic energy (log scale)", "kinetic energy [J]");
  p.yLog = true;
  p.series.push_back(line(s, total, 0, "translational + rotational"));
  p.series.push_back(line(s, translational, 1, "translational"));
  p.series.push_back(line(s, rotational, 2, "rotational"));
  p.series.back().dash = Series::Dashed;
  markStages(s, p);
  return render::drawPlot(p);
}

std::optional<render::Image> reactionFigure(const RunSeries& s) {
  const std::vector<std::string> columns = columnsWith(s.table, "reaction_", "_z_N");
  if (columns.empty()) return std::nullopt;
  // The vertical component: the one that carries the weight for every container, whatever the
  // walls' shapes.
  PlotSpec p = basePlot(s, "Wall reactions, vertical component (the particles' push on each wall)",
                        "R_z [N] (< 0: pushed down)");
  int index = 0;
  for (const std::string& name : columns) {
    p.series.push_back(line(s, s.table.column(name), index++,
                            name.substr(9, name.size() - 9 - 4)));  // reaction_<wall>_z_N
  }
  markStages(s, p);
  return render::drawPlot(p);
}

render::Image contactFigure(const RunSeries& s) {
  PlotSpec p = basePlot(s, "Contacts with overlap", "contacts [-]");
  int index = 0;
  for (const std::string& name : columnsWith(s.table, "contacts_", "")) {
    const std::string label = name == "contacts_particle_overlapping" ? "particle pairs"
                              : name == "contacts_wall_overlapping"   ? "particles on walls"
                                                                      : labelOf(name.substr(9), "");
    p.series.push_back(line(s, s.table.column(name), index++, label));
  }
  markStages(s, p);
  return render::drawPlot(p);
}

std::optional<render::Image> massFigure(const RunSeries& s) {
  const std::vector<std::string>& h = s.table.header;
  if (std::find(h.begin(), h.end(), "mass_held_kg") == h.end()) return std::nullopt;
  PlotSpec p = basePlot(s, "Particles in and out", "mass [kg]");
  int index = 0;
  for (const auto& [name, label] : {std::pair<const char*, const char*>{"mass_held_kg", "held"},
                                    {"mass_inserted_kg", "inserted"},
                                    {"mass_discharged_kg", "discharged"}}) {
    p.series.push_back(line(s, s.table.column(name), index++, label));
  }
  markStages(s, p);
  return render::drawPlot(p);
}

}  // namespace granular::app
