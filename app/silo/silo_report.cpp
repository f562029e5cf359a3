/// siloReport and writeSiloTables (silo_report.hpp).
#include "silo_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "csv_output.hpp"
#include "granular/beverloo.hpp"
#include "granular/lateral_ratio.hpp"

namespace granular::app {

namespace {

std::string fmt(const char* format, double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, x);
  return buffer;
}

const char* met(bool ok) {
  return ok ? "**met**" : "**not met**";
}

/// The largest ratio of a discharge's wall pressure to the pressure at rest over the levels in
/// the bed, and its level's index; the switch peak where it stands out of the rest's scatter.
struct Switch {
  double ratio = 0;
  std::size_t level = 0;
  bool peak = false;
};
Switch switchOf(const SiloStudyResult& r, const SiloDischarge& d) {
  Switch s;
  for (std::size_t k = 0; k < r.levels.size() && k < d.wallPressure.size(); ++k) {
    const SiloLevel& level = r.levels[k];
    if (!level.inBed || !(level.wallPressure > 0)) continue;
    const double ratio = d.wallPressure[k] / level.wallPressure;
    if (ratio > s.ratio) {
      s.ratio = ratio;
      s.level = k;
      s.peak = d.wallPressure[k] > level.wallPressure + 2.0 * level.wallPressureStd;
    }
  }
  return s;
}

std::string floorWords(const SiloStudyResult& r) {
  if (!r.hasHopper) return "a flat floor";
  return "a conical hopper of half-angle " + fmt("%.1f", r.hopperHalfAngle * 180.0 / M_PI) +
         "° from the vertical (the transition at z = " + fmt("%.3f", r.transition) + " m)";
}

/// The hopper's wall: its normal pressure per band at rest and in each discharge's steady
/// window.
void hopperSection(std::ostringstream& out, const SiloStudyResult& r) {
  out << "## The hopper's wall\n\n"
      << "p_n: the hopper wall's normal pressure, per band, at rest (with its scatter over the "
         "samples) and in each discharge's steady window.\n\n"
      << "| z [m] | p_n at rest [Pa] | ± [Pa] |";
  for (const SiloDischarge& dis : r.discharges) {
    if (dis.flowed) out << " D₀ = " << fmt("%.3f", dis.orifice) << " m [Pa] |";
  }
  out << "\n|---|---|---|";
  for (const SiloDischarge& dis : r.discharges) {
    if (dis.flowed) out << "---|";
  }
  out << "\n";
  for (std::size_t k = 0; k < r.hopperBands.size(); ++k) {
    const HopperBand& b = r.hopperBands[k];
    out << "| " << fmt("%.3f", b.zLow) << "–" << fmt("%.3f", b.zHigh) << " | "
        << fmt("%.1f", b.wallPressure) << " | " << fmt("%.1f", b.wallPressureStd) << " |";
    for (const SiloDischarge& dis : r.discharges) {
      if (dis.flowed) out << " " << fmt("%.1f", dis.hopperPressure[k]) << " |";
    }
    out << "\n";
  }
  // The switch on the hopper's wall: the largest ratio of discharge to rest over its bands.
  for (const SiloDischarge& dis : r.discharges) {
    if (!dis.flowed) continue;
    double largest = 0.0;
    std::size_t at = 0;
    for (std::size_t k = 0; k < r.hopperBands.size(); ++k) {
      const double ratio = dis.hopperPressure[k] / r.hopperBands[k].wallPressure;
      if (ratio > largest) {
        largest = ratio;
        at = k;
      }
    }
    const HopperBand& b = r.hopperBands[at];
    out << "\nD₀ = " << fmt("%.3f", dis.orifice) << " m: p_n rises to " << fmt("%.2f", largest)
        << " times its value at rest at z = " << fmt("%.3f", 0.5 * (b.zLow + b.zHigh)) << " m"
        << (b.zHigh >= r.transition - 1e-12 ? " (the band under the transition)" : "") << ".";
  }
  out << "\n\n";
}

}  // namespace

std::string siloReport(const SiloStudyResult& r, const std::string& scene, double seconds,
                       const std::vector<std::string>& figures, const SiloTargets& t) {
  std::ostringstream out;
  const double d = r.particleDiameter;
  out << "# Silo study\n\n"
      << "Scene `" << scene << "`: a cylinder of radius " << fmt("%.4g", r.radius) << " m on "
      << floorWords(r) << ", filled by pouring; " << fmt("%.4g", r.bedMass)
      << " kg of spheres of mean diameter d = " << fmt("%.4g", d) << " m. Bulk density "
      << fmt("%.4g", r.bulkDensity) << " kg/m³ (the middle of the bed), surface at "
      << fmt("%.4g", r.surface) << " m (the bed's height at that density). Wall clock "
      << fmt("%.1f", seconds) << " s (the fill " << fmt("%.1f", r.fillSeconds) << " s).\n\n";

  out << "## At rest: the wall pressure and Janssen's law\n\n"
      << "Averaged over " << r.restSamples << " samples of the settled bed";
  if (r.wallLift > 0) {
    out << ", after the cylinder was lifted by " << fmt("%.3g", r.wallLift)
        << " m, slowly, so that the bed slid down along the whole wall and mobilised its "
           "friction at every height (as poured, the top of a bed carries almost none)";
  }
  out << ". Bands of the wall and slices of the section two "
         "diameters high. p_h: the wall's normal pressure; τ_w: its upward shear on the bed; σ_v: "
         "Eq. (1) over the slice; K = p_h/σ_v; μ_mob = τ_w/p_h. Levels marked * are in the bed "
         "(a band or more below the surface and above the floor or the hopper) and enter the "
         "fits.\n\n"
      << "| z [m] | depth [m] | p_h [Pa] | ± [Pa] | τ_w [Pa] | σ_v [Pa] | K [-] | μ_mob [-] | "
         "ρ_b [kg/m³] |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const SiloLevel& l : r.levels) {
    out << "| " << fmt("%.3f", l.zLow) << "–" << fmt("%.3f", l.zHigh) << (l.inBed ? " *" : "")
        << " | " << fmt("%.3f", l.depth) << " | " << fmt("%.1f", l.wallPressure) << " | "
        << fmt("%.1f", l.wallPressureStd) << " | " << fmt("%.1f", l.wallShear) << " | "
        << fmt("%.1f", l.verticalStress) << " | " << fmt("%.3f", l.lateralRatio) << " | "
        << fmt("%.3f", l.mobilisedFriction) << " | " << fmt("%.1f", l.bulkDensity) << " |\n";
  }
  const JanssenFit& j = r.janssen;
  const double agreement =
      r.lambdaMeasured > 0 ? std::abs(j.lambda - r.lambdaMeasured) / r.lambdaMeasured : HUGE_VAL;
  out << "\nJanssen's σ_v(h) = (γ R_h/λ)(1 − exp(−λ h/R_h)), R_h = D/4, γ = ρ_b g measured, λ = "
         "μ_w K fitted to σ_v over the "
      << j.pointsInRms << " levels in the bed:\n\n"
      << "| quantity | ours | target | |\n|---|---|---|---|\n"
      << "| λ = μ_w K fitted [-] | " << fmt("%.4f", j.lambda) << " | | |\n"
      << "| σ_v about the fitted curve, RMS [-] | " << fmt("%.2f %%", 100 * j.rmsRelativeResidual)
      << " | ≤ " << fmt("%.0f %%", 100 * t.janssenRms) << " | "
      << met(j.rmsRelativeResidual <= t.janssenRms) << " |\n"
      << "| λ measured, Σ τ_w / Σ σ_v [-] | " << fmt("%.4f", r.lambdaMeasured) << " | | |\n"
      << "| fitted against measured λ | " << fmt("%.1f %%", 100 * agreement) << " | ≤ "
      << fmt("%.0f %%", 100 * t.lambdaAgreement) << " | " << met(agreement <= t.lambdaAgreement)
      << " |\n"
      << "| K, mean over the bed [-] | " << fmt("%.3f", r.lateralRatio) << " | | |\n"
      << "| μ_mob, mean over the bed [-] | " << fmt("%.3f", r.mobilisedFriction) << " | | |\n"
      << "| asymptotic σ_v, γ R_h/λ [Pa] | " << fmt("%.1f", j.asymptoticStress) << " | | |\n"
      << "| with γ fitted too: λ, ρ_b = γ/g, RMS | " << fmt("%.4f", r.janssenBoth.lambda) << ", "
      << fmt("%.1f kg/m³", r.janssenBoth.gamma / r.gravity) << ", "
      << fmt("%.2f %%", 100 * r.janssenBoth.rmsRelativeResidual) << " | | |\n\n";
  if (j.lambdaAtBound) {
    out << "λ lies at the end of the range the fit searches: the profile is hydrostatic or "
           "steeper, and the wall carries no weight to speak of.\n\n";
  }
  if (r.lateralRatio > 0 && r.lateralRatio < 1.1) {
    const double phi = std::asin(1.0 - r.lateralRatio / 1.1) * 180.0 / M_PI;
    out << "EN 1991-4 takes K = 1.1 (1 − sin φ_i); our K = " << fmt("%.3f", r.lateralRatio)
        << " is its value for φ_i = " << fmt("%.1f", phi) << "°.";
    if (std::isfinite(r.internalFriction)) {
      out << " The flowing material's effective angle of internal friction, measured in the "
             "converging flow above each orifice (below), is "
          << fmt("%.1f", r.internalFriction * 180.0 / M_PI) << "°, for which EN 1991-4's K is "
          << fmt("%.3f", en1991LateralRatio(r.internalFriction)) << ", "
          << fmt("%+.0f %%",
                 100.0 * (en1991LateralRatio(r.internalFriction) / r.lateralRatio - 1.0))
          << " from ours.";
    }
    out << "\n\n";
  }

  out << "## Discharge and Beverloo's law\n\n"
      << "Each orifice opened on the same settled bed, for the same time; the steady rate W is "
         "the slope of the discharged mass over 20–80 % of what it discharged. φ_flow: the "
         "effective "
         "angle of internal friction, sin φ = (σ1 − σ3)/(σ1 + σ3) of Eq. (1) in a sphere of "
         "radius D₀/3 on the axis, D₀ above the orifice, the mean over the same window; ρ_flow: "
         "the bulk density in that sphere.\n\n"
      << "| D₀ [m] | D₀/d | W [kg/s] | ± [kg/s] | window [s] | Beverloo W [kg/s] | φ_flow [°] | "
         "ρ_flow [kg/m³] |\n"
      << "|---|---|---|---|---|---|---|---|\n";
  const double g = r.gravity;
  for (const SiloDischarge& dis : r.discharges) {
    out << "| " << fmt("%.4f", dis.orifice) << " | " << fmt("%.2f", dis.orifice / d) << " | ";
    if (!dis.flowed) {
      out << "did not flow steadily (it stopped, or too few samples) | | | | | |\n";
      continue;
    }
    out << fmt("%.4f", dis.steady.rate) << " | " << fmt("%.4f", dis.steady.standardError) << " | "
        << fmt("%.2f", dis.steady.t0) << "–" << fmt("%.2f", dis.steady.t1) << " | ";
    if (r.beverlooFitted) {
      out << fmt("%.4f",
                 beverlooRate(r.beverloo.c, r.beverloo.k, r.bulkDensity, g, dis.orifice, d));
    }
    out << " | " << fmt("%.1f", dis.internalFriction * 180.0 / M_PI) << " | "
        << fmt("%.1f", dis.flowDensity) << " |\n";
  }
  if (r.beverlooFitted) {
    const bool inRange = r.beverloo.c >= t.cMin && r.beverloo.c <= t.cMax;
    out << "\nW = C ρ_b √g (D₀ − k d)^(5/2) fitted over " << r.beverloo.points
        << " orifices: C = " << fmt("%.3f", r.beverloo.c) << ", k = " << fmt("%.3f", r.beverloo.k)
        << ", RMS " << fmt("%.1f %%", 100 * r.beverloo.rmsRelativeResidual) << ". ";
    // The same rates with the flowing material's density in the law: C scales by ρ_b/ρ_flow.
    double flowSum = 0.0;
    int flows = 0;
    for (const SiloDischarge& dis : r.discharges) {
      if (dis.flowed && std::isfinite(dis.flowDensity)) {
        flowSum += dis.flowDensity;
        ++flows;
      }
    }
    const double rhoFlow = flows > 0 ? flowSum / flows : std::nan("");
    const double cFlow = r.beverloo.c * r.bulkDensity / rhoFlow;
    if (r.hasHopper) {
      // Rose and Tanaka's φ_d is the angle of a flat floor's stagnant zone to the horizontal,
      // which this run does not have: the factor is given over the range such zones take.
      const auto factor = [&r](double phiD) {
        return std::pow(std::tan(r.hopperHalfAngle) * std::tan(phiD), -0.35);
      };
      out << "The literature's C, " << fmt("%.2f", t.cMin) << "–" << fmt("%.2f", t.cMax)
          << ", is a flat floor's; a hopper's converging wall feeds its orifice faster, by Rose "
             "and Tanaka's factor F = (tan θ_h tan φ_d)^−0.35 (θ_h < 90° − φ_d), φ_d the angle "
             "of a flat floor's stagnant zone to the horizontal: with θ_h = "
          << fmt("%.1f", r.hopperHalfAngle * 180.0 / M_PI)
          << "°, F = " << fmt("%.2f", factor(M_PI / 4)) << " for φ_d = 45° to "
          << fmt("%.2f", factor(M_PI / 6)) << " for φ_d = 30°. The flat silo's C times F is "
          << "what this C is to be compared with.\n\n";
    } else {
      out << "C in the literature's " << fmt("%.2f", t.cMin) << "–" << fmt("%.2f", t.cMax) << ": "
          << met(inRange) << ".";
      if (std::isfinite(cFlow)) {
        out << " With the flowing material's density in place of ρ_b, ρ_flow = "
            << fmt("%.1f", rhoFlow) << " kg/m³ over the orifices ("
            << fmt("%.0f %%", 100.0 * (1.0 - rhoFlow / r.bulkDensity))
            << " below the bed's at rest): C = " << fmt("%.3f", cFlow) << ", "
            << (cFlow >= t.cMin && cFlow <= t.cMax ? "in" : "outside") << " that range.";
      }
      out << "\n\n";
    }
  } else {
    out << "\nBeverloo's law not fitted: fewer than two orifices flowed steadily.\n\n";
  }
  out << "## The switch: wall pressure during discharge\n\n"
      << "| D₀ [m] | largest p_h(discharge)/p_h(rest) | at z [m] | a peak beyond the rest's "
         "scatter |\n|---|---|---|---|\n";
  for (const SiloDischarge& dis : r.discharges) {
    if (!dis.flowed) continue;
    const Switch s = switchOf(r, dis);
    const SiloLevel& l = r.levels[s.level];
    out << "| " << fmt("%.4f", dis.orifice) << " | " << fmt("%.2f", s.ratio) << " | "
        << fmt("%.3f", 0.5 * (l.zLow + l.zHigh)) << " | " << (s.peak ? "yes" : "no") << " |\n";
  }
  out << "\n";
  if (r.hasHopper) hopperSection(out, r);
  const auto has = [&figures](const std::string& name) {
    return std::find(figures.begin(), figures.end(), name) != figures.end();
  };
  if (has("cutaway.png") || has("midsection_stress.png")) {
    out << "## The settled bed in section\n\n"
        << "`cutaway.png`: the particles behind the plane y = 0 seen from −y, coloured by "
           "Σ_j |F_ij|, the force chains on the cut face. `midsection_stress.png`: −σ33 "
           "coarse-grained on the midsection y = 0 (compression positive), with the trajectories "
           "of σ1, the major principal stress.\n\n";
  }
  out << "Figures:";
  for (std::size_t k = 0; k < figures.size(); ++k) {
    out << (k ? ", `" : " `") << figures[k] << '`';
  }
  out << ". Tables: `levels.csv`, `discharge.csv`" << (r.hasHopper ? ", `hopper.csv`" : "")
      << ".\n";
  return out.str();
}

void writeSiloTables(const SiloStudyResult& r, const std::filesystem::path& dir) {
  std::ostringstream levels;
  levels << "z_low_m,z_high_m,depth_m,in_bed,wall_pressure_Pa,wall_pressure_std_Pa,"
            "wall_shear_Pa,vertical_stress_Pa,lateral_ratio,mobilised_friction,"
            "bulk_density_kg_m3";
  for (std::size_t k = 0; k < r.discharges.size(); ++k) {
    levels << ",wall_pressure_discharge" << (k + 1) << "_Pa";
  }
  levels << "\n";
  for (std::size_t i = 0; i < r.levels.size(); ++i) {
    const SiloLevel& l = r.levels[i];
    levels << csvNumber(l.zLow) << ',' << csvNumber(l.zHigh) << ',' << csvNumber(l.depth) << ','
           << (l.inBed ? 1 : 0) << ',' << csvNumber(l.wallPressure) << ','
           << csvNumber(l.wallPressureStd) << ',' << csvNumber(l.wallShear) << ','
           << csvNumber(l.verticalStress) << ',' << csvNumber(l.lateralRatio) << ','
           << csvNumber(l.mobilisedFriction) << ',' << csvNumber(l.bulkDensity);
    for (const SiloDischarge& d : r.discharges) {
      levels << ',' << csvNumber(i < d.wallPressure.size() ? d.wallPressure[i] : std::nan(""));
    }
    levels << "\n";
  }
  writeTextFile(dir / "levels.csv", levels.str());
  std::ostringstream discharge;
  discharge << "orifice_m,time_s,discharged_kg\n";
  for (const SiloDischarge& d : r.discharges) {
    for (std::size_t k = 0; k < d.time.size(); ++k) {
      discharge << csvNumber(d.orifice) << ',' << csvNumber(d.time[k]) << ','
                << csvNumber(d.discharged[k]) << "\n";
    }
  }
  writeTextFile(dir / "discharge.csv", discharge.str());
  if (!r.hasHopper) return;
  std::ostringstream hopper;
  hopper << "z_low_m,z_high_m,wall_pressure_Pa,wall_pressure_std_Pa";
  for (std::size_t k = 0; k < r.discharges.size(); ++k) {
    hopper << ",wall_pressure_discharge" << (k + 1) << "_Pa";
  }
  hopper << "\n";
  for (std::size_t i = 0; i < r.hopperBands.size(); ++i) {
    const HopperBand& b = r.hopperBands[i];
    hopper << csvNumber(b.zLow) << ',' << csvNumber(b.zHigh) << ',' << csvNumber(b.wallPressure)
           << ',' << csvNumber(b.wallPressureStd);
    for (const SiloDischarge& d : r.discharges) {
      hopper << ',' << csvNumber(i < d.hopperPressure.size() ? d.hopperPressure[i] : std::nan(""));
    }
    hopper << "\n";
  }
  writeTextFile(dir / "hopper.csv", hopper.str());
}

}  // namespace granular::app
