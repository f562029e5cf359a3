/// The force pass: contact forces and torques of every contact at the current state (Eqs. 3-5).
/// Specialised at compile time for the friction path and the normal law, so the frictionless
/// scene carries no tangential history, no torques and no per-contact branch on either.
///
/// Sections: 1. one contact (pair, wall); 2. the hot pass, parallel and deterministic;
/// 3. the measuring pass that visits every contact; 4. dispatch.
///
/// The hot pass runs in two phases so that no two threads add to the same particle and the
/// result does not depend on the thread count, bit for bit: (a) every contact's force is
/// computed into its own slot (pairs and wall contacts in fixed blocks, powers summed per block
/// in order); (b) each particle gathers its contacts' forces in a fixed order (its pairs as the
/// first particle, then as the second, then its wall contacts).
#include <omp.h>

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

// ---- 1. One contact -----------------------------------------------------------------------

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

/// What one contact puts on its particle(s).
struct ContactResult {
  Vec3 force = Vec3::Zero();    ///< on particle i (−force on j) [N]
  Vec3 torqueI = Vec3::Zero();  ///< d_ci × F on i [N m]
  Vec3 moment = Vec3::Zero();   ///< n × F, the torques' common factor (pairs only) [N]
  double overlap = 0.0;         ///< h [m]
  Vec3 point = Vec3::Zero();    ///< contact point [m]
  bool touching = false;
};

/// Candidate pair k of the neighbour list. With kAdvance its tangential spring is advanced
/// (and dropped when the pair is apart); without, it is only read.
template <bool kFriction, NormalLaw kLaw, bool kAdvance>
inline ContactResult evaluatePair(const ContactConstants& c, const Particles& p,
                                  NeighbourList& list, std::size_t k, ContactPowers& powers) {
  ContactResult r;
  const std::uint32_t i = list.first[k], j = list.second[k];
  const Vec3 d = p.position[j] - p.position[i];
  const double reach = p.radius[i] + p.radius[j];
  const double distance2 = d.squaredNorm();
  if (distance2 >= reach * reach) {
    if constexpr (kFriction && kAdvance) list.history[k] = TangentialHistory{};  // contact open
    return r;
  }
  const double distance = std::sqrt(distance2);
  const Vec3 n = unitNormal(d, distance);
  const double h = reach - distance;
  const double armI = p.radius[i] - 0.5 * h, armJ = p.radius[j] - 0.5 * h;  // lever arms
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
  r.force = contactForce<kFriction, kLaw, kAdvance>(c, history, n, h, radius, mass, vrel,
                                                    angularTerm, powers);
  if constexpr (kFriction) {
    // d_ci × F with d_ci = a_i n; for j: (-a_j n) × (-F) = a_j n × F. The gather rebuilds both
    // torques from n × F and h with the same arithmetic as here.
    r.moment = n.cross(r.force);
    r.overlap = h;
  }
  r.point = p.position[i] + armI * n;
  r.touching = true;
  ++powers.particleContacts;
  return r;
}

/// Candidate k of wall w: the wall is a body of infinite radius and mass (R_ij = R_i,
/// m_ij = m_i) moving with its prescribed velocity.
template <bool kFriction, NormalLaw kLaw, bool kAdvance>
inline ContactResult evaluateWall(const ContactConstants& c, const Particles& p,
                                  NeighbourList& list, const Wall& wall, std::size_t w,
                                  std::size_t k, ContactPowers& powers) {
  ContactResult r;
  const std::uint32_t i = list.wallParticles[w][k];
  const double distance = (p.position[i] - wall.point).dot(wall.normal);
  const double h = p.radius[i] - distance;
  if (h <= 0.0) {
    if constexpr (kFriction && kAdvance) list.wallHistory[w][k] = TangentialHistory{};
    return r;
  }
  const Vec3 n = -wall.normal;  // from the particle towards the wall
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
  r.force = contactForce<kFriction, kLaw, kAdvance>(c, history, n, h, p.radius[i], p.mass[i], vrel,
                                                    angularTerm, powers);
  if constexpr (kFriction) r.torqueI = arm * n.cross(r.force);
  r.point = p.position[i] + arm * n;
  r.touching = true;
  powers.wallPower += r.force.dot(wall.velocity);
  ++powers.wallContacts;
  return r;
}

void addPowers(ContactPowers& sum, const ContactPowers& part) {
  sum.elasticNormal += part.elasticNormal;
  sum.elasticTangential += part.elasticTangential;
  sum.normalDampingPower += part.normalDampingPower;
  sum.tangentialDampingPower += part.tangentialDampingPower;
  sum.tangentialPower += part.tangentialPower;
  sum.stiffnessWork += part.stiffnessWork;
  sum.wallPower += part.wallPower;
  sum.particleContacts += part.particleContacts;
  sum.wallContacts += part.wallContacts;
  sum.tangentialEvaluations += part.tangentialEvaluations;
}

// ---- 2. The hot pass ----------------------------------------------------------------------

/// Contacts per block: the unit of work and of the ordered power sums. Fixed, so the sums do
/// not depend on the thread count.
constexpr std::size_t kBlock = 512;

template <bool kFriction, NormalLaw kLaw>
void parallelPass(SimulationState& s, double dt) {
  const ContactConstants c = constantsOf(s.config, dt);
  const Particles& p = s.particles;
  NeighbourList& list = s.neighbours;
  ContactScratch& out = s.contactScratch;
  const std::size_t pairs = list.first.size(), n = p.size();
  const int threads = s.config.threads > 0 ? s.config.threads : omp_get_max_threads();

  // (a) Pair forces into their slots.
  resizeScratch(out.pairForce, pairs);
  if constexpr (kFriction) {
    resizeScratch(out.pairMoment, pairs);
    resizeScratch(out.pairOverlap, pairs);
  }
  const std::size_t pairBlocks = (pairs + kBlock - 1) / kBlock;
  out.blockPowers.assign(pairBlocks, ContactPowers{});
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t b = 0; b < pairBlocks; ++b) {
    // A local sum: the compiler keeps it in registers (the output arrays are doubles too, so a
    // sum in memory would be reloaded after every store for fear of aliasing).
    ContactPowers powers;
    const std::size_t end = std::min(pairs, (b + 1) * kBlock);
    for (std::size_t k = b * kBlock; k < end; ++k) {
      const ContactResult r = evaluatePair<kFriction, kLaw, true>(c, p, list, k, powers);
      out.pairForce[k] = r.force;
      if constexpr (kFriction) {
        out.pairMoment[k] = r.moment;
        out.pairOverlap[k] = r.overlap;
      }
    }
    out.blockPowers[b] = powers;
  }
  // Wall contacts (few: one block per wall), in their own slots.
  ContactPowers powers;
  for (const ContactPowers& part : out.blockPowers) addPowers(powers, part);
  out.wallForce.resize(s.walls.size());
  out.wallTorque.resize(s.walls.size());
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    const std::size_t m = list.wallParticles[w].size();
    out.wallForce[w].resize(m);
    if constexpr (kFriction) out.wallTorque[w].resize(m);
    Vec3 reaction = Vec3::Zero();
    for (std::size_t k = 0; k < m; ++k) {
      const ContactResult r =
          evaluateWall<kFriction, kLaw, true>(c, p, list, s.walls[w], w, k, powers);
      out.wallForce[w][k] = r.force;
      if constexpr (kFriction) out.wallTorque[w][k] = r.torqueI;
      reaction -= r.force;
    }
    s.walls[w].reaction = reaction;
  }
  s.powers = powers;

  // (b) Each particle gathers its contacts in a fixed order.
  const ContactIndex& index = list.index;
  s.force.resize(n);
  if constexpr (kFriction) s.torque.resize(n);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 f = Vec3::Zero(), t = Vec3::Zero();
    const double radius = p.radius[i];
    for (std::uint32_t k = index.firstStart[i]; k < index.firstStart[i + 1]; ++k) {
      f += out.pairForce[k];
      if constexpr (kFriction) t += (radius - 0.5 * out.pairOverlap[k]) * out.pairMoment[k];
    }
    for (std::uint32_t e = index.secondStart[i]; e < index.secondStart[i + 1]; ++e) {
      const std::uint32_t k = index.secondPairs[e];
      f -= out.pairForce[k];
      if constexpr (kFriction) t += (radius - 0.5 * out.pairOverlap[k]) * out.pairMoment[k];
    }
    for (std::uint32_t e = index.wallStart[i]; e < index.wallStart[i + 1]; ++e) {
      const auto [w, k] = index.wallContacts[e];
      f += out.wallForce[w][k];
      if constexpr (kFriction) t += out.wallTorque[w][k];
    }
    s.force[i] = f;
    if constexpr (kFriction) s.torque[i] = t;
  }
}

// ---- 3. The measuring pass ----------------------------------------------------------------

/// Every contact at the current state, serially and without advancing any spring: forces go to
/// `force`, and `visit(i, other, point, F)` sees each contact once.
template <bool kFriction, NormalLaw kLaw, class Visitor>
void measuringPass(const SimulationState& state, std::vector<Vec3>& force, Visitor&& visit) {
  // Without advancing, the evaluations only read the list: casting away const is safe here.
  auto& s = const_cast<SimulationState&>(state);
  const ContactConstants c = constantsOf(s.config, s.config.timeStep);
  const Particles& p = s.particles;
  ContactPowers powers;
  force.assign(p.size(), Vec3::Zero());
  for (std::size_t k = 0; k < s.neighbours.first.size(); ++k) {
    const ContactResult r = evaluatePair<kFriction, kLaw, false>(c, p, s.neighbours, k, powers);
    if (!r.touching) continue;
    const std::uint32_t i = s.neighbours.first[k], j = s.neighbours.second[k];
    force[i] += r.force;
    force[j] -= r.force;
    visit(i, static_cast<long>(j), r.point, r.force);
  }
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    for (std::size_t k = 0; k < s.neighbours.wallParticles[w].size(); ++k) {
      const ContactResult r =
          evaluateWall<kFriction, kLaw, false>(c, p, s.neighbours, s.walls[w], w, k, powers);
      if (!r.touching) continue;
      const std::uint32_t i = s.neighbours.wallParticles[w][k];
      force[i] += r.force;
      visit(i, -static_cast<long>(w) - 1, r.point, r.force);
    }
  }
}

// ---- 4. Dispatch --------------------------------------------------------------------------

template <class F>
void withLaw(const SimulationState& s, F&& f) {
  const bool hertz = s.config.material.normalLaw == NormalLaw::Hertz;
  if (s.frictional) {
    hertz ? f.template operator()<true, NormalLaw::Hertz>()
          : f.template operator()<true, NormalLaw::Hooke>();
  } else {
    hertz ? f.template operator()<false, NormalLaw::Hertz>()
          : f.template operator()<false, NormalLaw::Hooke>();
  }
}

}  // namespace

void computeContactForces(SimulationState& s, double dt) {
  withLaw(s, [&]<bool kFriction, NormalLaw kLaw>() { parallelPass<kFriction, kLaw>(s, dt); });
}

void visitContacts(const SimulationState& s, const std::function<void(const ContactView&)>& visit,
                   std::vector<Vec3>* netForce) {
  std::vector<Vec3> force;
  auto each = [&](std::uint32_t i, long other, const Vec3& point, const Vec3& f) {
    if (!visit) return;
    visit(ContactView{i, other, point, f});
    if (other >= 0) visit(ContactView{static_cast<std::size_t>(other), i, point, -f});
  };
  withLaw(
      s, [&]<bool kFriction, NormalLaw kLaw>() { measuringPass<kFriction, kLaw>(s, force, each); });
  if (netForce) *netForce = std::move(force);
}

}  // namespace granular
