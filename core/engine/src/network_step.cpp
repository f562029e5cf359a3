/// The network's stable step (granular/network_step.hpp).
#include "granular/network_step.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <vector>

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

}  // namespace granular
