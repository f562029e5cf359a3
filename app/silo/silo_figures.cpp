/// drawSiloFigures (silo_figures.hpp).
#include "silo_figures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "granular/beverloo.hpp"
#include "granular/janssen.hpp"
#include "granular/render/plot.hpp"

namespace granular::app {

namespace {

constexpr double kDpi = 150.0;  // as the other figures

render::PlotSpec basePlot(const std::string& title, const std::string& x, const std::string& y) {
  render::PlotSpec p;
  p.title = title;
  p.xLabel = x;
  p.yLabel = y;
  p.style = render::FigureStyle::forDpi(kDpi);
  p.width = 1200;
  p.height = 900;
  p.grid = true;
  return p;
}

std::string orificeLabel(const SiloDischarge& d, double diameter) {
  char text[80];
  std::snprintf(text, sizeof text, "D₀ = %.3f m (%.1f d)", d.orifice, d.orifice / diameter);
  return text;
}

/// The middle heights of the levels [m].
std::vector<double> middles(const SiloStudyResult& r) {
  std::vector<double> z;
  for (const SiloLevel& l : r.levels) z.push_back(0.5 * (l.zLow + l.zHigh));
  return z;
}

}  // namespace

render::Image wallPressureFigure(const SiloStudyResult& r) {
  // Along the wall from the bottom up: the hopper's bands (its normal pressure), then the
  // cylinder's levels (p_h), one line each.
  std::vector<double> z;
  for (const HopperBand& b : r.hopperBands) z.push_back(0.5 * (b.zLow + b.zHigh));
  for (double m : middles(r)) z.push_back(m);
  const auto alongWall = [&r](const std::vector<double>& hopper,
                              const std::vector<double>& cylinder) {
    std::vector<double> x(hopper.begin(), hopper.end());
    x.insert(x.end(), cylinder.begin(), cylinder.end());
    x.resize(r.hopperBands.size() + r.levels.size(), 0.0);
    return x;
  };
  render::PlotSpec p = r.hasHopper
                           ? basePlot("Wall pressure: p_h on the cylinder, p_n on the hopper",
                                      "p_h, p_n [Pa]", "z [m]")
                           : basePlot("Wall pressure", "p_h [Pa]", "z [m]");
  render::Series rest;
  rest.label = "at rest";
  rest.width = 2.2;
  rest.marker = render::Marker::Circle;
  render::Series low, high;
  for (const HopperBand& b : r.hopperBands) {
    rest.x.push_back(b.wallPressure);
    low.x.push_back(b.wallPressure - b.wallPressureStd);
    high.x.push_back(b.wallPressure + b.wallPressureStd);
  }
  for (const SiloLevel& l : r.levels) {
    rest.x.push_back(l.wallPressure);
    low.x.push_back(l.wallPressure - l.wallPressureStd);
    high.x.push_back(l.wallPressure + l.wallPressureStd);
  }
  rest.y = low.y = high.y = z;
  low.dash = high.dash = render::Series::Dotted;
  low.width = high.width = 1.0;
  low.label = "at rest ± its scatter";
  rest.color = low.color = high.color = render::categorical(0);
  p.series = {rest, low, high};
  int index = 1;
  for (const SiloDischarge& d : r.discharges) {
    if (!d.flowed) continue;
    render::Series s;
    s.x = alongWall(d.hopperPressure, d.wallPressure);
    s.y = z;
    s.color = render::categorical(index++);
    s.width = 1.6;
    s.label = "discharging, " + orificeLabel(d, r.particleDiameter);
    p.series.push_back(s);
  }
  p.references.push_back({r.surface, "surface", {80, 80, 80, 255}, 1.0, true});
  if (r.hasHopper) {
    p.references.push_back({r.transition, "transition", {80, 80, 80, 255}, 1.0, true});
  }
  return render::drawPlot(p);
}

render::Image verticalStressFigure(const SiloStudyResult& r) {
  const double gravity = r.gravity;
  {
    render::PlotSpec p = basePlot("Vertical stress at rest", "σ_v [Pa]", "z [m]");
    render::Series measured;
    measured.label = "Eq. (1) over slices";
    measured.width = 0;
    measured.marker = render::Marker::Circle;
    measured.markerSize = 8;
    for (const SiloLevel& l : r.levels) {
      measured.x.push_back(l.verticalStress);
      measured.y.push_back(0.5 * (l.zLow + l.zHigh));
    }
    render::Series janssen, hydrostatic;
    const double rh = circleHydraulicRadius(2.0 * r.radius);
    const double gamma = r.bulkDensity * gravity;
    const double bottom = r.levels.empty() ? 0.0 : r.levels.front().zLow;
    for (int k = 0; k <= 100; ++k) {
      const double height = bottom + (r.surface - bottom) * k / 100.0;
      const double depth = std::max(0.0, r.surface - height);  // the top point rounds below 0
      if (r.janssen.lambda > 0) {
        janssen.x.push_back(janssenVerticalStress(depth, gamma, rh, r.janssen.lambda));
        janssen.y.push_back(height);
      }
      hydrostatic.x.push_back(gamma * depth);
      hydrostatic.y.push_back(height);
    }
    char label[96];
    std::snprintf(label, sizeof label, "Janssen, λ = μ_w K = %.3f (RMS %.1f %%)", r.janssen.lambda,
                  100 * r.janssen.rmsRelativeResidual);
    janssen.label = label;
    janssen.width = 2.2;
    janssen.color = render::categorical(1);
    hydrostatic.label = "hydrostatic, ρ_b g h";
    hydrostatic.dash = render::Series::Dashed;
    hydrostatic.color = render::categorical(2);
    measured.color = render::categorical(0);
    p.series = {measured, janssen, hydrostatic};
    p.references.push_back({r.surface, "surface", {80, 80, 80, 255}, 1.0, true});
    return render::drawPlot(p);
  }
}

render::Image dischargeFigure(const SiloStudyResult& r) {
  const double gravity = r.gravity;
  {
    render::PlotSpec p =
        basePlot("Discharge", "time since the orifice opened [s]", "discharged mass [kg]");
    p.height = 750;
    int index = 0;
    for (const SiloDischarge& d : r.discharges) {
      render::Series s;
      s.x = d.time;
      s.y = d.discharged;
      s.color = render::categorical(index);
      s.width = 2.0;
      s.label = orificeLabel(d, r.particleDiameter);
      p.series.push_back(s);
      if (d.flowed && r.beverlooFitted) {
        const double w = beverlooRate(r.beverloo.c, r.beverloo.k, r.bulkDensity, gravity, d.orifice,
                                      r.particleDiameter);
        // Through the middle of the steady window at Beverloo's slope.
        const double tm = 0.5 * (d.steady.t0 + d.steady.t1);
        const double mm = d.steady.intercept + d.steady.rate * tm;
        render::Series line;
        line.x = {d.steady.t0, d.steady.t1};
        line.y = {mm + w * (d.steady.t0 - tm), mm + w * (d.steady.t1 - tm)};
        line.color = render::Rgba{0, 0, 0, 255};  // black over the measured colours
        line.dash = render::Series::Dashed;
        line.width = 1.4;
        if (index == 0) line.label = "Beverloo, fitted C and k";
        p.series.push_back(line);
      }
      ++index;
    }
    return render::drawPlot(p);
  }
}

std::vector<std::filesystem::path> drawSiloFigures(const SiloStudyResult& r,
                                                   const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> written;
  auto save = [&](const render::Image& image, const std::string& name) {
    render::writePng(image, dir / name, kDpi);
    written.push_back(dir / name);
  };
  save(wallPressureFigure(r), "wall_pressure.png");
  save(verticalStressFigure(r), "vertical_stress.png");
  save(dischargeFigure(r), "discharge.png");
  return written;
}

}  // namespace granular::app
