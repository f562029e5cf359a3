/// The contact network's frequency bound (granular/network_frequency.hpp).
#include "granular/network_frequency.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace granular {

ContactStiffness contactStiffness(const Material& material, double reducedRadius, double overlap) {
  // The terms' own formulas (contact_terms/), as the force pass evaluates them.
  ContactStiffness k;
  const double kappa = material.normalCoefficient();
  const double h = std::max(overlap, 0.0);
  k.normal = material.normalLaw == NormalLaw::Hooke
                 ? NormalElastic::stiffness<NormalLaw::Hooke>(kappa, reducedRadius, h)
                 : NormalElastic::stiffness<NormalLaw::Hertz>(kappa, reducedRadius, h);
  if (material.hasFriction()) {
    const double constant =
        material.tangentialLaw == TangentialLaw::Constant ? material.tangentialStiffness : 0.0;
    k.tangential =
        TangentialSpring::stiffness(material.tangentialCoefficient(), constant, reducedRadius, h);
  }
  if (RollingResistance::active(material)) {
    k.rolling =
        RollingResistance::constants(material).stiffness * k.normal * reducedRadius * reducedRadius;
  }
  return k;
}

double contactGain(const ContactStiffness& k, const ContactBody& body, bool rotations) {
  // G G^T for the outputs (normal, tangential in the tangent plane, rolling): the normal row
  // sees only the translation, k_n/m; the tangential rows see the translation (1/m) and the
  // rotation through the lever arm (a²/I), on the same two tangent directions; the rolling rows
  // see the rotation (1/I) on those directions too. In the contact's frame (n, t1, t2) the
  // tangential and rolling rows of one tangent direction couple only with each other (the
  // rotation about t2 moves the contact point along t1), so G G^T is diag(k_n/m) and, per
  // tangent direction, the 2×2 [[k_t (1/m + a²/I), √(k_t k_r) a/I], [·, k_r/I]].
  const double normal = k.normal / body.mass;
  if (!rotations) return std::sqrt(normal);
  const double kt = k.tangential, kr = k.rolling, m = body.mass, inertia = body.inertia;
  Eigen::Matrix2d t;
  t << kt * (1.0 / m + body.arm * body.arm / inertia), std::sqrt(kt * kr) * body.arm / inertia,
      std::sqrt(kt * kr) * body.arm / inertia, kr / inertia;
  const double tangent = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(t).eigenvalues()(1);
  return std::sqrt(std::max(normal, tangent));
}

NetworkFrequency networkFrequencyBound(const Simulation& sim, int sweeps) {
  const Particles& p = sim.particles();
  const Material& material = sim.config().material;
  const bool rotations = sim.frictional();
  // The gain matrix B: B_ii = Σ_c gain_i², B_ij = gain_i gain_j per contact; it dominates the
  // block norms of A entrywise, so λ_max(A) ≤ ρ(B) ≤ max_i (B x)_i / x_i for any positive x
  // (Collatz–Wielandt). x = 1 is Gershgorin's bound; each sweep x ← B x tightens it.
  struct Link {
    std::uint32_t i, j;
    double gi, gj;
  };
  std::vector<Link> links;
  std::vector<double> diagonal(p.size(), 0.0);
  auto body = [&](std::size_t i, double h) {
    return ContactBody{p.mass[i], p.inertia(i), p.radius[i] - 0.5 * h};
  };
  NetworkFrequency out;
  auto damping = [&](const ContactStiffness& k, double mass) {
    double zeta = 0.5 * material.normalDamping * std::sqrt(mass / k.normal);
    if (k.tangential > 0.0) {
      zeta = std::max(zeta, 0.5 * material.tangentialDamping * std::sqrt(mass / k.tangential));
    }
    if (k.rolling > 0.0) zeta = std::max(zeta, material.rollingDamping);
    out.dampingRatio = std::max(out.dampingRatio, zeta);
  };
  sim.forEachContact([&](const ContactView& c) {
    const std::size_t i = c.particle;
    if (c.isWall()) {
      const ContactStiffness k = contactStiffness(material, p.radius[i], c.overlap);
      damping(k, p.mass[i]);
      const double gain = contactGain(k, body(i, c.overlap), rotations);
      diagonal[i] += gain * gain;
      ++out.contacts;
      return;
    }
    const std::size_t j = c.otherParticle();
    if (j < i) return;  // each pair once (the view sees it from both sides)
    const double reduced = p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
    const ContactStiffness k = contactStiffness(material, reduced, c.overlap);
    damping(k, p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]));
    const double gi = contactGain(k, body(i, c.overlap), rotations);
    const double gj = contactGain(k, body(j, c.overlap), rotations);
    diagonal[i] += gi * gi;
    diagonal[j] += gj * gj;
    links.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), gi, gj});
    ++out.contacts;
  });
  auto multiply = [&](const std::vector<double>& x, std::vector<double>& y) {
    for (std::size_t i = 0; i < x.size(); ++i) y[i] = diagonal[i] * x[i];
    for (const Link& l : links) {
      y[l.i] += l.gi * l.gj * x[l.j];
      y[l.j] += l.gi * l.gj * x[l.i];
    }
  };
  // A particle without contacts has a zero row: x stays positive there (1), and its ratio 0.
  std::vector<double> x(p.size(), 1.0), y(p.size(), 0.0);
  for (int sweep = 0;; ++sweep) {
    multiply(x, y);
    double largest = 0.0;
    std::size_t at = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      const double ratio = y[i] / x[i];
      if (ratio > largest) largest = ratio, at = i;
    }
    if (sweep == 0 || largest < out.omegaMax * out.omegaMax) {
      out.omegaMax = std::sqrt(largest);
      out.particle = at;
    }
    if (sweep == sweeps) break;
    double scale = 0.0;
    for (double v : y) scale = std::max(scale, v);
    if (!(scale > 0.0)) break;
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::max(y[i] / scale, 1e-300);
  }
  return out;
}

}  // namespace granular
