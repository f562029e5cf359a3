/// The dense reference spectra of the tests (network_matrices.hpp).
#include "network_matrices.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "granular/contact_theory.hpp"
#include "granular/network_frequency.hpp"
#include "integrators.hpp"

namespace granular::testing {

double largestEigenvalue(const Eigen::MatrixXd& a) {
  const Eigen::VectorXd values = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(a).eigenvalues();
  return values(values.size() - 1);
}

Eigen::MatrixXd networkMatrix(const Simulation& sim, bool damping) {
  const Particles& p = sim.particles();
  const Material& material = sim.config().material;
  const bool rotations = sim.frictional();
  const Eigen::Index per = rotations ? 6 : 3, n = static_cast<Eigen::Index>(p.size()) * per;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  sim.forEachContact([&](const ContactView& c) {
    const std::size_t i = c.particle;
    const bool wall = c.isWall();
    const std::size_t j = wall ? i : c.otherParticle();
    if (!wall && j < i) return;
    const double reduced =
        wall ? p.radius[i] : p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
    ContactStiffness k = contactStiffness(material, reduced, c.overlap);
    if (damping) {  // the dashpots' coefficients, as the terms apply them
      const double mass = wall ? p.mass[i] : p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
      const double ii = 1.4 * p.mass[i] * p.radius[i] * p.radius[i];
      const double ij = wall ? 0.0 : 1.4 * p.mass[j] * p.radius[j] * p.radius[j];
      const double inertia = wall ? ii : ii * ij / (ii + ij);
      const double rolling = 2.0 * material.rollingDamping * std::sqrt(inertia * k.rolling);
      k = ContactStiffness{material.normalDamping * mass,
                           k.tangential > 0 ? material.tangentialDamping * mass : 0.0, rolling};
    }
    const Eigen::Vector3d nn = c.normal;
    const Eigen::Matrix3d tangent = Eigen::Matrix3d::Identity() - nn * nn.transpose();
    const Eigen::Matrix3d cross = crossMatrix(c.normal);
    // One body's columns of G; `sign` +1 for i, −1 for j (its translation and rolling count
    // negatively; its rotation moves its contact point as i's does: − a [n]×).
    auto columns = [&](std::size_t body, double sign) {
      Eigen::MatrixXd g = Eigen::MatrixXd::Zero(7, per);
      const double m = p.mass[body], inertia = p.inertia(body);
      const double arm = p.radius[body] - 0.5 * c.overlap;
      g.block(0, 0, 1, 3) = sign * std::sqrt(k.normal / m) * nn.transpose();
      if (rotations) {
        g.block(1, 0, 3, 3) = sign * std::sqrt(k.tangential / m) * tangent;
        g.block(1, 3, 3, 3) = -std::sqrt(k.tangential / inertia) * arm * cross;
        g.block(4, 3, 3, 3) = sign * std::sqrt(k.rolling / inertia) * tangent;
      }
      return g;
    };
    const Eigen::MatrixXd gi = columns(i, 1.0);
    const Eigen::Index bi = static_cast<Eigen::Index>(i) * per;
    a.block(bi, bi, per, per) += gi.transpose() * gi;
    if (wall) return;
    const Eigen::MatrixXd gj = columns(j, -1.0);
    const Eigen::Index bj = static_cast<Eigen::Index>(j) * per;
    a.block(bj, bj, per, per) += gj.transpose() * gj;
    a.block(bi, bj, per, per) += gi.transpose() * gj;
    a.block(bj, bi, per, per) += gj.transpose() * gi;
  });
  return a;
}

double verletStepRadius(const Eigen::MatrixXd& a, const Eigen::MatrixXd& d, double dt,
                        double dashpotLead) {
  const Eigen::Index n = a.rows();
  const Eigen::MatrixXd one = Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd step = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  // Rows of y', then a' (from y' and the predicted velocity), then v'.
  const Eigen::MatrixXd yy = one, yv = dt * one, ya = 0.5 * dt * dt * one;
  const Eigen::MatrixXd ay = -a * yy, av = -a * yv - d, aa = -a * ya - dashpotLead * dt * d;
  step.block(0, 0, n, n) = yy;
  step.block(0, n, n, n) = yv;
  step.block(0, 2 * n, n, n) = ya;
  step.block(n, 0, n, n) = 0.5 * dt * ay;
  step.block(n, n, n, n) = one + 0.5 * dt * av;
  step.block(n, 2 * n, n, n) = 0.5 * dt * (one + aa);
  step.block(2 * n, 0, n, n) = ay;
  step.block(2 * n, n, n, n) = av;
  step.block(2 * n, 2 * n, n, n) = aa;
  return Eigen::EigenSolver<Eigen::MatrixXd>(step, false).eigenvalues().cwiseAbs().maxCoeff();
}

double gearStepRadius(const Eigen::MatrixXd& a, const Eigen::MatrixXd& d, double dt) {
  const Eigen::Index n = a.rows();
  Eigen::MatrixXd step(6 * n, 6 * n);
  std::vector<Vec3> y(n), v(n), accel(n);
  Derivatives z;
  std::vector<Vec3>* parts[6] = {&y, &v, &z.d2, &z.d3, &z.d4, &z.d5};
  const double scale[6] = {
      1.0, dt, dt * dt, dt * dt * dt, dt * dt * dt * dt, dt * dt * dt * dt * dt};
  Eigen::VectorXd yp(n), vp(n);
  for (Eigen::Index column = 0; column < 6 * n; ++column) {
    for (std::vector<Vec3>* part : parts) part->assign(n, Vec3::Zero());
    (*parts[column / n])[column % n].x() = 1.0 / scale[column / n];
    Gear5::predict(&y, v, z, dt);
    for (Eigen::Index i = 0; i < n; ++i) {
      yp(i) = y[i].x();
      vp(i) = v[i].x();
    }
    const Eigen::VectorXd f = -a * yp - d * vp;
    for (Eigen::Index i = 0; i < n; ++i) accel[i] = Vec3(f(i), 0, 0);
    Gear5::correct(&y, v, z, accel, dt);
    for (int k = 0; k < 6; ++k) {
      for (Eigen::Index i = 0; i < n; ++i) step(k * n + i, column) = scale[k] * (*parts[k])[i].x();
    }
  }
  return Eigen::EigenSolver<Eigen::MatrixXd>(step, false).eigenvalues().cwiseAbs().maxCoeff();
}

double exactOmegaMax(const Simulation& sim) {
  return std::sqrt(std::max(largestEigenvalue(networkMatrix(sim, false)), 0.0));
}

}  // namespace granular::testing
