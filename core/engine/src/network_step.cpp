/// The network's stable step (granular/network_step.hpp).
#include "granular/network_step.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "granular/network_frequency.hpp"
#include "integrators.hpp"

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
  // Scan up in steps of 10⁻², then bisect the first unstable bracket: the interval starts at 0.
  double lo = 0.0, hi = 0.0;
  for (double w = 1e-2; w <= 4.0; w += 1e-2) {
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

NetworkStep networkStableStep(const Simulation& sim) {
  const NetworkFrequency f = networkFrequencyBound(sim);
  NetworkStep out;
  out.omegaMax = f.omegaMax;
  out.particle = f.particle;
  out.zeta = f.dampingRatio;
  out.dt = out.omegaMax > 0.0 ? stableOmegaDt(sim.config().integrator, out.zeta) / out.omegaMax
                              : std::numeric_limits<double>::infinity();
  return out;
}

}  // namespace granular
