/// The sensitivity study's numbers, CSV and report section (paper_sensitivity.hpp).
#include "paper_sensitivity.hpp"

#include <cmath>

#include "csv_output.hpp"
#include "paper_derived.hpp"
#include "run_header.hpp"

namespace granular::app {
namespace {

/// Mean and sample standard deviation.
struct Spread {
  double mean = 0, sd = 0;
  std::size_t n = 0;
  double standardError() const { return n > 0 ? sd / std::sqrt(double(n)) : 0.0; }
};

Spread spread(const std::vector<double>& x) {
  Spread s;
  s.n = x.size();
  for (double v : x) s.mean += v / double(x.size());
  for (double v : x) s.sd += (v - s.mean) * (v - s.mean);
  s.sd = x.size() > 1 ? std::sqrt(s.sd / double(x.size() - 1)) : 0.0;
  return s;
}

std::string percentSpread(const Spread& s) {
  return format("%.1f", 100 * s.mean) + " ± " + format("%.1f", 100 * s.sd) + " %";
}

/// Whether two laws' means differ by more than three standard errors of the difference.
struct Comparison {
  double difference = 0, standardError = 0;
  bool separated() const { return std::abs(difference) > 3 * standardError; }
};

Comparison compare(const Spread& constant, const Spread& mindlin) {
  Comparison c;
  c.difference = constant.mean - mindlin.mean;
  c.standardError = std::hypot(constant.standardError(), mindlin.standardError());
  return c;
}

}  // namespace

void sensitivitySection(std::ostringstream& out, const std::vector<CaseOutcome>& cases,
                        const SensitivityOutcome& s) {
  const CaseOutcome& mindlin = cases.back();
  out << "\n## Sensitivity: a constant tangential stiffness\n\n";
  if (!s.constant) {
    out << "Not run: " << s.skipped << ".\n";
    return;
  }
  const CaseOutcome& constant = *s.constant;
  const double paperShare = mindlin.reference->sideWallShare;
  out << "The paper's tangential spring stiffens with the overlap, k_t = (8/3)G/(2−ν)·√(R_ij h) "
         "(Mindlin's, our default). Here the μ = "
      << format("%g", mindlin.friction)
      << " case is run again with one k_t for every contact (`material.tangential_law = "
         "\"constant\"`, LAMMPS's `tangential linear_history`): the Mindlin value at the mean "
         "reduced radius and mean overlap of the settled Mindlin bed, k_t = (8/3)G/(2−ν)·√(R̄ h̄) = "
      << format("%.0f", s.coefficient) << " Pa × √(" << format("%.4f", s.bed.meanRadius) << " m × "
      << format("%.3f", 1000 * s.bed.meanOverlap) << " mm) = " << format("%.0f", s.stiffness)
      << " N/m, the means taken over its " << s.bed.count
      << " contacts (each particle pair once, each particle–wall contact once with R_ij = R_i). "
         "At that bed's side-wall contacts Mindlin's k_t averages "
      << format("%.0f", s.bed.sideWallMindlin) << " N/m, "
      << (s.bed.sideWallMindlin > s.stiffness ? "more" : "less")
      << " than the constant. The scene, its seed (" << mindlin.seed
      << ") and so the initial state are the same; only the law differs. The μ = 0 case is not "
         "run again: without friction the tangential force is zero whatever k_t, so its result "
         "would be the μ = 0 case's.\n\n";

  const LawNumbers m = lawNumbers(mindlin), c = lawNumbers(constant);
  out << "| seed " << mindlin.seed
      << " | Mindlin k_t ∝ √h (the paper's law) | constant k_t | paper |\n|---|---|---|---|\n";
  out << "| side walls' share of the weight, end of settling | " << pct(m.shareSettled, "%.1f %%")
      << " | " << pct(c.shareSettled, "%.1f %%") << " | - |\n";
  out << "| side walls' share of the weight, t = 1 s | " << pct(m.shareEnd, "%.1f %%") << " | "
      << pct(c.shareEnd, "%.1f %%") << " | ≈ " << pct(paperShare, "%.0f %%") << " (Fig. 7) |\n";
  out << "| σ33 convexity at mid-depth, end of settling | " << pct(m.convexity, "%+.1f %%") << " | "
      << pct(c.convexity, "%+.1f %%") << " | convex (Fig. 9) |\n";
  out << "| σ1 tilt from vertical near the walls, mid-depth | " << format("%.0f", m.tiltWalls)
      << "° | " << format("%.0f", c.tiltWalls) << "° | bending towards the walls (Fig. 10) |\n";
  out << "| side walls' mobilised friction τ_w/σ_h, end of settling | "
      << pct(m.wallFriction, "%.1f %%") << " | " << pct(c.wallFriction, "%.1f %%") << " | - |\n";
  out << "| settled height | " << format("%.4f", m.settledHeight) << " m | "
      << format("%.4f", c.settledHeight) << " m | "
      << format("%.3f", mindlin.reference->settledHeight) << " m |\n";
  const auto& paper = mindlin.reference->stress;
  out << "| σ11, σ22, σ33 at t = 1 s (Eq. 1) | " << format("%.0f", m.sigma[0]) << ", "
      << format("%.0f", m.sigma[1]) << ", " << format("%.0f", m.sigma[2]) << " Pa | "
      << format("%.0f", c.sigma[0]) << ", " << format("%.0f", c.sigma[1]) << ", "
      << format("%.0f", c.sigma[2]) << " Pa | " << format("%.0f", paper[0][0]) << ", "
      << format("%.0f", paper[1][1]) << ", " << format("%.0f", paper[2][2]) << " Pa |\n";
  out << "\nThe side walls' share is their upward reaction over the weight: at the end of "
         "settling the instantaneous value on the settled bed (stage 2's first sample), at t = 1 s "
         "the mean over the last "
      << format("%g", kEndWindow)
      << " s as above. The convexity is that of Fig. 9's map at mid-depth, |σ33| at the centre "
         "over the mean of its values at the two walls, minus 1: positive for a profile peaked "
         "at the centre. One bed's convexity carries its packing's fluctuations"
      << (cases.front().friction == 0
              ? " (the frictionless bed, with no reason to be convex, shows " +
                    pct(lawNumbers(cases.front()).convexity, "%+.0f %%") + ")"
              : std::string())
      << "; the figures `fig09_sigma33_constant_kt.png` and "
         "`fig10_trajectories_constant_kt.png` under Figures show the constant law's map and σ1 "
         "trajectories.\n\n";

  if (s.mindlinSeeds.size() < 2) {
    out << "One bed cannot say whether a difference between the laws exceeds the scatter from "
           "one random packing to the next. `granular paper --sensitivity` runs both laws from "
        << s.defaultSeeds << " initial states (the particles' grid seed " << mindlin.seed << " to "
        << mindlin.seed + std::uint64_t(s.defaultSeeds - 1)
        << ", the same k_t; about 7 s a bed on 2 cores) and gives their means ± standard "
           "deviations here.\n\nIn this one bed the constant k_t puts "
        << pct(c.shareSettled, "%.1f %%") << " of the weight on the side walls at the end of "
        << "settling and " << pct(c.shareEnd, "%.1f %%") << " at t = 1 s, Mindlin's "
        << pct(m.shareSettled, "%.1f %%") << " and " << pct(m.shareEnd, "%.1f %%")
        << "; the paper reports ≈ " << pct(paperShare, "%.0f %%") << ".\n";
    return;
  }

  std::vector<LawNumbers> ms, cs;
  for (const CaseOutcome& o : s.mindlinSeeds) ms.push_back(lawNumbers(o));
  for (const CaseOutcome& o : s.constantSeeds) cs.push_back(lawNumbers(o));
  auto over = [](const std::vector<LawNumbers>& v, double LawNumbers::*field) {
    std::vector<double> x;
    for (const LawNumbers& n : v) x.push_back(n.*field);
    return spread(x);
  };
  const std::size_t n = ms.size();
  out << "### Over " << n << " seeds\n\nThe same two runs from " << n
      << " initial states (the particles' grid seed " << s.mindlinSeeds.front().seed << " to "
      << s.mindlinSeeds.back().seed
      << ", each law from the same ones, the same k_t): mean ± standard deviation over the beds, "
         "and the difference of the means ± its standard error "
         "(`sensitivity/seeds.csv` has every bed).\n\n"
      << "| | Mindlin | constant k_t | constant − Mindlin (percentage points) |\n"
         "|---|---|---|---|\n";
  struct Row {
    const char* name;
    double LawNumbers::*field;
  };
  const Row rows[] = {
      {"side walls' share, end of settling", &LawNumbers::shareSettled},
      {"side walls' share, t = 1 s", &LawNumbers::shareEnd},
      {"σ33 convexity at mid-depth", &LawNumbers::convexity},
      {"side walls' mobilised friction τ_w/σ_h", &LawNumbers::wallFriction},
  };
  for (const Row& r : rows) {
    const Spread a = over(ms, r.field), b = over(cs, r.field);
    const Comparison d = compare(b, a);
    out << "| " << r.name << " | " << percentSpread(a) << " | " << percentSpread(b) << " | "
        << format("%+.1f", 100 * d.difference) << " ± " << format("%.1f", 100 * d.standardError)
        << " %" << (d.separated() ? " (beyond 3 standard errors)" : "") << " |\n";
  }

  // What the numbers say, only as far as they go.
  const Spread settledM = over(ms, &LawNumbers::shareSettled),
               settledC = over(cs, &LawNumbers::shareSettled);
  const Spread endM = over(ms, &LawNumbers::shareEnd), endC = over(cs, &LawNumbers::shareEnd);
  const Spread convexM = over(ms, &LawNumbers::convexity),
               convexC = over(cs, &LawNumbers::convexity);
  const Comparison settled = compare(settledC, settledM), end = compare(endC, endM);
  auto closer = [&](const Spread& a, const Spread& b) {  // the law nearer the paper's share
    return std::abs(b.mean - paperShare) < std::abs(a.mean - paperShare) ? "the constant k_t"
                                                                         : "Mindlin's k_t";
  };
  auto convex = [](const Spread& x) { return x.mean > 2 * x.standardError(); };
  out << "\n**What this says.** ";
  if (settled.separated()) {
    out << "At the end of settling the laws differ beyond the scatter of the packings: the "
           "constant k_t leaves "
        << percentSpread(settledC) << " of the weight on the side walls, Mindlin's "
        << percentSpread(settledM) << ", and " << closer(settledM, settledC)
        << " is the nearer to the paper's ≈ " << pct(paperShare, "%.0f %%") << ". ";
  } else {
    out << "At the end of settling the laws do not differ beyond the scatter of the packings ("
        << percentSpread(settledC) << " against " << percentSpread(settledM) << "). ";
  }
  if (end.separated()) {
    out << "At t = 1 s they still differ (" << percentSpread(endC) << " against "
        << percentSpread(endM) << "); " << closer(endM, endC) << " is the nearer to the paper. ";
  } else {
    out << "At t = 1 s, once stage 2 has pushed the bed down past the walls, they no longer "
           "differ beyond the scatter ("
        << percentSpread(endC) << " against " << percentSpread(endM) << "). ";
  }
  out << "The σ33 convexity at mid-depth is " << percentSpread(convexC) << " with the constant k_t"
      << (convex(convexC) ? " (convex beyond twice its standard error)"
                          : " (not distinguishable "
                            "from flat)")
      << " and " << percentSpread(convexM) << " with Mindlin's"
      << (convex(convexM) ? " (convex beyond twice its standard error)"
                          : " (not distinguishable "
                            "from flat)")
      << ".\n\n";
  const bool constantNearer =
      std::abs(settledC.mean - paperShare) < std::abs(settledM.mean - paperShare);
  if (settled.separated() && constantNearer) {
    out << "So the paper's ≈ " << pct(paperShare, "%.0f %%")
        << " of the weight on the walls most likely comes from a tangential spring that does "
           "not soften at small overlaps, as a constant k_t: with the same μ, our Mindlin spring "
           "puts markedly less weight on the walls by the end of settling";
    out << (convex(convexC) && !convex(convexM)
                ? ", and only the constant k_t gives the paper's convex σ33."
                : (convex(convexC) ? "; the convex σ33 appears with both laws."
                                   : "; the convex σ33 of the paper's Fig. 9 is not reproduced "
                                     "beyond the scatter by either law, so these beds cannot "
                                     "say where it came from."))
        << "\n";
  } else {
    out << "So these beds do not point to the tangential law as the origin of the paper's ≈ "
        << pct(paperShare, "%.0f %%") << " and its convex σ33.\n";
  }
}

LawNumbers lawNumbers(const CaseOutcome& c) {
  LawNumbers n;
  const BoxStress& settled = c.result.samples.front().box;
  n.shareSettled = settled.sideVerticalForce / settled.weight;
  const Derived d = derive(c);
  n.shareEnd = d.sideShare;
  auto field = [&](const char* key) {
    const auto it = c.fields.find(key);
    return it == c.fields.end() ? std::nan("") : it->second;
  };
  n.convexity = field("sigma33_mid_centre_Pa") / field("sigma33_mid_walls_Pa") - 1.0;
  n.tiltWalls = field("sigma1_tilt_walls_deg");
  n.wallFriction = field("wall_friction_mobilised");
  n.settledHeight = c.result.settledHeight;
  for (int i = 0; i < 3; ++i) n.sigma[i] = d.end.eq1(i, i);
  return n;
}

std::string sensitivityCsv(const SensitivityOutcome& s) {
  std::ostringstream out;
  out << "seed,tangential_law,tangential_stiffness_N_per_m,settled_height_m,"
         "side_share_end_of_settling,side_share_t1,sigma33_convexity_mid,"
         "side_wall_friction_mobilised\n";
  for (const auto* runs : {&s.mindlinSeeds, &s.constantSeeds}) {
    for (const CaseOutcome& c : *runs) {
      const LawNumbers n = lawNumbers(c);
      out << c.seed << ',' << (c.constantStiffness > 0 ? "constant" : "mindlin") << ','
          << csvNumber(c.constantStiffness) << ',' << csvNumber(n.settledHeight) << ','
          << csvNumber(n.shareSettled) << ',' << csvNumber(n.shareEnd) << ','
          << csvNumber(n.convexity) << ',' << csvNumber(n.wallFriction) << '\n';
    }
  }
  return out.str();
}

}  // namespace granular::app
