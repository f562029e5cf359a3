/// The network's stable step (granular/network_step.hpp).
#include "granular/network_step.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <vector>

#include "granular/contact_theory.hpp"
#include "granular/network_frequency.hpp"
#include "integrators.hpp"
#include "network_bound.hpp"
#include "simulation_state.hpp"

namespace granular {

double stepSpectralRadius(Integrator integrator, double w, double zeta) {
  const bool gear = integrator == Integrator::Gear5;
  const int n = gear ? 6 : 3;
  Eigen::MatrixXd step(n, n);
  for (int k = 0; k < n; ++k) {
    std::vector<Vec3> x{Vec3(k == 0, 0, 0)}, v{Vec3(k == 1, 0, 0)}, a(1);
    Derivatives d;
    d.d2 = {Vec3(k == 2, 0, 0)};
    auto accel = [&] { return Vec3(-x[0].x() - 2.0 * zeta * v[0].x(), 0, 0); };
    if (gear) {
      d.d3 = {Vec3(k == 3, 0, 0)};
      d.d4 = {Vec3(k == 4, 0, 0)};
      d.d5 = {Vec3(k == 5, 0, 0)};
      Gear5::predict(&x, v, d, w);
      a[0] = accel();
      Gear5::correct(&x, v, d, a, w);
    } else {
      VelocityVerlet::drift(&x, v, d, w);
      a[0] = accel();
      VelocityVerlet::kick(v, d, a, w);
    }
    step(0, k) = x[0].x();
    step(1, k) = v[0].x();
    step(2, k) = d.d2[0].x();
    if (gear) {
      step(3, k) = d.d3[0].x();
      step(4, k) = d.d4[0].x();
      step(5, k) = d.d5[0].x();
    }
  }
  return Eigen::EigenSolver<Eigen::MatrixXd>(step).eigenvalues().cwiseAbs().maxCoeff();
}

double stableOmegaDt(Integrator integrator, double zeta, double growthPerStep) {
  auto stable = [&](double w) {
    return stepSpectralRadius(integrator, w, zeta) <= 1.0 + growthPerStep;
  };
  // Scan up in steps of 1/32, then bisect the first unstable bracket: the interval starts at 0
  // (a coarser scan would step over nothing: no integrator here has an unstable island inside
  // its interval, tests/test_integrator_stability.cpp scans at 10⁻³).
  double lo = 0.0, hi = 0.0;
  for (double w = 1.0 / 32; w <= 4.0; w += 1.0 / 32) {
    if (!stable(w)) {
      hi = w;
      break;
    }
    lo = w;
  }
  if (hi == 0.0) return lo;
  while (hi - lo > 1e-6) {
    const double mid = 0.5 * (lo + hi);
    (stable(mid) ? lo : hi) = mid;
  }
  return lo;
}

double stableOmegaDtOver(Integrator integrator, double zetaLow, double zetaHigh) {
  // The grid ζ_k = (k/64)²: fine near 0, where Gear's interval changes fastest with ζ.
  constexpr double kGrid = 64.0;
  // A least damped contact above the corner's ratio: the corner's ratio is the lower end.
  const double low = std::floor(std::sqrt(std::clamp(zetaLow, 0.0, zetaHigh)) * kGrid);
  const double high = std::ceil(std::sqrt(std::max(zetaHigh, 0.0)) * kGrid);
  if (!(high < 1e4)) return 0.0;  // no finite ratio: nothing is stable
  static std::mutex mutex;
  static std::map<std::pair<int, long>, double> table;
  std::lock_guard<std::mutex> lock(mutex);
  double smallest = std::numeric_limits<double>::infinity();
  for (long k = static_cast<long>(low); k <= static_cast<long>(high); ++k) {
    const std::pair<int, long> key{static_cast<int>(integrator), k};
    auto it = table.find(key);
    if (it == table.end()) {
      const double zeta = (k / kGrid) * (k / kGrid);
      it = table.emplace(key, stableOmegaDt(integrator, zeta)).first;
    }
    smallest = std::min(smallest, it->second);
  }
  return smallest;
}

double networkStepOf(Integrator integrator, const NetworkFrequency& f) {
  return f.omegaMax > 0.0
             ? stableOmegaDtOver(integrator, f.smallestDampingRatio, f.dampingRatio) / f.omegaMax
             : std::numeric_limits<double>::infinity();
}

NetworkStep networkStableStep(const SimulationState& s, double lookahead) {
  const NetworkFrequency f = networkFrequencyBound(s, 32, lookahead, nullptr);
  NetworkStep out;
  out.omegaMax = f.omegaMax;
  out.particle = f.particle;
  out.zeta = f.dampingRatio;
  out.smallestZeta = f.smallestDampingRatio;
  out.dt = networkStepOf(s.config.integrator, f);
  return out;
}

NetworkStep networkStableStep(const Simulation& sim, double lookahead) {
  return networkStableStep(SimulationAccess::state(sim), lookahead);
}

NetworkStep denseBedStep(const SimulationConfig& config, double smallestRadius) {
  const double r = smallestRadius;
  const Material& material = config.material;
  // Touching at the overlap the stiffest contact reaches: Hooke's stiffness does not depend on
  // it; Hertz's at the peak of a pair's impact at the expected speed (as the binary limit).
  double overlap = 1e-6 * r;
  if (material.normalLaw == NormalLaw::Hertz) {
    const double mass = material.density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
    const double hertz = material.normalCoefficient() * std::sqrt(0.5 * r);
    overlap =
        std::max(overlap, hertzUndampedImpact(hertz, 0.5 * mass, config.impactSpeed).peakOverlap);
  }
  const double spacing = 2.0 * r - overlap;      // nearest neighbours' distance
  const double cube = spacing * std::sqrt(2.0);  // the cubic cell's edge
  const Vec3 sites[4] = {Vec3(0, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0.5), Vec3(0, 0.5, 0.5)};
  constexpr int kCells = 3;  // 3 × 3 × 3 cells of 4 sites: 108 spheres, a third of them inside
  Particles p;
  for (int k = 0; k < kCells; ++k) {
    for (int j = 0; j < kCells; ++j) {
      for (int i = 0; i < kCells; ++i) {
        for (const Vec3& site : sites) {
          const Vec3 centre = cube * (Vec3(i, j, k) + site) + Vec3(r, r, r - overlap);
          p.add(centre, r, material.density);
        }
      }
    }
  }
  Wall floor;
  floor.name = "bottom";
  SimulationConfig model = config;
  model.gravity = Vec3::Zero();
  model.step = StepControl{};
  model.timeStep = 1e-3 * maxStableStep(stiffestContact(material, r, config.impactSpeed),
                                        config.integrator);  // any step the model accepts
  model.threads = 1;
  const Simulation bed(std::move(p), {floor}, model);
  return networkStableStep(bed, 0.0);
}

}  // namespace granular
