#pragma once
/// Rolling resistance, the elastic–plastic spring–dashpot ("EPSD", type C) model of Ai, Chen,
/// Rotter & Ooi, Powder Technology 206 (2011) 269–282 (docs/physics.md §2.13): on i (its
/// opposite on the other body) the spring torque −k_r θ of the relative rotation θ accumulated
/// while the contact lasts (ω_r = the tangential part of ω_i − ω_other), capped at μ_r R_ij F_n,
/// plus the dashpot −C_r ω_r while the spring is below the cap. At the cap the spring is reset so
/// that it carries the cap and the dashpot is off (Ai et al.'s full mobilisation, f = 0): the
/// torque is then exactly μ_r R_ij F_n, and a reset never stretches the spring (capping spring and
/// dashpot together would, and create energy at an impact's fast spin). So a sphere rolls on a
/// plane against the constant torque μ_r R F_n and rests, with no creep, under any torque below it.
///   k_r = β_r μ_r² k_n R_ij² (k_n = dF_n^e/dh at the contact: (2/3)E/(1−ν²) R_ij (Hooke),
///   (3/2) of it × √(h/R_ij) (Hertz); β_r = 2.25 by default, the value Ai et al. use),
///   C_r = 2 η_r √(I_r k_r), I_r = 1/(1/(I_i + m_i R_i²) + 1/(I_j + m_j R_j²)) (the relative
///   rotation's inertia about the contact point; a wall's term is zero).
/// The term acts only where rolling_friction > 0 (optional: other scenes run a build without it)
/// and needs friction (a sphere that cannot stick to the plane slides rather than rolls).
#include <array>
#include <cmath>
#include <cstddef>
#include <tuple>

#include "granular/contact_terms/normal_elastic.hpp"
#include "granular/contact_terms/tangential_spring.hpp"
#include "granular/contact_terms/term.hpp"

namespace granular {

struct RollingResistance {
  static constexpr std::string_view name = "rolling_resistance";

  struct Parameters {
    double rollingFriction = 0.0;    ///< μ_r [-]: the torque's cap is μ_r R_ij F_n; 0: no term
    double rollingStiffness = 2.25;  ///< β_r [-]: k_r = β_r μ_r² k_n R_ij²
    double rollingDamping = 0.3;     ///< η_r [-]: C_r = 2 η_r √(I_r k_r) below the cap
  };
  static constexpr auto parameters = std::tuple{
      NumberParameter<Parameters>{"rolling_friction", "μ_r", "-", ValueRange::closed(0, 1),
                                  "rolling friction: the rolling torque is capped at "
                                  "μ_r R_ij F_n; 0 switches rolling resistance off",
                                  &Parameters::rollingFriction},
      NumberParameter<Parameters>{"rolling_stiffness", "β_r", "-", ValueRange::aboveUpTo(0, 100),
                                  "rolling stiffness k_r = β_r μ_r² k_n R_ij², k_n = dF_n/dh at "
                                  "the contact (β_r μ_r² at most 2.25)",
                                  &Parameters::rollingStiffness},
      NumberParameter<Parameters>{"rolling_damping", "η_r", "-", ValueRange::closed(0, 1),
                                  "rolling damping ratio: C_r = 2 η_r √(I_r k_r) below the cap",
                                  &Parameters::rollingDamping},
  };
  /// Rolling resistance needs friction, and its spring's frequency √(k_r/I_r) stays within
  /// 1.3 √(k_n/m) (the normal law's, which sets the step): β_r μ_r² ≤ 2.25.
  template <class Material>
  static RuleProblem rule(const Material& m) {
    if (m.rollingFriction > 0.0 && !(m.friction > 0.0)) {
      return {"rolling_friction", "needs friction > 0: without it a sphere slides, not rolls"};
    }
    if (m.rollingStiffness * m.rollingFriction * m.rollingFriction > 2.25) {
      return {"rolling_stiffness",
              "needs rolling_stiffness × rolling_friction² <= 2.25, so that the rolling "
              "spring is no faster than the normal contact the step resolves"};
    }
    return {};
  }
  /// Without rolling friction the term is off, and its stiffness and damping with it.
  static std::array<IdleParameter, 2> idle(const Parameters& p) {
    if (p.rollingFriction > 0.0) return {};
    constexpr std::string_view why =
        "applies with rolling_friction > 0 only (rolling_friction = 0 switches rolling "
        "resistance off); remove it, or set rolling_friction";
    return {IdleParameter{"rolling_stiffness", why}, IdleParameter{"rolling_damping", why}};
  }
  /// A scene without rolling friction runs the law's build without this term.
  static bool active(const Parameters& p) { return p.rollingFriction > 0.0; }

  /// Per contact: the relative rotation θ [rad] (three slots, in the current tangent plane) and
  /// k_r at the previous step [N m/rad], for the stiffness-work term.
  static constexpr std::string_view kHistory[] = {"rotation_x", "rotation_y", "rotation_z",
                                                  "stiffness"};
  static constexpr std::span<const std::string_view> history{kHistory};
  static constexpr EnergyTerm kEnergy[] = {
      {"elastic_rolling_J", EnergyKind::Stored, "rolling", "Σ over contacts of ½ k_r |θ|²"},
      {"dissipated_rolling_J", EnergyKind::Dissipated, "rolling",
       "by the rolling dashpot below the cap"},
      {"dissipated_rolling_slip_J", EnergyKind::Slip, "rolling",
       "by rolling at the cap: the rest of the rolling torques' work"},
      {"rolling_stiffness_work_J", EnergyKind::Supplied, "rolling",
       "gained by the rolling spring when k_r (∝ k_n) changes at fixed θ (0 with Hooke)"},
      {"rolling_work_J", EnergyKind::Work, "rolling",
       "work of the capped rolling torque on the relative spin"}};
  static constexpr std::span<const EnergyTerm> energy{kEnergy};
  static constexpr bool needsFriction = true;
  /// The torque is a pure couple: +q on i, −q on the other body (the force pass adds it).
  static constexpr bool pureTorque = true;
  /// It reads the bodies' own spins, radii and masses (the relative spin, I_r).
  static constexpr bool readsBodies = true;
  static constexpr std::string_view stableStep =
      "the half-period π √(I_r/k_r) joins the durations the step must resolve (shorter than the "
      "normal contact's where β_r μ_r² is above about 1.6); its dashpot's rate on a sphere's own "
      "rotation shrinks Gear's interval, so a fixed step of a scene that starts without "
      "contacts is judged at load on the network of a dense bed (denseBedStep)";

  struct Constants {
    double friction;   ///< μ_r
    double stiffness;  ///< β_r μ_r²
    double damping;    ///< 2 η_r
  };
  static Constants constants(const Parameters& p) {
    return {p.rollingFriction, p.rollingStiffness * p.rollingFriction * p.rollingFriction,
            2.0 * p.rollingDamping};
  }

  /// The whole term in the first loop (it needs F_n, which the normal terms have set): the
  /// stored rotation turned (and with kAdvance advanced by ω_r Δt), the spring torque and its
  /// cap, the dashpot below the cap, the torque on i and the energy accounts.
  template <NormalLaw kLaw, bool kAdvance, class ModelConstants, class Chunk>
  [[gnu::always_inline]] static void first(const ModelConstants& k, Chunk& c, std::size_t e,
                                           ContactLane& lane) {
    const Constants& r = k.template of<RollingResistance>();
    const double nx = lane.nx, ny = lane.ny, nz = lane.nz, radius = lane.radius;
    const double wx = c.wix[e] - c.wjx[e], wy = c.wiy[e] - c.wjy[e], wz = c.wiz[e] - c.wjz[e];
    const double wn = wx * nx + wy * ny + wz * nz;
    const double ux = wx - wn * nx, uy = wy - wn * ny, uz = wz - wn * nz;  // ω_r
    const double kr =
        r.stiffness *
        NormalElastic::stiffness<kLaw>(k.template of<NormalElastic>().coefficient, radius, lane.h) *
        radius * radius;
    const double inertiaI = 1.4 * c.mi[e] * c.ri[e] * c.ri[e];  // I + m R² = (7/5) m R²
    const double inertiaJ = 1.4 * c.mj[e] * c.rj[e] * c.rj[e];  // a wall's: infinite
    const double inertia = 1.0 / (1.0 / inertiaI + 1.0 / inertiaJ);
    const double damping = r.damping * std::sqrt(inertia * kr);  // C_r

    double* const txs = c.template history<RollingResistance>(0);
    double* const tys = c.template history<RollingResistance>(1);
    double* const tzs = c.template history<RollingResistance>(2);
    double* const krs = c.template history<RollingResistance>(3);
    double tx = txs[e], ty = tys[e], tz = tzs[e];
    const double length2 =
        TangentialSpring::turnAndAdvance<kAdvance>(nx, ny, nz, ux, uy, uz, k.dt, tx, ty, tz);
    c.template energy<RollingResistance>(3)[e] = kAdvance ? 0.5 * (kr - krs[e]) * length2 : 0.0;
    double sx = -kr * tx, sy = -kr * ty, sz = -kr * tz;  // the spring's torque
    const double limit = r.friction * radius * std::abs(lane.normal);
    const bool rolling = TangentialSpring::cap(limit, kr, sx, sy, sz, tx, ty, tz);
    const double dashpot = rolling ? 0.0 : damping;
    const double qx = sx - dashpot * ux, qy = sy - dashpot * uy, qz = sz - dashpot * uz;
    lane.qx += qx;
    lane.qy += qy;
    lane.qz += qz;
    // The powers on the relative spin plus its lead (term.hpp).
    const double lx = wx + (c.uix[e] - c.ujx[e]), ly = wy + (c.uiy[e] - c.ujy[e]),
                 lz = wz + (c.uiz[e] - c.ujz[e]);
    const double ln = lx * nx + ly * ny + lz * nz;
    c.template energy<RollingResistance>(0)[e] = 0.5 * kr * (tx * tx + ty * ty + tz * tz);
    c.template energy<RollingResistance>(1)[e] =
        dashpot * (ux * (lx - ln * nx) + uy * (ly - ln * ny) + uz * (lz - ln * nz));
    c.template energy<RollingResistance>(4)[e] = qx * lx + qy * ly + qz * lz;
    if constexpr (kAdvance) {
      txs[e] = tx;
      tys[e] = ty;
      tzs[e] = tz;
      krs[e] = kr;
    }
  }

  /// Its spring and dashpot in the network's linearisation (k_r = β_r μ_r² k_n R², C_r), and
  /// the damping ratio of the rolling mode, η_r.
  template <class ModelConstants>
  static void linearise(const ModelConstants& k, LinearContact& c) {
    const Constants& own = k.template of<RollingResistance>();
    const double kr = own.stiffness * c.stiffness.normal * c.radius * c.radius;
    c.stiffness.rolling += kr;
    c.damping.rolling += own.damping * std::sqrt(c.rollingInertia * kr);
    c.leastDampingRatio(0.5 * own.damping);
  }

  /// Why a stored history is not a state this term can have come to (nullptr: it can).
  static const char* historyProblem(const double* slot) {
    for (int k = 0; k < 4; ++k) {
      if (!std::isfinite(slot[k])) return "a rolling spring is not finite";
    }
    return slot[3] >= 0.0 ? nullptr : "a rolling stiffness is negative";
  }
};

}  // namespace granular
