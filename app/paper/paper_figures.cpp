/// The paper's figures from saved results (paper_figures.hpp). Sections: 1. reading a case;
/// 2. the 3-D figures; 3. the time plots; 4. all of them.
#include "paper_figures.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <iostream>
#include <optional>

#include "csv_input.hpp"
#include "csv_output.hpp"
#include "granular/render/colormap.hpp"
#include "granular/render/contour.hpp"
#include "granular/render/particle_figure.hpp"
#include "granular/render/plot.hpp"
#include "run_header.hpp"
#include "stop_signals.hpp"

namespace granular::app {
namespace {

using render::Image;
using render::PlotSpec;
using render::Series;

constexpr double kDpi = 150.0;  // the figures' resolution: readable on screen, fine for print

struct Case {
  std::string name;   ///< folder: mu0, mu03
  std::string label;  ///< "μ = 0"
};
const Case kCases[] = {{"mu0", "μ = 0"}, {"mu03", "μ = 0.3"}};

// 1. Reading a case ---------------------------------------------------------------------------

struct ParticleData {
  std::vector<Vec3> centres;
  std::vector<double> radii, values;
};

ParticleData readParticles(const std::filesystem::path& file, const std::string& valueColumn) {
  const CsvTable t = readCsv(file);
  ParticleData d;
  const auto &x = t.column("x_m"), &y = t.column("y_m"), &z = t.column("z_m");
  for (std::size_t i = 0; i < t.rows(); ++i) d.centres.emplace_back(x[i], y[i], z[i]);
  d.radii = t.column("radius_m");
  d.values = t.column(valueColumn);
  return d;
}

/// The box's floor corner and its x, y extent from box.txt; the top at the highest particle.
std::pair<Vec3, Vec3> readBox(const std::filesystem::path& file, const ParticleData& particles) {
  const auto kv = readKeyValues(file);
  const Vec3 lo(numberAt(kv, "x_min", file), numberAt(kv, "y_min", file),
                numberAt(kv, "z_min", file));
  double top = lo.z();
  for (std::size_t i = 0; i < particles.centres.size(); ++i) {
    top = std::max(top, particles.centres[i].z() + particles.radii[i]);
  }
  return {lo, Vec3(numberAt(kv, "x_max", file), numberAt(kv, "y_max", file), top)};
}

// 2. The 3-D figures --------------------------------------------------------------------------

Image particleFigure(render::FigureRenderer& renderer, const std::filesystem::path& dir,
                     const std::string& file, const std::string& column, const std::string& title,
                     const std::string& barTitle) {
  const ParticleData d = readParticles(dir / file, column);
  const auto [lo, hi] = readBox(dir / "box.txt", d);
  render::ParticleFigureSpec spec;
  spec.centres = d.centres;
  spec.radii = d.radii;
  spec.values = d.values;
  spec.boxMin = lo;
  spec.boxMax = hi;
  spec.title = title;
  spec.colorBarTitle = barTitle;
  spec.minValue = 0.0;
  spec.style = render::FigureStyle::forDpi(kDpi);
  spec.width = 1100;
  spec.height = static_cast<int>(
      std::clamp(1100 * (hi.z() - lo.z()) / (hi.x() - lo.x()) * 0.75, 900.0, 1800.0));
  return renderer.particleFigure(spec);
}

// 3. The time plots ---------------------------------------------------------------------------

Series line(const std::vector<double>& x, const std::vector<double>& y, int colour,
            const std::string& label, double width = 1.5) {
  Series s;
  s.x = x;
  s.y = y;
  s.color = render::categorical(colour);
  s.width = width;
  s.label = label;
  return s;
}

PlotSpec basePlot(const std::string& title, const std::string& yLabel) {
  PlotSpec p;
  p.title = title;
  p.xLabel = "t [s]";
  p.yLabel = yLabel;
  p.style = render::FigureStyle::forDpi(kDpi);
  p.width = 1200;
  p.height = 750;
  return p;
}

/// The columns each time plot draws, whose cells are checked for numbers before it is drawn.
const std::vector<std::string> kForceColumns = {"time_s", "R33_bottom_N", "R33_top_N",
                                                "side_mean_R_N", "weight_N"};
const std::vector<std::string> kStressColumns = {
    "time_s", "s11_eq1_Pa", "s22_eq1_Pa", "s33_eq1_Pa", "s11_eq2_Pa", "s22_eq2_Pa", "s33_eq2_Pa"};
const std::vector<std::string> kSettleColumns = {"time_s", "kinetic_J"};

/// The largest finite value; nullopt when there is none.
std::optional<double> finiteMax(const std::vector<double>& values) {
  std::optional<double> top;
  for (double v : values) {
    if (std::isfinite(v)) top = top ? std::max(*top, v) : v;
  }
  return top;
}

/// Figs. 4 and 7: vertical reactions of top and bottom walls, the weight, the mean side wall.
/// A cell that is not a number is a gap in its line (the caller has said so).
Image forcesFigure(const CsvTable& t, const std::string& label) {
  const auto& time = t.column("time_s");
  PlotSpec p = basePlot("Forces vs time, stage 2 (" + label + ")", "force [N]");
  p.series.push_back(line(time, t.column("R33_bottom_N"), 0, "R₃₃ bottom", 2.0));
  p.series.push_back(line(time, t.column("R33_top_N"), 1, "R₃₃ top", 2.0));
  p.series.push_back(line(time, t.column("side_mean_R_N"), 2, "¼ Σ |R| side walls", 2.0));
  double top = finiteMax(t.column("R33_bottom_N")).value_or(0.0);
  // The weight is the same in every row: the first one that is a number.
  for (double w : t.column("weight_N")) {
    if (!std::isfinite(w)) continue;
    render::ReferenceLine weight;
    weight.y = w;
    weight.label = "weight";
    p.references.push_back(weight);
    top = std::max(top, w);
    break;
  }
  if (top > 0) p.yRange = render::AxisRange{0.0, 1.15 * top};
  return render::drawPlot(p);
}

/// Figs. 5 and 8: σ11, σ22, σ33 of Eq. (1) thin and of Eq. (2) bold.
Image stressFigure(const CsvTable& t, const std::string& label) {
  const auto& time = t.column("time_s");
  PlotSpec p = basePlot("Normal stresses vs time, stage 2 (" + label + ")", "σ [Pa]");
  const char* names[] = {"σ₁₁", "σ₂₂", "σ₃₃"};
  for (int i = 0; i < 3; ++i) {
    const std::string ii = std::to_string(i + 1) + std::to_string(i + 1);
    p.series.push_back(
        line(time, t.column("s" + ii + "_eq1_Pa"), i, std::string(names[i]) + " Eq. (1)", 1.2));
  }
  for (int i = 0; i < 3; ++i) {
    const std::string ii = std::to_string(i + 1) + std::to_string(i + 1);
    p.series.push_back(
        line(time, t.column("s" + ii + "_eq2_Pa"), i, std::string(names[i]) + " Eq. (2)", 3.2));
  }
  return render::drawPlot(p);
}

/// Stage 1: the kinetic energy falling by orders of magnitude, on a log scale.
Image settleFigure(const std::vector<std::pair<std::string, CsvTable>>& cases, double threshold) {
  PlotSpec p = basePlot("Kinetic energy while settling, stage 1", "log₁₀ (kinetic energy [J])");
  if (threshold > 0) {
    render::ReferenceLine end;
    end.y = std::log10(threshold);
    end.label = "end of stage 1: below " + format("%g", threshold) + " J, sustained";
    p.references.push_back(end);
  }
  int colour = 0;
  for (const auto& [label, t] : cases) {
    std::vector<double> logKe;
    for (double e : t.column("kinetic_J")) logKe.push_back(e > 0 ? std::log10(e) : std::nan(""));
    p.series.push_back(line(t.column("time_s"), logKe, colour++, label, 2.0));
  }
  return render::drawPlot(p);
}

// 3b. The stress fields (Figs. 9 and 10 and beyond) -------------------------------------------

/// One column of fields/midsection.csv as the grid a contour map takes (row 0 at the floor).
render::ContourSpec midsectionMap(const CsvTable& t, const std::string& column) {
  const auto &i = t.column("i"), &k = t.column("k"), &x = t.column("x_m"), &z = t.column("z_m");
  const auto& v = t.column(column);
  const int nx = static_cast<int>(*std::max_element(i.begin(), i.end())) + 1;
  const int nz = static_cast<int>(*std::max_element(k.begin(), k.end())) + 1;
  render::ContourSpec spec;
  spec.values.assign(nz, std::vector<double>(nx, std::nan("")));
  for (std::size_t r = 0; r < t.rows(); ++r) spec.values[int(k[r])][int(i[r])] = v[r];
  spec.xMin = *std::min_element(x.begin(), x.end());
  spec.xMax = *std::max_element(x.begin(), x.end());
  spec.yMin = *std::min_element(z.begin(), z.end());
  spec.yMax = *std::max_element(z.begin(), z.end());
  spec.xLabel = "x [m]";
  spec.yLabel = "z [m]";
  spec.style = render::FigureStyle::forDpi(kDpi);
  spec.width = 1000;
  spec.height = static_cast<int>(
      1000 * std::clamp((spec.yMax - spec.yMin) / (spec.xMax - spec.xMin), 1.0, 2.2));
  return spec;
}

/// Fig. 9: σ33 on the midsection y = L/2, filled bands with labelled isolines.
Image sigma33Figure(const CsvTable& t, const std::string& column, const std::string& title) {
  render::ContourSpec spec = midsectionMap(t, column);
  spec.title = title;
  spec.colorBarTitle = "σ₃₃ [Pa]";
  spec.levelCount = 9;
  return render::drawContour(spec);
}

/// Fig. 10: σ1 trajectories over the midsection, the walls as the frame.
Image trajectoryFigure(const CsvTable& field, const CsvTable& lines, const std::string& title) {
  render::ContourSpec spec = midsectionMap(field, "s33_rep_Pa");
  spec.values.clear();  // axes and overlays only: the walls are the frame
  spec.colorBar = false;
  spec.title = title;
  const auto &id = lines.column("line"), &x = lines.column("x_m"), &z = lines.column("z_m");
  for (std::size_t r = 0; r < lines.rows(); ++r) {
    if (r == 0 || id[r] != id[r - 1]) {
      spec.polylines.emplace_back();
      spec.polylines.back().color = render::categorical(0);
      spec.polylines.back().width = 2.0;
    }
    spec.polylines.back().points.push_back({x[r], z[r]});
  }
  return render::drawContour(spec);
}

/// The columns of profiles.csv that profileFigure draws.
std::vector<std::string> profileColumns(bool frictional) {
  return {"z_m",
          "s33_rep_centre_Pa",
          "s33_cg_centre_c0.05_Pa",
          "s33_cg_centre_c0.1_Pa",
          "s33_cg_centre_c0.15_Pa",
          "s33_cg_section_mean_Pa",
          frictional ? "janssen_Pa" : "hydrostatic_Pa"};
}

/// σ33 against height: the centre line (representative spheres; coarse-grained at three widths),
/// the cross-section mean, and Janssen's law or the hydrostatic load.
Image profileFigure(const CsvTable& t, const std::string& label, bool frictional) {
  PlotSpec p = basePlot("σ₃₃ against height, end of stage 1 (" + label + ")", "σ₃₃ [Pa]");
  p.xLabel = "z [m]";
  const auto& z = t.column("z_m");
  p.series.push_back(
      line(z, t.column("s33_rep_centre_Pa"), 0, "centre line, spheres (Eq. 1)", 1.5));
  int colour = 1;
  for (const std::string w : {"0.05", "0.1", "0.15"}) {
    p.series.push_back(line(z, t.column("s33_cg_centre_c" + w + "_Pa"), colour++,
                            "centre line, coarse-grained c = " + w + " m", 1.2));
  }
  p.series.push_back(
      line(z, t.column("s33_cg_section_mean_Pa"), 4, "cross-section mean (c = 0.1 m)", 3.0));
  Series reference = line(z, t.column(frictional ? "janssen_Pa" : "hydrostatic_Pa"), 7,
                          frictional ? "Janssen, fitted μ_w K" : "hydrostatic (weight above)", 2.0);
  reference.dash = Series::Dashed;
  p.series.push_back(reference);
  p.legend = render::LegendPosition::LowerRight;
  return render::drawPlot(p);
}

}  // namespace

// 4. All of them ------------------------------------------------------------------------------

/// The label of a case: its friction as case.txt records it ("μ = 0.3"), else its folder's.
std::string caseLabel(const std::filesystem::path& dir, const Case& c) {
  const std::filesystem::path file = dir / "case.txt";
  if (!std::filesystem::exists(file)) return c.label;
  return "μ = " + format("%g", numberAt(readKeyValues(file), "friction", file));
}

FigureSet drawPaperFigures(const std::filesystem::path& runDir) {
  const std::filesystem::path out = runDir / "figures";
  FigureSet set;
  std::optional<render::FigureRenderer> renderer;
  // A figure's PNG is encoded on a thread of its own while the next one is drawn (the particle
  // figures' OpenGL context stays on this thread): encoding costs about as much as drawing.
  std::future<void> encoding;
  // A data file of a line plot, read, with every cell of `columns` that is not a number said:
  // the plot leaves it out.
  auto plotted = [&](const std::filesystem::path& file, const std::vector<std::string>& columns,
                     const std::string& figure) {
    CsvTable table = readCsv(file);
    for (const std::string& cell : nonFiniteCells(table, columns)) {
      set.gaps.push_back(file.string() + " " + cell + "; left out of " + figure +
                         " (a gap in its line)");
    }
    return table;
  };
  // Each figure is drawn if its inputs exist, and listed as missing with the first absent one
  // otherwise; the names do not depend on what else exists.
  auto draw = [&](const std::string& name, const std::string& caption,
                  const std::vector<std::filesystem::path>& inputs, const auto& makeImage) {
    stopIfSignalled("figures up to " + name + " not drawn");
    for (const std::filesystem::path& input : inputs) {
      if (!std::filesystem::exists(runDir / input)) {
        set.missing.push_back(name + " (" + input.generic_string() + " is missing)");
        return;
      }
    }
    if (!renderer) {
      createOutputFolder(out);
      renderer.emplace();
    }
    render::Image image = makeImage();
    if (encoding.valid()) encoding.get();  // the last figure's PNG, which may throw
    encoding = std::async(std::launch::async, [image = std::move(image), file = out / name] {
      render::writePng(image, file, kDpi);
    });
    set.written.push_back({caption, std::filesystem::path("figures") / name});
  };
  const Case& mu0 = kCases[0];
  const std::string mu0Label = caseLabel(runDir / mu0.name, mu0);
  draw("fig02_falling_mu0.png",
       "Fig. 2: particles falling at t = 1 s of stage 1, " + mu0Label + ", coloured by speed",
       {"mu0/falling_t1.csv", "mu0/box.txt"}, [&] {
         return particleFigure(*renderer, runDir / mu0.name, "falling_t1.csv", "speed_m_per_s",
                               "Particles falling, t = 1 s of stage 1 (" + mu0Label + ")",
                               "speed [m/s]");
       });
  std::vector<std::pair<std::string, CsvTable>> settle;
  double threshold = 0;
  for (std::size_t k = 0; k < std::size(kCases); ++k) {
    const Case& c = kCases[k];
    const std::filesystem::path dir = runDir / c.name, rel = c.name;
    const std::string label = caseLabel(dir, c);
    const std::string n = std::to_string(3 + 3 * k), n4 = std::to_string(4 + 3 * k),
                      n5 = std::to_string(5 + 3 * k);
    draw("fig0" + n + "_settled_" + c.name + ".png",
         "Fig. " + n + ": the settled assembly, " + label + ", coloured by Σ|F_ij| [N]",
         {rel / "settled_particles.csv", rel / "box.txt"}, [&] {
           return particleFigure(*renderer, dir, "settled_particles.csv", "force_sum_N",
                                 "Settled assembly, end of stage 1 (" + label + ")", "Σ|F_ij| [N]");
         });
    const std::string forces = "fig0" + n4 + "_forces_" + c.name + ".png";
    draw(forces, "Fig. " + n4 + ": wall reactions and weight vs time, stage 2, " + label,
         {rel / "compaction_stress.csv"}, [&] {
           return forcesFigure(plotted(dir / "compaction_stress.csv", kForceColumns, forces),
                               label);
         });
    const std::string stresses = "fig0" + n5 + "_stresses_" + c.name + ".png";
    draw(stresses, "Fig. " + n5 + ": σ11, σ22, σ33 vs time, Eq. (1) thin, Eq. (2) bold, " + label,
         {rel / "compaction_stress.csv"}, [&] {
           return stressFigure(plotted(dir / "compaction_stress.csv", kStressColumns, stresses),
                               label);
         });
    if (std::filesystem::exists(dir / "settle_kinetic.csv")) {
      settle.emplace_back(
          label, plotted(dir / "settle_kinetic.csv", kSettleColumns, "settle_kinetic_energy.png"));
      if (std::filesystem::exists(dir / "settle_summary.txt")) {
        const auto kv = readKeyValues(dir / "settle_summary.txt");
        threshold = numberAt(kv, "threshold_J", dir / "settle_summary.txt");
      }
    }
  }
  if (settle.empty()) {
    set.missing.push_back("settle_kinetic_energy.png (no mu0/ or mu03/settle_kinetic.csv)");
  } else {
    draw("settle_kinetic_energy.png", "Kinetic energy during stage 1 (log scale), both cases", {},
         [&] { return settleFigure(settle, threshold); });
  }
  // The stress fields of the settled beds: the paper shows μ = 0.3; μ = 0 for comparison.
  for (const Case& c : {kCases[1], kCases[0]}) {
    const std::filesystem::path fields = runDir / c.name / "fields", rel = c.name + "/fields";
    const std::string label = caseLabel(runDir / c.name, c);
    const bool frictional = c.name == "mu03";
    const std::string suffix = frictional ? "" : "_mu0";
    const std::vector<std::filesystem::path> mid = {rel / "midsection.csv"};
    draw("fig09_sigma33" + suffix + ".png",
         "Fig. 9" + std::string(frictional ? "" : " (μ = 0 for comparison)") +
             ": σ33 on the midsection y = L/2 from representative spheres (Eq. 1), tricubic "
             "spline, " +
             label,
         mid, [&] {
           return sigma33Figure(readCsv(fields / "midsection.csv"), "s33_rep_Pa",
                                "σ₃₃ on the midsection, end of stage 1 (" + label + ")");
         });
    draw("fig10_trajectories" + suffix + ".png",
         "Fig. 10" + std::string(frictional ? "" : " (μ = 0 for comparison)") +
             ": trajectories of the most compressive principal stress σ1 on the midsection, " +
             label,
         {rel / "midsection.csv", rel / "trajectories.csv"}, [&] {
           return trajectoryFigure(readCsv(fields / "midsection.csv"),
                                   readCsv(fields / "trajectories.csv"),
                                   "Trajectories of σ₁, end of stage 1 (" + label + ")");
         });
    draw("fig09_sigma33_coarse_grained" + suffix + ".png",
         "Beyond the paper: σ33 on the midsection, coarse-grained (Lucy kernel, c = 0.1 m), " +
             label,
         mid, [&] {
           return sigma33Figure(readCsv(fields / "midsection.csv"), "s33_cg_Pa",
                                "σ₃₃ coarse-grained (c = 0.1 m), end of stage 1 (" + label + ")");
         });
    const std::string profile = "profile_sigma33" + suffix + ".png";
    draw(profile,
         "Beyond the paper: σ33 against height, centre line and cross-section mean, against " +
             std::string(frictional ? "Janssen's law" : "the hydrostatic load") + ", " + label,
         {rel / "profiles.csv"}, [&] {
           return profileFigure(
               plotted(fields / "profiles.csv", profileColumns(frictional), profile), label,
               frictional);
         });
  }
  // The sensitivity study's bed (report.md, "Sensitivity"): the μ = 0.3 case with a constant
  // k_t, Figs. 9 and 10 again. A run has it unless its μ = 0.3 case had no friction.
  const std::filesystem::path mu03 = runDir / kCases[1].name;
  const bool frictionless =
      std::filesystem::exists(mu03 / "case.txt") &&
      numberAt(readKeyValues(mu03 / "case.txt"), "friction", mu03 / "case.txt") == 0.0;
  if (!frictionless) {
    const std::string name = kCases[1].name + "_constant_kt";
    const std::filesystem::path dir = runDir / name, fields = dir / "fields",
                                rel = name + "/fields";
    std::string label = caseLabel(dir, kCases[1]) + ", constant k_t";
    if (std::filesystem::exists(dir / "case.txt")) {
      const auto kv = readKeyValues(dir / "case.txt");
      if (kv.count("tangential_stiffness_N_per_m")) {
        label += " = " +
                 format("%.0f", numberAt(kv, "tangential_stiffness_N_per_m", dir / "case.txt")) +
                 " N/m";
      }
    }
    draw("fig09_sigma33_constant_kt.png",
         "Fig. 9 with a constant tangential stiffness (sensitivity): σ33 on the midsection "
         "y = L/2 from representative spheres (Eq. 1), " +
             label,
         {rel / "midsection.csv"}, [&] {
           return sigma33Figure(readCsv(fields / "midsection.csv"), "s33_rep_Pa",
                                // Shorter than Fig. 9's own title: the label is longer.
                                "σ₃₃ at the end of stage 1 (" + label + ")");
         });
    draw("fig10_trajectories_constant_kt.png",
         "Fig. 10 with a constant tangential stiffness (sensitivity): trajectories of σ1 on the "
         "midsection, " +
             label,
         {rel / "midsection.csv", rel / "trajectories.csv"}, [&] {
           return trajectoryFigure(readCsv(fields / "midsection.csv"),
                                   readCsv(fields / "trajectories.csv"),
                                   "Trajectories of σ₁, end of stage 1 (" + label + ")");
         });
  }
  if (encoding.valid()) encoding.get();
  return set;
}

int figuresCommand(const std::filesystem::path& runDir) {
  return withErrorMapping([&] {
    catchStopSignals();
    if (!std::filesystem::is_directory(runDir)) {
      throw IoError(runDir.string() +
                    ": not a folder (give the --out folder of `granular run` or `granular paper`)");
    }
    const FigureSet set = drawPaperFigures(runDir);
    for (const std::string& gap : set.gaps) std::cerr << "warning: " << gap << "\n";
    if (set.written.empty()) {
      throw IoError(runDir.string() +
                    ": nothing to draw: neither the --out folder of `granular run` (it holds "
                    "summary.txt, written at the run's end, and timeseries.csv) nor that of "
                    "`granular paper` (it needs mu0/ and mu03/ with settled_particles.csv, "
                    "compaction_stress.csv and fields/)");
    }
    for (const FigureFile& f : set.written) {
      std::cout << "wrote " << (runDir / f.path).string() << "\n";
    }
    if (!set.missing.empty()) {
      std::string list;
      for (const std::string& m : set.missing) list += (list.empty() ? "" : "; ") + m;
      throw IoError(runDir.string() + ": drew " + std::to_string(set.written.size()) + " of " +
                    std::to_string(set.written.size() + set.missing.size()) +
                    " figures; not drawn: " + list);
    }
    return 0;
  });
}

}  // namespace granular::app
