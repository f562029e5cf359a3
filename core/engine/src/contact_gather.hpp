#pragma once
/// Contacts in and out of a chunk (contact_law.hpp): the pipeline gather → law → scatter that
/// the force pass and the measuring pass run for pairs and walls alike (throughLaw), and its
/// stages: picking the touching candidates, loading the bodies' values and stored histories,
/// and reading the results back.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "chunk_kernels.hpp"
#include "pair_springs.hpp"
#include "wall_contact.hpp"

namespace granular {

/// Pairs (the chunk's raw columns, whose geometry the kernel computes) or wall contacts (loaded
/// with their geometry).
enum class ChunkOf { Pairs, Walls };

/// One chunk through the pipeline: `gather(c)` fills it and returns how many contacts it holds,
/// the kernels compute the pairs' geometry and the law (advancing the history with kAdvance),
/// and `scatter(c, m)` takes the results.
template <ChunkOf kOf, bool kFriction, NormalLaw kLaw, unsigned kOptional, bool kAdvance,
          class Gather, class Scatter>
void throughLaw(const ContactConstants& constants, ContactChunk& c, Gather&& gather,
                Scatter&& scatter) {
  const std::size_t m = gather(c);
  if constexpr (kOf == ChunkOf::Pairs) geometry(c, m, kFriction);
  law(constants, c, m, kFriction, kLaw, kAdvance, kOptional);
  scatter(c, m);
}

/// Writes pair k's slot and particles i and j, centre offset x_j - x_i and radii into entry m of
/// the chunk; returns 1 if the spheres touch, else 0 (the entry is then overwritten by the next
/// one). The particles kept in the chunk spare the later loops a load through the slot. In a
/// build with a term that acts beyond touch (kReach), "touch" is within `beyond` of touching.
template <bool kReach>
[[gnu::always_inline]] inline std::size_t pickPair(const Particles& p, const NeighbourList& list,
                                                   std::uint32_t i, std::uint32_t k,
                                                   ContactChunk& c, std::size_t m, double beyond) {
  const std::uint32_t j = list.second[k];
  const Vec3 d = p.position[j] - p.position[i];
  const double ri = p.radius[i], rj = p.radius[j];
  double reach = ri + rj;
  if constexpr (kReach) reach += beyond;
  c.slot[m] = k;
  c.first[m] = i;
  c.second[m] = j;
  c.dx[m] = d.x();
  c.dy[m] = d.y();
  c.dz[m] = d.z();
  c.ri[m] = ri;
  c.rj[m] = rj;
  return d.squaredNorm() < reach * reach ? 1 : 0;
}

/// Picks the touching pairs (kReach: within `beyond` of touching) among the candidates
/// [begin, begin + count) into the chunk (slot,
/// particles, offset and radii; loadPairs adds the rest); returns how many. Branch-free; `rows`
/// walks the list's rows, its next run starting at `begin`.
template <bool kReach>
inline std::size_t pickTouchingPairs(const Particles& p, const NeighbourList& list,
                                     std::size_t begin, std::size_t count, RowWalker& rows,
                                     ContactChunk& c, double beyond) {
  std::uint32_t starts[RowWalker::kMaxRun];
  std::uint32_t i = rows.mark(begin, count, starts);
  std::size_t m = 0;
  for (std::size_t k = begin; k < begin + count; ++k) {
    i += starts[k - begin];
    m += pickPair<kReach>(p, list, i, static_cast<std::uint32_t>(k), c, m, beyond);
  }
  rows.reached(i);
  return m;
}

/// pickTouchingWallContacts for a wall of finite shape: the distance from its closest point.
/// Out of line, so that the planes' path in the force pass stays as small as it was.
template <bool kReach>
[[gnu::noinline]] std::size_t pickTouchingShellContacts(const Particles& p,
                                                        const NeighbourList& list, const Wall& wall,
                                                        std::size_t w, std::size_t begin,
                                                        std::size_t count, ContactChunk& c,
                                                        std::size_t m, double beyond) {
  for (std::size_t k = begin; k < begin + count; ++k) {
    const std::uint32_t i = list.wallParticles[w][k];
    const double distance = touchOf(wall, p.position[i]).distance;
    c.slot[m] = static_cast<std::uint32_t>(k);
    c.wall[m] = static_cast<std::uint32_t>(w);
    if constexpr (kReach) {
      m += p.radius[i] - distance > -beyond ? 1 : 0;
    } else {
      m += p.radius[i] - distance > 0.0 ? 1 : 0;
    }
  }
  return m;
}

/// Appends the touching ones (kReach: within `beyond`) among wall w's candidates
/// [begin, begin + count) to the chunk's m
/// entries (slot: candidate, wall: w); returns the new count. Touching when the overlap
/// R_i - distance is positive (with kReach: above −beyond).
template <bool kReach>
inline std::size_t pickTouchingWallContacts(const Particles& p, const NeighbourList& list,
                                            const Wall& wall, std::size_t w, std::size_t begin,
                                            std::size_t count, ContactChunk& c, std::size_t m,
                                            double beyond) {
  if (wall.shell())
    return pickTouchingShellContacts<kReach>(p, list, wall, w, begin, count, c, m, beyond);
  for (std::size_t k = begin; k < begin + count; ++k) {
    const std::uint32_t i = list.wallParticles[w][k];
    const double distance = (p.position[i] - wall.point).dot(wall.normal);
    c.slot[m] = static_cast<std::uint32_t>(k);
    c.wall[m] = static_cast<std::uint32_t>(w);
    if constexpr (kReach) {
      m += p.radius[i] - distance > -beyond ? 1 : 0;
    } else {
      m += p.radius[i] - distance > 0.0 ? 1 : 0;
    }
  }
  return m;
}

/// Copies a contact's stored history into entry e of the chunk: the slots of the terms the
/// build includes (the others' rows stay untouched, so a scene without an optional term moves no
/// more memory per contact than a model without it).
template <bool kFriction, unsigned kOptional>
inline void loadSpring(const ContactHistory& history, ContactChunk& c, std::size_t e) {
  for (std::size_t k = 0; k < kHistorySlots; ++k) {
    if (kIncludedHistorySlots<kFriction, kOptional>[k]) c.historyRows[k][e] = history.slot[k];
  }
}
/// The same from a stored record (PairSprings: the included slots, in order).
template <bool kFriction, unsigned kOptional>
inline void loadSpring(const double* record, ContactChunk& c, std::size_t e) {
  std::size_t at = 0;
  for (std::size_t k = 0; k < kHistorySlots; ++k) {
    if (kIncludedHistorySlots<kFriction, kOptional>[k]) c.historyRows[k][e] = record[at++];
  }
}

/// The powers' lead of a force pass (ContactChunk::ux). Verlet's force pass reads the
/// half-step velocities v_½ = v + (Δt/2) a; the velocity its forces work on over the step is
/// v + Δt a = v_½ + (Δt/2) a to O(Δt²), a the accelerations of the step before (Derivatives::d2),
/// so its powers take that lead. None for Gear, whose forces act at the predicted velocity
/// itself, nor between steps (the measuring pass reads the step's own velocities).
struct PowerLead {
  const Vec3* accel = nullptr;      ///< the particles' a [m/s²]; null: no lead
  const Vec3* spinAccel = nullptr;  ///< their dω/dt [rad/s²] (friction)
  double half = 0.0;                ///< Δt/2 [s]
};

/// The lead of a force pass over Δt on the state s: Verlet's, where the pass advances (Δt > 0).
inline PowerLead powerLeadOf(const SimulationState& s, double dt) {
  if (s.config.integrator != Integrator::VelocityVerlet || !(dt > 0.0)) return {};
  return {s.translation.d2.data(), s.frictional ? s.rotation.d2.data() : nullptr, 0.5 * dt};
}

/// Writes pair e's lead into the chunk: the centres' (Δt/2)(a_i − a_j) into ux..uz and, with
/// friction, the spins' (Δt/2) α_i and α_j into uix..ujz.
template <bool kFriction>
[[gnu::always_inline]] inline void loadPairLead(const PowerLead& lead, ContactChunk& c,
                                                std::size_t e, std::uint32_t i, std::uint32_t j) {
  const double half = lead.half;
  const Vec3 u = half * (lead.accel[i] - lead.accel[j]);
  c.ux[e] = u.x();
  c.uy[e] = u.y();
  c.uz[e] = u.z();
  if constexpr (kFriction) {
    const Vec3 ui = half * lead.spinAccel[i], uj = half * lead.spinAccel[j];
    c.uix[e] = ui.x();
    c.uiy[e] = ui.y();
    c.uiz[e] = ui.z();
    c.ujx[e] = uj.x();
    c.ujy[e] = uj.y();
    c.ujz[e] = uj.z();
  }
}

/// No lead: zero for the m pairs.
template <bool kFriction>
void zeroPairLeads(ContactChunk& c, std::size_t m) {
  for (double* row : {c.ux, c.uy, c.uz}) std::fill_n(row, m, 0.0);
  if constexpr (kFriction) {
    for (double* row : {c.uix, c.uiy, c.uiz, c.ujx, c.ujy, c.ujz}) std::fill_n(row, m, 0.0);
  }
}

/// Writes the lead of particle i against a wall (which moves at its prescribed velocity) into
/// entry e: the centre's into ux..uz and, with friction, the spin's into uix..uiz (the wall's,
/// ujx..ujz, zero).
template <bool kFriction>
[[gnu::always_inline]] inline void loadWallLead(const PowerLead& lead, ContactChunk& c,
                                                std::size_t e, std::uint32_t i) {
  Vec3 u = Vec3::Zero(), ui = Vec3::Zero();
  if (lead.accel) {
    u = lead.half * lead.accel[i];
    if constexpr (kFriction) ui = lead.half * lead.spinAccel[i];
  }
  c.ux[e] = u.x();
  c.uy[e] = u.y();
  c.uz[e] = u.z();
  if constexpr (kFriction) {
    c.uix[e] = ui.x();
    c.uiy[e] = ui.y();
    c.uiz[e] = ui.z();
    c.ujx[e] = c.ujy[e] = c.ujz[e] = 0.0;
  }
}

/// Completes the m picked pairs in the chunk with masses, velocities, the powers' lead and
/// springs (their geometry is computed next, by the kernel). `springOf(e)` gives entry e's
/// stored spring. kLead: the pass has a lead (else it is zero).
template <bool kFriction, unsigned kOptional, bool kLead, class SpringOf>
void loadPairsOf(const Particles& p, const PowerLead& lead, ContactChunk& c, std::size_t m,
                 SpringOf&& springOf) {
  for (std::size_t e = 0; e < m; ++e) {
    const std::uint32_t i = c.first[e], j = c.second[e];
    const Vec3 v = p.velocity[i] - p.velocity[j];
    c.mi[e] = p.mass[i];
    c.mj[e] = p.mass[j];
    c.vx[e] = v.x();
    c.vy[e] = v.y();
    c.vz[e] = v.z();
    // In the same iteration as the velocities: the loads of both bodies overlap.
    if constexpr (kLead) loadPairLead<kFriction>(lead, c, e, i, j);
    if constexpr (kFriction) {
      const Vec3& wi = p.angularVelocity[i];
      const Vec3& wj = p.angularVelocity[j];
      c.wix[e] = wi.x();
      c.wiy[e] = wi.y();
      c.wiz[e] = wi.z();
      c.wjx[e] = wj.x();
      c.wjy[e] = wj.y();
      c.wjz[e] = wj.z();
      loadSpring<kFriction, kOptional>(springOf(e), c, e);
    }
  }
  if constexpr (!kLead) zeroPairLeads<kFriction>(c, m);
}
/// loadPairsOf with the lead where the pass has one (a test once, outside the loop).
template <bool kFriction, unsigned kOptional, class SpringOf>
void loadPairs(const Particles& p, const PowerLead& lead, ContactChunk& c, std::size_t m,
               SpringOf&& springOf) {
  if (lead.accel) {
    loadPairsOf<kFriction, kOptional, true>(p, lead, c, m, springOf);
  } else {
    loadPairsOf<kFriction, kOptional, false>(p, lead, c, m, springOf);
  }
}

/// A shell's contact with the particle at x (radius r, velocity u): the normal n out of the
/// particle, overlap h, arm and the velocity relative to the wall's material point at the
/// contact, which moves with the wall's translation and turn. Out of line (see above).
[[gnu::noinline]] inline void shellContact(const Wall& wall, const Vec3& x, double r, const Vec3& u,
                                           Vec3& n, double& h, double& arm, Vec3& v) {
  const WallTouch touch = touchOf(wall, x);
  n = -touch.normal;
  h = r - touch.distance;
  arm = r - 0.5 * h;
  v = u - wall.velocityAt(x + arm * n);
}

/// The history of a contact that has none yet.
inline const ContactHistory kNoHistory{};

/// A mesh's contact, its normal and overlap already in the chunk's entry e (pickMeshContacts):
/// the arm and the velocity relative to the mesh's material point at the contact.
[[gnu::noinline]] inline void meshContact(const Wall& wall, const ContactChunk& c, std::size_t e,
                                          const Vec3& x, double r, const Vec3& u, Vec3& n,
                                          double& h, double& arm, Vec3& v) {
  n = Vec3(c.nx[e], c.ny[e], c.nz[e]);
  h = c.overlap[e];
  arm = r - 0.5 * h;
  v = u - wall.velocityAt(x + arm * n);
}

/// Copies the m picked wall contacts into the chunk with their geometry: the wall is a body of
/// infinite radius and mass (R_ij = R_i, m_ij = m_i) moving with its prescribed motion; n
/// points from the particle towards the wall's closest point. In a build with a term that reads the
/// bodies (kReadsBodies) the raw columns get the particle's radius, mass and spin as i's, and the
/// wall's as j's: infinite radius and mass, no spin.
template <bool kFriction, unsigned kOptional>
void loadWallContacts(const Particles& p, const NeighbourList& list, const std::vector<Wall>& walls,
                      const PowerLead& lead, ContactChunk& c, std::size_t m) {
  for (std::size_t e = 0; e < m; ++e) {
    const std::uint32_t k = c.slot[e], w = c.wall[e];
    const Wall& wall = walls[w];
    const std::uint32_t i = list.wallParticles[w][k];
    Vec3 n;
    double h, arm;
    Vec3 v;
    bool fresh = false;  // a mesh's entry that starts a new contact: its spring starts at zero
    if (!wall.shell()) {
      n = -wall.normal;
      h = p.radius[i] - (p.position[i] - wall.point).dot(wall.normal);
      arm = p.radius[i] - 0.5 * h;
      v = p.velocity[i] - wall.velocity;
    } else if (wall.shape != WallShape::Mesh) {
      shellContact(wall, p.position[i], p.radius[i], p.velocity[i], n, h, arm, v);
    } else {
      meshContact(wall, c, e, p.position[i], p.radius[i], p.velocity[i], n, h, arm, v);
      fresh = c.first[e] != 0;
    }
    c.nx[e] = n.x();
    c.ny[e] = n.y();
    c.nz[e] = n.z();
    c.overlap[e] = h;
    c.armI[e] = arm;
    c.radius[e] = p.radius[i];
    c.mass[e] = p.mass[i];
    c.vx[e] = v.x();
    c.vy[e] = v.y();
    c.vz[e] = v.z();
    loadWallLead<kFriction>(lead, c, e, i);
    if constexpr (kFriction) {
      const Vec3 turn = arm * Vec3(c.uix[e], c.uiy[e], c.uiz[e]).cross(n);  // the arm's lead
      c.ux[e] += turn.x();
      c.uy[e] += turn.y();
      c.uz[e] += turn.z();
      const Vec3 contactVelocity = v + arm * p.angularVelocity[i].cross(n);
      c.cx[e] = contactVelocity.x();
      c.cy[e] = contactVelocity.y();
      c.cz[e] = contactVelocity.z();
      loadSpring<kFriction, kOptional>(fresh ? kNoHistory : list.wallHistory[w][k], c, e);
    }
    if constexpr (kReadsBodies<kFriction, kOptional>) {
      constexpr double kInfinite = std::numeric_limits<double>::infinity();
      if constexpr (kFriction) {
        const Vec3& wi = p.angularVelocity[i];
        c.wix[e] = wi.x();
        c.wiy[e] = wi.y();
        c.wiz[e] = wi.z();
        c.wjx[e] = c.wjy[e] = c.wjz[e] = 0.0;
      }
      c.ri[e] = p.radius[i];
      c.mi[e] = p.mass[i];
      c.rj[e] = c.mj[e] = kInfinite;
    }
  }
}

inline Vec3 forceOf(const ContactChunk& c, std::size_t e) {
  return {c.fx[e], c.fy[e], c.fz[e]};
}
/// A term's pure torque on i of the chunk's entry e (kPureTorque; −it on the other body).
[[maybe_unused]] inline Vec3 pureTorqueOf(const ContactChunk& c, std::size_t e) {
  return {c.qx[e], c.qy[e], c.qz[e]};
}
inline Vec3 normalOf(const ContactChunk& c, std::size_t e) {
  return {c.nx[e], c.ny[e], c.nz[e]};
}

template <unsigned kOptional>
inline void storeRecord(const ContactChunk& c, std::size_t e, double* record) {
  std::size_t at = 0;
  for (std::size_t k = 0; k < kHistorySlots; ++k) {
    if (kIncludedHistorySlots<true, kOptional>[k]) record[at++] = c.historyRows[k][e];
  }
}

/// The advanced history of the chunk's entry e (zero in the slots of terms the build leaves out).
template <bool kFriction, unsigned kOptional>
inline ContactHistory springOf(const ContactChunk& c, std::size_t e) {
  ContactHistory history;
  for (std::size_t k = 0; k < kHistorySlots; ++k) {
    if (kIncludedHistorySlots<kFriction, kOptional>[k]) history.slot[k] = c.historyRows[k][e];
  }
  return history;
}

}  // namespace granular
