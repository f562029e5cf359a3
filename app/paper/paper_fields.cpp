/// Stress fields of the settled bed (paper_fields.hpp). Sections: 1. geometry; 2. the paper's
/// representative spheres and trajectories; 3. coarse graining and its balance; 4. profiles,
/// wall stresses and Janssen; 5. files.
#include "paper_fields.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <sstream>

#include "csv_output.hpp"
#include "granular/coarse_grain.hpp"
#include "granular/geometry.hpp"
#include "granular/principal.hpp"
#include "granular/spline.hpp"
#include "granular/stress_field.hpp"
#include "run_header.hpp"
#include "vtk_output.hpp"

namespace granular::app {
namespace {

// ---- 1. Geometry --------------------------------------------------------------------------

struct Box {
  Vec3 lo, hi;  ///< side walls and floor; the top at the highest particle surface [m]
  double side() const { return hi.x() - lo.x(); }
  double height() const { return hi.z() - lo.z(); }
};

Box settledBox(const Simulation& sim) {
  auto wall = [&](const char* name) { return sim.walls()[sim.findWall(name)].point; };
  Box b{Vec3(wall("x-").x(), wall("y-").y(), wall("bottom").z()),
        Vec3(wall("x+").x(), wall("y+").y(), wall("bottom").z())};
  const Particles& p = sim.particles();
  for (std::size_t i = 0; i < p.size(); ++i) {
    b.hi.z() = std::max(b.hi.z(), p.position[i].z() + p.radius[i]);
  }
  return b;
}

/// Spacing of the representative spheres and the coarse-graining width: about three particle
/// diameters, enough particles per sphere (~20) for a stress, fine enough to see the profile.
constexpr double kSphereSpacing = 0.1;  // [m]
constexpr double kWidth = 0.1;          // Lucy kernel support radius c [m]
constexpr double kRadiusFactor = 2.0;
constexpr double kWidths[] = {0.05, 0.1, 0.15};

// ---- 4. Wall stresses (used by the Janssen fit) -------------------------------------------

/// Side-wall normal stress σ_h and upward shear τ_w (on the material) in height bins [Pa].
struct WallBins {
  std::vector<double> z, normal, shear;
};

WallBins sideWallStress(const Simulation& sim, const Box& box, int bins) {
  WallBins w;
  w.normal.assign(bins, 0.0);
  w.shear.assign(bins, 0.0);
  const double dz = box.height() / bins;
  std::vector<bool> side(sim.walls().size(), false);
  for (const char* name : {"x-", "x+", "y-", "y+"}) side[sim.findWall(name)] = true;
  sim.forEachContact([&](const ContactView& c) {
    if (!c.isWall() || !side[c.wall()]) return;
    const Wall& wall = sim.walls()[c.wall()];
    const int k = std::clamp(static_cast<int>((c.point.z() - box.lo.z()) / dz), 0, bins - 1);
    w.normal[k] += c.force.dot(wall.normal);  // the wall pushes the material inwards
    w.shear[k] += c.force.z();
  });
  const double area = 4.0 * box.side() * dz;  // the four walls' strip
  for (int k = 0; k < bins; ++k) {
    w.z.push_back(box.lo.z() + (k + 0.5) * dz);
    w.normal[k] /= area;
    w.shear[k] /= area;
  }
  return w;
}

std::string num(double x) {
  return csvNumber(x);
}

/// f(n) for the points n = 0 … count − 1, on OpenMP's threads, each into its own slot: the
/// results in the points' order, the same bits on any thread count (the points are
/// independent, a coarse-grained field or balance each).
template <class F>
auto atEachPoint(int count, F&& f) {
  std::vector<decltype(f(0))> out(static_cast<std::size_t>(count));
#pragma omp parallel for schedule(dynamic)
  for (int n = 0; n < count; ++n) out[std::size_t(n)] = f(n);
  return out;
}

}  // namespace

std::map<std::string, double> writeStressFields(const Simulation& sim,
                                                const std::filesystem::path& caseDir) {
  const std::filesystem::path dir = caseDir / "fields";
  createOutputFolder(dir);
  const Box box = settledBox(sim);
  const double L = box.side(), H = box.height(), yMid = 0.5 * (box.lo.y() + box.hi.y());
  std::map<std::string, double> summary;
  summary["box_side_m"] = L;
  summary["bed_height_m"] = H;

  // ---- 2. Representative spheres (the paper's method) -------------------------------------
  const std::array<int, 3> cells = {std::max(1, static_cast<int>(std::lround(L / kSphereSpacing))),
                                    std::max(1, static_cast<int>(std::lround(L / kSphereSpacing))),
                                    std::max(1, static_cast<int>(std::lround(H / kSphereSpacing)))};
  const Vec3 size = box.hi - box.lo;
  const double spacing = std::max({size.x() / cells[0], size.y() / cells[1], size.z() / cells[2]});
  // Twice the smallest radius whose spheres cover the whole box (half the cell diagonal): with
  // ~13 particles a sphere the field is noise; ~100 (this) resolve the trend of Figs. 9 and 10.
  const double radius = kRadiusFactor * 0.5 * std::sqrt(3.0) * spacing;
  const RepresentativeStress rep = representativeSphereStress(sim, box.lo, box.hi, cells, radius);
  summary["spheres"] = double(rep.stress.size());
  summary["sphere_radius_m"] = radius;
  double members = 0;
  for (int m : rep.members) members += m;
  summary["mean_members"] = members / rep.members.size();

  const int nx = 49, nz = std::max(2, static_cast<int>(std::lround(48 * H / L)) + 1);
  const PlaneField plane =
      interpolateOnPlane(rep, yMid, box.lo.x(), box.hi.x(), box.lo.z(), box.hi.z(), nx, nz);
  auto planeAt = [&](int i, int k) -> const Mat3& { return plane.stress[std::size_t(k) * nx + i]; };

  // σ1 trajectories, started across the bed just below its surface and traced downwards, as the
  // weight travels; they stop at the floor or at a nearly isotropic point (direction undefined).
  std::vector<Vec3> starts;
  for (double depth : {0.05, 0.5}) {  // a second row from mid-depth fills the lower half
    for (int s = 1; s <= 11; ++s) {
      starts.emplace_back(box.lo.x() + s * L / 12.0, yMid, box.hi.z() - depth * H);
    }
  }
  const auto lines = principalTrajectories(plane, starts, L / 200.0, -Vec3::UnitZ(), 0.05);

  // Convexity at mid-depth (the paper: peak at the centre, lower at the walls) and the tilt of
  // σ1 from the vertical at the centre and near the walls.
  const int kMid = nz / 2;
  const double centre = planeAt(nx / 2, kMid)(2, 2);
  const double walls = 0.5 * (planeAt(0, kMid)(2, 2) + planeAt(nx - 1, kMid)(2, 2));
  summary["sigma33_mid_centre_Pa"] = centre;
  summary["sigma33_mid_walls_Pa"] = walls;
  auto tiltDegrees = [&](int i) {
    const auto d = inPlaneSigma1(planeAt(i, kMid), 0.0);
    return d ? std::atan2(std::abs(d->x()), std::abs(d->z())) * 180.0 / std::numbers::pi : 0.0;
  };
  summary["sigma1_tilt_centre_deg"] = tiltDegrees(nx / 2);
  summary["sigma1_tilt_walls_deg"] = 0.5 * (tiltDegrees(2) + tiltDegrees(nx - 3));

  // ---- 3. Coarse graining and the momentum balance -----------------------------------------
  // The fields at the points on the threads, gathered in the points' order (atEachPoint): the
  // files are the same bytes on any count.
  const CoarseGrainer cg(sim, kWidth);
  std::vector<double> cgPlane(std::size_t(nx) * nz), cgDensity(std::size_t(nx) * nz);
  std::vector<double> cgTensor, repTensor;
  const std::vector<CoarseGrainedFields> planeFields =
      atEachPoint(nx * nz, [&](int n) { return cg.at(plane.point(n % nx, n / nx)); });
  for (int k = 0; k < nz; ++k) {
    for (int i = 0; i < nx; ++i) {
      const CoarseGrainedFields& f = planeFields[std::size_t(k) * nx + i];
      cgPlane[std::size_t(k) * nx + i] = f.stress()(2, 2);
      cgDensity[std::size_t(k) * nx + i] = f.density;
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
          cgTensor.push_back(f.stress()(a, b));
          repTensor.push_back(planeAt(i, k)(a, b));
        }
      }
    }
  }
  // Residual of ∇·σ + ρg + t on a coarser grid reaching the walls and the floor; where the bed
  // is thin (the free surface) ρ|g| is no scale, so only points with ρ above half the bulk's.
  double bulk = 0;
  for (double rho : cgDensity) bulk = std::max(bulk, rho);
  double worst = 0, sumSq = 0, closure = 0, motion = 0;
  int points = 0;
  const double h = kWidth / 400.0;  // central differences: error ∝ h², round-off ∝ 1/h
  struct Balance {
    bool counted = false;
    double residual = 0, closure = 0, motion = 0;  ///< each over ρ|g|
  };
  constexpr int kBalanceX = 11, kBalanceZ = 19;
  const std::vector<Balance> balance = atEachPoint(kBalanceX * kBalanceZ, [&](int n) {
    const int i = n % kBalanceX, k = n / kBalanceX;
    const Vec3 r(box.lo.x() + 0.01 + i * (L - 0.02) / 10.0, yMid,
                 box.lo.z() + 0.01 + k * (H - 0.01 - kWidth) / 18.0);
    const double rho = cg.at(r).density;
    if (rho < 0.5 * bulk) return Balance{};
    const double scale = rho * cg.gravity().norm();
    return Balance{true, cg.balanceResidual(r, h).norm() / scale,
                   cg.closureError(r, h).norm() / scale, cg.unbalancedForce(r).norm() / scale};
  });
  for (const Balance& b : balance) {
    if (!b.counted) continue;
    worst = std::max(worst, b.residual);
    closure = std::max(closure, b.closure);
    motion = std::max(motion, b.motion);
    sumSq += b.residual * b.residual;
    ++points;
  }
  summary["balance_residual_max"] = worst;
  summary["balance_residual_rms"] = points ? std::sqrt(sumSq / points) : 0.0;
  summary["balance_points"] = points;
  summary["closure_error_max"] = closure;
  summary["unbalanced_force_max"] = motion;

  // ---- 4. Profiles, wall stresses and Janssen ----------------------------------------------
  double mass = 0;
  for (double m : sim.particles().mass) mass += m;
  const double g = sim.config().gravity.norm();
  const double bulkDensity = mass / (L * L * H);
  summary["bulk_density_kg_m3"] = bulkDensity;
  const WallBins wallStress = sideWallStress(sim, box, 12);
  // The cross-section mean of σ33 at a height, from the coarse-grained field.
  auto sectionMean = [&](double z) {
    const std::vector<double> at = atEachPoint(81, [&](int n) {
      const int i = n % 9, j = n / 9;
      return cg.at(Vec3(box.lo.x() + (i + 0.5) * L / 9, box.lo.y() + (j + 0.5) * L / 9, z))
          .stress()(2, 2);
    });
    double sum = 0;
    for (double value : at) sum += value;  // in the points' order
    return sum / 81.0;
  };
  // Janssen: fit μ_w K = τ_w/σ_v and K = σ_h/σ_v over the middle of the bed (away from the
  // floor and the surface), then σ_v(d) = ρ_b g λ (1 − e^{−d/λ}) with λ = D/(4 μ_w K).
  double shear = 0, normal = 0, vertical = 0;
  for (std::size_t k = 0; k < wallStress.z.size(); ++k) {
    const double depthFraction = (box.hi.z() - wallStress.z[k]) / H;
    if (depthFraction < 0.2 || depthFraction > 0.8) continue;
    shear += wallStress.shear[k];
    normal += wallStress.normal[k];
    vertical += -sectionMean(wallStress.z[k]);
  }
  const double muK = vertical > 0 ? shear / vertical : 0.0;
  summary["janssen_K"] = vertical > 0 ? normal / vertical : 0.0;
  summary["wall_friction_mobilised"] = normal > 0 ? shear / normal : 0.0;
  summary["janssen_muK"] = muK;
  const double lambda = muK > 0 ? L / (4.0 * muK) : 0.0;
  summary["janssen_lambda_m"] = lambda;
  // The weight above a horizontal plane, each particle counted by the share of its volume above
  // it: the exact hydrostatic load of a frictionless static bed, whatever its density profile.
  const Particles& particles = sim.particles();
  auto weightAbove = [&](double z) {
    double w = 0;
    for (std::size_t i = 0; i < particles.size(); ++i) {
      const double r = particles.radius[i], top = particles.position[i].z() + r;
      if (z <= top - 2 * r) {
        w += particles.mass[i];
      } else if (z < top) {
        w += particles.mass[i] * sphereCapVolume(r, top - z) /
             (4.0 / 3.0 * std::numbers::pi * r * r * r);
      }
    }
    return g * w;
  };
  std::ostringstream profiles;
  profiles << "z_m,depth_m,s33_rep_centre_Pa";
  for (double w : kWidths) profiles << ",s33_cg_centre_c" << num(w) << "_Pa";
  profiles << ",s33_cg_section_mean_Pa,janssen_Pa,hydrostatic_Pa\n";
  // Janssen's slice balance dσ_v/dd = ρ(d) g − (4 μ_w K / D) σ_v integrated down from the
  // surface with the measured load increments, exact for a load spread evenly over each step.
  const double a = 4.0 * muK / L, area = L * L;
  double janssenStress = 0, previousWeight = 0;
  const TricubicSpline s33(rep.grid.origin, rep.grid.spacing, rep.grid.counts,
                           component(rep.stress, 2, 2));
  std::vector<CoarseGrainer> widths;
  for (double w : kWidths) widths.emplace_back(sim, w);
  double devSq = 0;
  int devCount = 0;
  const Vec3 axis(0.5 * (box.lo.x() + box.hi.x()), yMid, 0.0);
  // From the surface down, so the Janssen integration runs with depth; written bottom-up.
  constexpr int kLevels = 61;
  std::vector<std::string> rows(kLevels);
  double hydroSq = 0;
  for (int k = kLevels - 1; k >= 0; --k) {
    const double z = box.lo.z() + 0.005 + k * (H - 0.01) / (kLevels - 1), depth = box.hi.z() - z;
    const double mean = sectionMean(z), weight = weightAbove(z);
    const double load = (weight - previousWeight) / area,
                 decay = std::exp(-a * (H - 0.01) / (kLevels - 1));
    janssenStress =
        k == kLevels - 1 ? weight / area
        : a > 0 ? janssenStress * decay + load * (1 - decay) / (a * (H - 0.01) / (kLevels - 1))
                : janssenStress + load;
    previousWeight = weight;
    const double hydrostatic = weight / area;
    std::ostringstream row;
    row << num(z) << ',' << num(depth) << ',' << num(s33(Vec3(axis.x(), axis.y(), z)));
    for (const CoarseGrainer& c : widths)
      row << ',' << num(c.at(Vec3(axis.x(), axis.y(), z)).stress()(2, 2));
    row << ',' << num(mean) << ',' << num(-janssenStress) << ',' << num(-hydrostatic) << '\n';
    rows[k] = row.str();
    if (depth > 0.1 * H && depth < 0.9 * H) {
      devSq += std::pow((-mean - janssenStress) / janssenStress, 2);
      hydroSq += std::pow((-mean - hydrostatic) / hydrostatic, 2);
      ++devCount;
    }
  }
  for (const std::string& row : rows) profiles << row;
  summary["hydrostatic_rms_deviation"] = devCount ? std::sqrt(hydroSq / devCount) : 0.0;
  summary["janssen_rms_deviation"] = devCount ? std::sqrt(devSq / devCount) : 0.0;

  // ---- 5. Files -----------------------------------------------------------------------------
  std::ostringstream mid;
  mid << "i,k,x_m,z_m,s33_rep_Pa,s33_cg_Pa,density_cg_kg_m3\n";
  for (int k = 0; k < nz; ++k) {
    for (int i = 0; i < nx; ++i) {
      const Vec3 r = plane.point(i, k);
      const std::size_t n = std::size_t(k) * nx + i;
      mid << i << ',' << k << ',' << num(r.x()) << ',' << num(r.z()) << ','
          << num(planeAt(i, k)(2, 2)) << ',' << num(cgPlane[n]) << ',' << num(cgDensity[n]) << '\n';
    }
  }
  writeTextFile(dir / "midsection.csv", mid.str());
  std::ostringstream traj;
  traj << "line,x_m,z_m\n";
  for (std::size_t l = 0; l < lines.size(); ++l) {
    for (const Vec3& p : lines[l]) traj << l << ',' << num(p.x()) << ',' << num(p.z()) << '\n';
  }
  writeTextFile(dir / "trajectories.csv", traj.str());
  writeTextFile(dir / "profiles.csv", profiles.str());
  std::ostringstream wall;
  wall << "z_m,wall_normal_Pa,wall_shear_up_Pa\n";
  for (std::size_t k = 0; k < wallStress.z.size(); ++k) {
    wall << num(wallStress.z[k]) << ',' << num(wallStress.normal[k]) << ','
         << num(wallStress.shear[k]) << '\n';
  }
  writeTextFile(dir / "wall_stress.csv", wall.str());

  std::vector<double> tensor, fraction, count;
  for (std::size_t s = 0; s < rep.stress.size(); ++s) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) tensor.push_back(rep.stress[s](a, b));
    }
    fraction.push_back(rep.solidFraction[s]);
    count.push_back(rep.members[s]);
  }
  writeVti(dir / "representative.vti", rep.grid.origin, rep.grid.spacing, rep.grid.counts,
           {{"stress_Pa", 9, tensor}, {"solid_fraction", 1, fraction}, {"members", 1, count}});
  const Vec3 planeOrigin(box.lo.x(), yMid, box.lo.z());
  const Vec3 planeSpacing(L / (nx - 1), 1.0, H / (nz - 1));
  writeVti(dir / "midsection.vti", planeOrigin, planeSpacing, {nx, 1, nz},
           {{"stress_representative_Pa", 9, repTensor},
            {"stress_coarse_grained_Pa", 9, cgTensor},
            {"density_coarse_grained_kg_m3", 1, cgDensity}});
  writeVtpLines(dir / "trajectories.vtp", lines);

  std::ostringstream text;
  for (const auto& [key, value] : summary) text << key << " = " << num(value) << '\n';
  writeTextFile(dir / "summary.txt", text.str());
  return summary;
}

}  // namespace granular::app
