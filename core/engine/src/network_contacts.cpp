/// The contacts the step control counts (network_contacts.hpp, network_bound.hpp).
#include "network_contacts.hpp"

#include <omp.h>

#include <algorithm>

#include "contact_linearisation.hpp"
#include "force_pass.hpp"

namespace granular {

bool isListed(const SimulationState& s) {
  return s.neighbours.valid && s.neighbours.rowStart.size() == s.particles.size() + 1;
}

bool pairsFromGeometry(const SimulationState& s) {
  return isListed(s) && std::none_of(s.walls.begin(), s.walls.end(), [](const Wall& w) {
           return w.shape == WallShape::Mesh && !w.removed;
         });
}

int networkThreads(const SimulationState& s, std::size_t pairs) {
  constexpr std::size_t kPairsForThreads = 4096;
  if (pairs < kPairsForThreads) return 1;
  const int threads = passThreads(s) > 0 ? passThreads(s) : omp_get_max_threads();
  return std::max(threads, 1);
}

NetworkWalk::NetworkWalk(const SimulationState& s, double lookahead)
    : s_(s),
      lookahead_(lookahead),
      listed_(isListed(s)),
      ahead_(lookahead > 0.0 && listed_),
      geometric_(pairsFromGeometry(s)),
      hertz_(s.config.material.normalLaw == NormalLaw::Hertz),
      kappa_(s.config.material.normalCoefficient()) {}

double NetworkWalk::impactOverlap(double mass, double reduced, double u) const {
  if (!hertz_ || !(u > 0.0)) return 0.0;
  return std::pow(5.0 * mass * u * u / (4.0 * kappa_ * std::sqrt(reduced)), 0.4);
}

NetworkContact NetworkWalk::pair(std::size_t i, std::size_t j, const Vec3& normal, double u,
                                 double h, bool touching, double relative) const {
  const Particles& p = s_.particles;
  const double reduced = p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
  const double mass = p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
  return NetworkContact{i, j,        normal,  reduced, mass, h + impactOverlap(mass, reduced, u),
                        u, touching, relative};
}

NetworkContact NetworkWalk::wall(std::size_t i, const Vec3& normal, double u, double h,
                                 bool touching, double relative) const {
  const Particles& p = s_.particles;
  return NetworkContact{i,           i,         normal,
                        p.radius[i], p.mass[i], h + impactOverlap(p.mass[i], p.radius[i], u),
                        u,           touching,  relative};
}

void NetworkWalk::touchingFromPass(const std::function<void(const NetworkContact&)>& visit) const {
  const Particles& p = s_.particles;
  visitContacts(
      s_,
      [&](const ContactView& c) {
        // A pull across a gap (a term that reaches beyond touch) has no spring: the pair is
        // a candidate, about to touch if it approaches.
        if (c.overlap < 0.0) return;
        const std::size_t i = c.particle;
        if (c.isWall()) {
          const Vec3 v = p.velocity[i] - s_.walls[c.wall()].velocityAt(c.point);
          visit(wall(i, c.normal, v.dot(c.normal), c.overlap, true, v.norm()));
        } else {
          const std::size_t j = c.otherParticle();
          if (j < i) return;
          const Vec3 v = p.velocity[i] - p.velocity[j];
          visit(pair(i, j, c.normal, v.dot(c.normal), c.overlap, true, v.norm()));
        }
      },
      nullptr);
}

void visitNetworkContacts(const SimulationState& s, double lookahead,
                          const std::function<void(const NetworkContact&)>& visit) {
  walkNetworkContacts(s, lookahead, visit);
}

LinearContact linearisedContact(const SimulationState& s, const NetworkContact& n,
                                const ContactConstants& constants, unsigned optional) {
  const Particles& p = s.particles;
  const bool wall = n.j == n.i;
  LinearContact linear;
  linear.radius = n.reduced;
  linear.mass = n.mass;
  linear.overlap = std::max(n.overlap, 0.0);
  const double ii = 1.4 * p.mass[n.i] * p.radius[n.i] * p.radius[n.i];  // I + m R²
  const double ij = wall ? 0.0 : 1.4 * p.mass[n.j] * p.radius[n.j] * p.radius[n.j];
  linear.rollingInertia = wall ? ii : 1.0 / (1.0 / ii + 1.0 / ij);
  lineariseContact(constants, s.frictional, optional, linear);
  return linear;
}

}  // namespace granular
