#pragma once
/// The contact law of docs/physics.md §1 (Eqs. 3-5), composed of the contact model's terms
/// (granular/contact_terms/), evaluated for a chunk of contacts at once.
///
/// Why chunks: the law is a chain of square roots and divisions (distance, normal, reduced
/// radius and mass, the spring's rotation, k_t ∝ √(R h), the Coulomb scaling) with
/// data-dependent branches (sliding or sticking, a spring or none). One contact at a time, the
/// CPU waits on those latencies and mispredicts the branches. Here the force pass copies the
/// touching contacts of a chunk of candidates into arrays (`ContactChunk`), and two branch-free
/// loops over the arrays compute the geometry and the law for several contacts per instruction
/// (2 with SSE2, 4 with AVX2). Every operation is
/// an IEEE operation on one lane (no reductions inside the loops, no fused multiply-add:
/// -ffp-contract=off), so the results are the same bits whatever vector width the compiler
/// picks, and the same as one contact at a time would give. Every operation is done for every
/// lane and the unwanted results are dropped by a select (`cond ? a : b` of two computed
/// values): a division or root under a condition would be a branch (it might trap), and a
/// branch stops the vectoriser.
///
/// Particle pairs and particle-wall contacts share `contactLaw`; only the geometry differs (a
/// wall is a body of infinite radius and mass moving with its prescribed velocity).
#include <cstddef>
#include <cstdint>

#include "granular/contact_model.hpp"
#include "simulation_state.hpp"

namespace granular {

/// Constants of the law for a scene, computed once.
struct ContactConstants {
  double normalCoefficient;      ///< (2/3) E/(1-ν²) [Pa]
  double tangentialCoefficient;  ///< (8/3) G/(2-ν) [Pa]
  double tangentialStiffness;    ///< k_t of the constant law; 0: Mindlin's, from the above [N/m]
  double normalDamping;          ///< γn [1/s]
  double tangentialDamping;      ///< γt [1/s]
  double friction;               ///< μ [-]
  double dt;                     ///< [s]
  double normalForceFloor;       ///< 0 (no pull: F_n = max(0, ·)) or −∞ (Material::noPull) [N]
};

/// Contacts per chunk: 64 fill the arrays below with ≈ 27 KB, about what an L1 data cache holds
/// (32-48 KB), and give the loops long enough runs of vector instructions.
constexpr std::size_t kChunk = 64;

/// One chunk of contacts as arrays (one entry per contact). Inputs are filled by the caller
/// (pairs: the raw columns then `pairGeometry`; walls: the geometry directly); `contactLaw`
/// fills the outputs and, when it advances, the new spring.
struct ContactChunk {
  std::uint32_t slot[kChunk];    ///< the contact's index in the list it came from
  std::uint32_t first[kChunk];   ///< pairs: the first particle i
  std::uint32_t second[kChunk];  ///< pairs: the second particle j
  std::uint32_t wall[kChunk];    ///< wall contacts: the wall
  // Raw pair data (pairGeometry's input): centre offset x_j - x_i, radii, masses, angular
  // velocities.
  alignas(64) double dx[kChunk], dy[kChunk], dz[kChunk];
  alignas(64) double ri[kChunk], rj[kChunk], mi[kChunk], mj[kChunk];
  alignas(64) double wix[kChunk], wiy[kChunk], wiz[kChunk], wjx[kChunk], wjy[kChunk], wjz[kChunk];
  // Geometry (contactLaw's input); every contact in a chunk touches.
  alignas(64) double nx[kChunk], ny[kChunk], nz[kChunk];  ///< unit normal from i to the other
  alignas(64) double overlap[kChunk];                     ///< h [m]
  alignas(64) double armI[kChunk];                        ///< lever arm R_i - h/2 [m]
  alignas(64) double armJ[kChunk];  ///< pairs with friction: lever arm R_j - h/2 [m]
  alignas(64) double radius[kChunk], mass[kChunk];        ///< R_ij [m], m_ij [kg]
  alignas(64) double vx[kChunk], vy[kChunk], vz[kChunk];  ///< v_i - v_other [m/s]
  alignas(64) double cx[kChunk], cy[kChunk], cz[kChunk];  ///< contact-point velocity [m/s]
  // Tangential spring: the stored one in, the advanced one out.
  alignas(64) double sx[kChunk], sy[kChunk], sz[kChunk], stiffness[kChunk];
  // Between the law's two loops (friction only): trial tangential force [N], tangential
  // velocity [m/s], k_t [N/m], Coulomb limit μ F_n [N].
  alignas(64) double tx[kChunk], ty[kChunk], tz[kChunk];
  alignas(64) double vtx[kChunk], vty[kChunk], vtz[kChunk];
  alignas(64) double kt[kChunk], limit[kChunk];
  // Outputs: force on i [N], n × F [N] (friction only), and this contact's share of each power.
  alignas(64) double fx[kChunk], fy[kChunk], fz[kChunk];
  alignas(64) double mx[kChunk], my[kChunk], mz[kChunk];
  alignas(64) double elasticNormal[kChunk], normalDampingPower[kChunk];
  alignas(64) double elasticTangential[kChunk], tangentialDampingPower[kChunk];
  alignas(64) double tangentialPower[kChunk], stiffnessWork[kChunk];
};

/// Pair geometry from the raw columns dx..mj of touching pairs (and the angular velocities with
/// friction; v is already v_i - v_j): n, h, lever arm, R_ij, m_ij, contact-point velocity.
/// Coincident centres have no direction: +z is used, so the particles are pushed apart along a
/// defined axis instead of producing NaN.
template <bool kFriction>
[[gnu::always_inline]] inline void pairGeometry(ContactChunk& c, std::size_t count) {
#pragma omp simd
  for (std::size_t k = 0; k < count; ++k) {
    const double d2 = c.dx[k] * c.dx[k] + c.dy[k] * c.dy[k] + c.dz[k] * c.dz[k];
    const double reach = c.ri[k] + c.rj[k];
    const double distance = std::sqrt(d2);
    const bool apart = distance > 0.0;
    const double nx = apart ? c.dx[k] / (apart ? distance : 1.0) : 0.0;
    const double ny = apart ? c.dy[k] / (apart ? distance : 1.0) : 0.0;
    const double nz = apart ? c.dz[k] / (apart ? distance : 1.0) : 1.0;
    const double h = reach - distance;
    const double armI = c.ri[k] - 0.5 * h;
    c.nx[k] = nx;
    c.ny[k] = ny;
    c.nz[k] = nz;
    c.overlap[k] = h;
    c.armI[k] = armI;
    c.radius[k] = c.ri[k] * c.rj[k] / reach;
    c.mass[k] = c.mi[k] * c.mj[k] / (c.mi[k] + c.mj[k]);
    if constexpr (kFriction) {
      // Contact-point velocity of i relative to j: v_i - v_j + (a_i ω_i + a_j ω_j) × n.
      const double armJ = c.rj[k] - 0.5 * h;
      c.armJ[k] = armJ;
      const double ax = armI * c.wix[k] + armJ * c.wjx[k];
      const double ay = armI * c.wiy[k] + armJ * c.wjy[k];
      const double az = armI * c.wiz[k] + armJ * c.wjz[k];
      c.cx[k] = c.vx[k] + (ay * nz - az * ny);
      c.cy[k] = c.vy[k] + (az * nx - ax * nz);
      c.cz[k] = c.vz[k] + (ax * ny - ay * nx);
    }
  }
}

/// F_ij of Eq. (5) for every contact of the chunk, with n pointing from i to the other body,
/// composed of the contact model's terms (granular/contact_terms/): the normal elastic law and
/// dashpot (clamped at zero unless the scene allows a pull), and with friction the tangential
/// spring and dashpot capped at μ |F_n|. With kAdvance the spring is advanced by v_t Δt and
/// written back; without, the force is evaluated for the stored spring (measurements between
/// steps). The terms are inline functions on one lane: the composition is fixed at compile
/// time, and a frictionless scene's build has no tangential code at all.
template <bool kFriction, NormalLaw kLaw, bool kAdvance>
[[gnu::always_inline]] inline void contactLaw(const ContactConstants& constants, ContactChunk& c,
                                              std::size_t count) {
  // Two loops rather than one: each iteration's chain of roots and divisions is long (the
  // spring's rotation, k_t, then the Coulomb scaling), and with the loop split the CPU overlaps
  // more contacts' chains.
#pragma omp simd
  for (std::size_t k = 0; k < count; ++k) {
    const double h = c.overlap[k], nx = c.nx[k], ny = c.ny[k], nz = c.nz[k];
    const double radius = c.radius[k], mass = c.mass[k];
    double fe, stored;
    NormalElastic::force<kLaw>(constants.normalCoefficient, radius, h, fe, stored);
    const double rate = c.vx[k] * nx + c.vy[k] * ny + c.vz[k] * nz;  // ḣ
    double fn, dashpot;
    NormalDamping::force(constants.normalDamping, constants.normalForceFloor, mass, fe, rate, fn,
                         dashpot);
    c.fx[k] = -fn * nx;
    c.fy[k] = -fn * ny;
    c.fz[k] = -fn * nz;
    c.elasticNormal[k] = stored;
    c.normalDampingPower[k] = dashpot;
    if constexpr (kFriction) {
      const double cn = c.cx[k] * nx + c.cy[k] * ny + c.cz[k] * nz;
      const double vtx = c.cx[k] - cn * nx, vty = c.cy[k] - cn * ny, vtz = c.cz[k] - cn * nz;
      double sx = c.sx[k], sy = c.sy[k], sz = c.sz[k];
      const double length2 = TangentialSpring::turnAndAdvance<kAdvance>(nx, ny, nz, vtx, vty, vtz,
                                                                        constants.dt, sx, sy, sz);
      const double kt = TangentialSpring::stiffness(constants.tangentialCoefficient,
                                                    constants.tangentialStiffness, radius, h);
      c.stiffnessWork[k] = kAdvance ? 0.5 * (kt - c.stiffness[k]) * length2 : 0.0;
      // The trial force, before the Coulomb cap: the spring's, then the dashpot's.
      double tx = -kt * sx, ty = -kt * sy, tz = -kt * sz;
      c.tangentialDampingPower[k] =
          TangentialDamping::addForce(constants.tangentialDamping, mass, vtx, vty, vtz, tx, ty, tz);
      c.tx[k] = tx;
      c.ty[k] = ty;
      c.tz[k] = tz;
      c.sx[k] = sx;
      c.sy[k] = sy;
      c.sz[k] = sz;
      c.vtx[k] = vtx;
      c.vty[k] = vty;
      c.vtz[k] = vtz;
      c.kt[k] = kt;
      c.limit[k] = constants.friction * std::abs(fn);  // μ |F_n|: F_n < 0 only with a pull
    }
  }
  if constexpr (kFriction) {
#pragma omp simd
    for (std::size_t k = 0; k < count; ++k) {
      double tx = c.tx[k], ty = c.ty[k], tz = c.tz[k];
      double sx = c.sx[k], sy = c.sy[k], sz = c.sz[k];
      const double kt = c.kt[k];
      const bool sliding = TangentialSpring::cap(c.limit[k], kt, tx, ty, tz, sx, sy, sz);
      const double dampingPower = c.tangentialDampingPower[k];
      c.tangentialDampingPower[k] = sliding ? 0.0 : dampingPower;  // sticking only
      c.tangentialPower[k] = tx * c.vtx[k] + ty * c.vty[k] + tz * c.vtz[k];
      c.elasticTangential[k] = 0.5 * kt * (sx * sx + sy * sy + sz * sz);
      if constexpr (kAdvance) {
        c.sx[k] = sx;
        c.sy[k] = sy;
        c.sz[k] = sz;
        c.stiffness[k] = kt;
      }
      const double fx = c.fx[k] + tx, fy = c.fy[k] + ty, fz = c.fz[k] + tz;
      c.fx[k] = fx;
      c.fy[k] = fy;
      c.fz[k] = fz;
      // n × F: the torques' common factor (d_ci × F with d_ci = a_i n).
      const double nx = c.nx[k], ny = c.ny[k], nz = c.nz[k];
      c.mx[k] = ny * fz - nz * fy;
      c.my[k] = nz * fx - nx * fz;
      c.mz[k] = nx * fy - ny * fx;
    }
  }
}

}  // namespace granular
