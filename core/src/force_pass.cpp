/// The force pass: contact forces and torques of every contact at the current state (Eqs. 3-5).
/// Specialised at compile time for the friction path and the normal law, so the frictionless
/// scene carries no tangential history, no torques and no per-contact branch on either.
#include <cmath>

#include "contact_forces.hpp"
#include "force_pass.hpp"

namespace granular {
namespace {

ContactConstants constantsOf(const SimulationConfig& cfg, double dt) {
  const Material& m = cfg.material;
  return {m.normalCoefficient(),
          m.tangentialCoefficient(),
          m.normalDamping,
          m.tangentialDamping,
          m.friction,
          dt};
}

/// Unit normal from i towards j. Coincident centres have no direction: +z is used so the
/// particles are pushed apart along a defined axis instead of producing NaN.
inline Vec3 unitNormal(const Vec3& d, double distance) {
  return distance > 0.0 ? Vec3(d / distance) : Vec3(Vec3::UnitZ());
}

/// F_ij of Eq. (5) for particles i and j (or i and a wall) and its bookkeeping.
/// `n` points from i towards the other body, `vrel` = v_i - v_other, lever arm a_i = R_i - h/2.
template <bool kFriction, NormalLaw kLaw, bool kAdvance>
inline Vec3 contactForce(const ContactConstants& c, TangentialHistory* history, const Vec3& n,
                         double overlap, double radius, double mass, const Vec3& vrel,
                         const Vec3& angularTerm, ContactPowers& powers) {
  // Normal: elastic + viscous, never pulling (the clamp at zero).
  double elastic = 0.0;
  const double fe = normalElasticForce<kLaw>(c, radius, overlap, elastic);
  const double overlapRate = vrel.dot(n);
  const double fn = std::max(0.0, fe + c.normalDamping * mass * overlapRate);
  powers.elasticNormal += elastic;
  powers.normalDampingPower += (fn - fe) * overlapRate;
  Vec3 f = -fn * n;
  if constexpr (kFriction) {
    f += tangentialForce<kAdvance>(c, *history, n, vrel + angularTerm, radius, overlap, mass, fn,
                                   powers);
  }
  return f;
}

/// With kAdvance the pass writes the forces, torques, wall reactions and powers into `s` and
/// advances the tangential springs; without it, `s` is only read and the results go to `out`.
template <bool kFriction, NormalLaw kLaw, bool kAdvance, class Visitor>
void forcePass(SimulationState& s, double dt, std::vector<Vec3>& force, std::vector<Vec3>& torque,
               Visitor&& visit) {
  const ContactConstants c = constantsOf(s.config, dt);
  const Particles& p = s.particles;
  NeighbourList& list = s.neighbours;
  ContactPowers powers;
  force.assign(p.size(), Vec3::Zero());
  if constexpr (kFriction) torque.assign(p.size(), Vec3::Zero());

  /// Particle pairs.
  for (std::size_t k = 0; k < list.first.size(); ++k) {
    const std::uint32_t i = list.first[k], j = list.second[k];
    const Vec3 d = p.position[j] - p.position[i];
    const double reach = p.radius[i] + p.radius[j];
    const double distance2 = d.squaredNorm();
    if (distance2 >= reach * reach) {
      if constexpr (kFriction && kAdvance) list.history[k] = TangentialHistory{};  // contact open
      continue;
    }
    const double distance = std::sqrt(distance2);
    const Vec3 n = unitNormal(d, distance);
    const double h = reach - distance;
    const double armI = p.radius[i] - 0.5 * h, armJ = p.radius[j] - 0.5 * h;
    const double radius = p.radius[i] * p.radius[j] / reach;
    const double mass = p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
    const Vec3 vrel = p.velocity[i] - p.velocity[j];
    Vec3 angularTerm = Vec3::Zero();
    TangentialHistory* history = nullptr;
    TangentialHistory scratch;
    if constexpr (kFriction) {
      // Contact-point velocity of i relative to j: ω_i × (a_i n) - ω_j × (-a_j n).
      angularTerm = (armI * p.angularVelocity[i] + armJ * p.angularVelocity[j]).cross(n);
      if constexpr (kAdvance) {
        history = &list.history[k];
      } else {
        scratch = list.history[k];
        history = &scratch;
      }
    }
    const Vec3 f = contactForce<kFriction, kLaw, kAdvance>(c, history, n, h, radius, mass, vrel,
                                                           angularTerm, powers);
    force[i] += f;
    force[j] -= f;
    if constexpr (kFriction) {
      const Vec3 t = n.cross(f);  // d_ci × F with d_ci = a_i n; for j: (-a_j n) × (-F)
      torque[i] += armI * t;
      torque[j] += armJ * t;
    }
    ++powers.particleContacts;
    visit(i, static_cast<long>(j), Vec3(p.position[i] + armI * n), f);
  }

  /// Particle-wall contacts: the wall is a body of infinite radius and mass (R_ij = R_i,
  /// m_ij = m_i) moving with its prescribed velocity.
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    const Wall& wall = s.walls[w];
    const Vec3 n = -wall.normal;  // from the particle towards the wall
    Vec3 reaction = Vec3::Zero();
    const std::vector<std::uint32_t>& candidates = list.wallParticles[w];
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const std::uint32_t i = candidates[k];
      const double distance = (p.position[i] - wall.point).dot(wall.normal);
      const double h = p.radius[i] - distance;
      if (h <= 0.0) {
        if constexpr (kFriction && kAdvance) list.wallHistory[w][k] = TangentialHistory{};
        continue;
      }
      const double arm = p.radius[i] - 0.5 * h;
      const Vec3 vrel = p.velocity[i] - wall.velocity;
      Vec3 angularTerm = Vec3::Zero();
      TangentialHistory* history = nullptr;
      TangentialHistory scratch;
      if constexpr (kFriction) {
        angularTerm = arm * p.angularVelocity[i].cross(n);
        if constexpr (kAdvance) {
          history = &list.wallHistory[w][k];
        } else {
          scratch = list.wallHistory[w][k];
          history = &scratch;
        }
      }
      const Vec3 f = contactForce<kFriction, kLaw, kAdvance>(c, history, n, h, p.radius[i],
                                                             p.mass[i], vrel, angularTerm, powers);
      force[i] += f;
      if constexpr (kFriction) torque[i] += arm * n.cross(f);
      reaction -= f;
      powers.wallPower += f.dot(wall.velocity);
      ++powers.wallContacts;
      visit(i, -static_cast<long>(w) - 1, Vec3(p.position[i] + arm * n), f);
    }
    if constexpr (kAdvance) s.walls[w].reaction = reaction;
  }
  if constexpr (kAdvance) s.powers = powers;
}

struct NoVisit {
  void operator()(std::uint32_t, long, const Vec3&, const Vec3&) const {}
};

template <bool kAdvance, class Visitor>
void dispatch(SimulationState& s, double dt, std::vector<Vec3>& force, std::vector<Vec3>& torque,
              Visitor&& visit) {
  const bool hertz = s.config.material.normalLaw == NormalLaw::Hertz;
  if (s.frictional) {
    hertz ? forcePass<true, NormalLaw::Hertz, kAdvance>(s, dt, force, torque, visit)
          : forcePass<true, NormalLaw::Hooke, kAdvance>(s, dt, force, torque, visit);
  } else {
    hertz ? forcePass<false, NormalLaw::Hertz, kAdvance>(s, dt, force, torque, visit)
          : forcePass<false, NormalLaw::Hooke, kAdvance>(s, dt, force, torque, visit);
  }
}

}  // namespace

void computeContactForces(SimulationState& s, double dt) {
  dispatch<true>(s, dt, s.force, s.torque, NoVisit{});
}

void visitContacts(const SimulationState& s, const std::function<void(const ContactView&)>& visit,
                   std::vector<Vec3>* netForce) {
  // Without kAdvance the pass never writes to the state (see forcePass), so casting away const
  // here is safe; the forces go to scratch arrays.
  SimulationState& state = const_cast<SimulationState&>(s);
  std::vector<Vec3> force, torque;
  dispatch<false>(state, s.config.timeStep, force, torque,
                  [&](std::uint32_t i, long other, const Vec3& point, const Vec3& f) {
                    if (!visit) return;
                    visit(ContactView{i, other, point, f});
                    if (other >= 0)
                      visit(ContactView{static_cast<std::size_t>(other), i, point, -f});
                  });
  if (netForce) *netForce = std::move(force);
}

}  // namespace granular
