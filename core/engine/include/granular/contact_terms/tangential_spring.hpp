#pragma once
/// Tangential spring with history and the Coulomb cap (docs/physics.md §1, Eqs. (4)-(5)): the
/// force −k_t ξ of the stretch ξ accumulated while the contact lasts, capped at μ |F_n|, with the
/// paper's k_t = (8/3) G √(R h)/(2−ν) (Mindlin's, the default) or a constant k_t (the
/// linear-history spring of other codes, for comparison). The stored stretch is first turned
/// into the current tangent plane keeping its length (the contact frame turns with the particles;
/// the stretch does not grow or shrink by it); while sliding it is reset so that the spring alone
/// carries the cap.
#include <array>
#include <cmath>
#include <cstddef>
#include <tuple>

#include "granular/contact_terms/normal_elastic.hpp"
#include "granular/contact_terms/term.hpp"

namespace granular {

/// How k_t depends on the contact: Mindlin's (8/3) G/(2−ν) √(R h), the paper's, or a constant.
enum class TangentialLaw { Mindlin, Constant };

struct TangentialSpring {
  static constexpr std::string_view name = "tangential_spring";
  static constexpr std::string_view kLawNames[] = {"mindlin", "constant"};

  struct Parameters {
    double friction = 0.0;         ///< Coulomb friction coefficient μ [-], particles and walls
    double shearModulus = 0.11e6;  ///< shear modulus G [Pa]
    TangentialLaw tangentialLaw = TangentialLaw::Mindlin;  ///< how k_t depends on the contact
    /// k_t of the constant law [N/m]; 0 (unset) is refused with it and friction; Mindlin's
    /// ignores it.
    double tangentialStiffness = 0.0;

    /// True when the tangential force can be non-zero: the Coulomb cap μ|F_n| is then positive.
    /// With μ = 0 the tangential force is min(|F_st|, 0) = 0 whatever γt is, so the scene needs
    /// neither tangential history nor rotations.
    bool hasFriction() const { return friction > 0.0; }
  };
  static constexpr auto parameters = std::tuple{
      NumberParameter<Parameters>{"friction", "μ", "-", ValueRange::closed(0, 10),
                                  "Coulomb coefficient, particles and walls; 0 switches "
                                  "tangential forces and rotations off",
                                  &Parameters::friction},
      NumberParameter<Parameters>{"shear_modulus", "G", "Pa", ValueRange::aboveUpTo(0, 1e12),
                                  "shear modulus", &Parameters::shearModulus},
      ChoiceParameter<Parameters, TangentialLaw>{
          "tangential_law", "k_t", kLawNames,
          "k_t = (8/3)G/(2−ν)·√(R h) (mindlin, the paper's) or tangential_stiffness (constant)",
          &Parameters::tangentialLaw},
      NumberParameter<Parameters>{"tangential_stiffness", "k_t", "N/m", ValueRange::closed(0, 1e12),
                                  "k_t of the constant law (needed by it, > 0; unused by mindlin)",
                                  &Parameters::tangentialStiffness},
  };
  /// With friction, the constant law has no k_t without tangential_stiffness: refused rather
  /// than read as 0 (which would switch the spring off) or as Mindlin's. Without friction the
  /// spring acts on nothing, as γt does (requireStableTangentialDamping).
  static RuleProblem rule(const Parameters& p) {
    if (p.hasFriction() && p.tangentialLaw == TangentialLaw::Constant &&
        !(p.tangentialStiffness > 0.0)) {
      return {"tangential_law", "needs tangential_stiffness > 0 N/m, the constant law's k_t"};
    }
    return {};
  }
  /// Mindlin's k_t comes from G and the overlap: a tangential_stiffness beside it is a setting
  /// the run would silently ignore.
  static std::array<IdleParameter, 1> idle(const Parameters& p) {
    if (p.tangentialLaw == TangentialLaw::Constant) return {};
    return {IdleParameter{"tangential_stiffness",
                          "applies to tangential_law = \"constant\" only (Mindlin's k_t follows "
                          "from shear_modulus and the overlap); remove it, or set "
                          "tangential_law = \"constant\""}};
  }
  /// Per contact: the stretch ξ [m] (three slots, in the current tangent plane) and k_t at the
  /// previous step [N/m], for the stiffness-work term.
  static constexpr std::string_view kHistory[] = {"stretch_x", "stretch_y", "stretch_z",
                                                  "stiffness"};
  static constexpr std::span<const std::string_view> history{kHistory};
  static constexpr EnergyTerm kEnergy[] = {
      {"elastic_tangential_J", EnergyKind::Stored, "tangential", "Σ over contacts of ½ k_t |ξ|²"},
      {"dissipated_friction_J", EnergyKind::Slip, "tangential",
       "by Coulomb sliding: the rest of the tangential forces' work"},
      {"tangential_stiffness_work_J", EnergyKind::Supplied, "tangential",
       "gained by the spring when k_t ∝ √(R h) changes at fixed ξ (the Mindlin-type spring is "
       "not conservative; 0 with a constant k_t)"},
      {"tangential_work_J", EnergyKind::Work, "tangential",
       "work of the capped tangential force on the contact points' relative motion"}};
  static constexpr std::span<const EnergyTerm> energy{kEnergy};
  static constexpr bool needsFriction = true;
  static constexpr std::string_view stableStep =
      "mindlin: k_t <= k_n, covered by the normal law's duration; constant: the half-period "
      "π √(m_ij/(3.5 k_t)) of a sticking contact joins the durations the step must resolve";

  struct Constants {
    double coefficient;  ///< (8/3) G/(2−ν) of Mindlin's k_t [Pa]
    double stiffness;    ///< k_t of the constant law; 0: Mindlin's [N/m]
    double friction;     ///< μ [-]
  };
  template <class Material>
  static Constants constants(const Material& m) {
    return {m.tangentialCoefficient(),
            m.tangentialLaw == TangentialLaw::Constant ? m.tangentialStiffness : 0.0, m.friction};
  }
  /// Per contact between the law's loops: k_t [N/m] and the Coulomb limit μ|F_n| [N].
  static constexpr std::string_view kBetweenLoops[] = {"stiffness", "limit"};
  static constexpr std::span<const std::string_view> betweenLoops{kBetweenLoops};

  /// First loop: the contact points' tangential velocity, the stored stretch turned (and with
  /// kAdvance advanced), k_t, the stiffness work, and the trial force −k_t ξ.
  template <NormalLaw kLaw, bool kAdvance, class ModelConstants, class Chunk>
  [[gnu::always_inline]] static void first(const ModelConstants& k, Chunk& c, std::size_t e,
                                           ContactLane& lane) {
    const Constants& own = k.template of<TangentialSpring>();
    const double nx = lane.nx, ny = lane.ny, nz = lane.nz;
    const double cn = c.cx[e] * nx + c.cy[e] * ny + c.cz[e] * nz;
    const double vtx = c.cx[e] - cn * nx, vty = c.cy[e] - cn * ny, vtz = c.cz[e] - cn * nz;
    double* const sxs = c.template history<TangentialSpring>(0);
    double* const sys = c.template history<TangentialSpring>(1);
    double* const szs = c.template history<TangentialSpring>(2);
    double* const kts = c.template history<TangentialSpring>(3);
    double sx = sxs[e], sy = sys[e], sz = szs[e];
    const double length2 = turnAndAdvance<kAdvance>(nx, ny, nz, vtx, vty, vtz, k.dt, sx, sy, sz);
    const double kt = stiffness(own.coefficient, own.stiffness, lane.radius, lane.h);
    c.template energy<TangentialSpring>(2)[e] = kAdvance ? 0.5 * (kt - kts[e]) * length2 : 0.0;
    lane.tx += -kt * sx;
    lane.ty += -kt * sy;
    lane.tz += -kt * sz;
    lane.vtx = vtx;
    lane.vty = vty;
    lane.vtz = vtz;
    sxs[e] = sx;
    sys[e] = sy;
    szs[e] = sz;
    c.template between<TangentialSpring>(0)[e] = kt;
    // μ |F_n|: F_n < 0 only with a pull.
    c.template between<TangentialSpring>(1)[e] = own.friction * std::abs(lane.normal);
  }

  /// Second loop: the Coulomb cap on the trial force (spring and dashpot), the spring reset
  /// while sliding, the work of the capped force and the energy the spring stores.
  template <bool kAdvance, class Constants, class Chunk>
  [[gnu::always_inline]] static void second(const Constants&, Chunk& c, std::size_t e,
                                            ContactLane& lane) {
    double* const sxs = c.template history<TangentialSpring>(0);
    double* const sys = c.template history<TangentialSpring>(1);
    double* const szs = c.template history<TangentialSpring>(2);
    double sx = sxs[e], sy = sys[e], sz = szs[e];
    const double kt = c.template between<TangentialSpring>(0)[e];
    const double limit = c.template between<TangentialSpring>(1)[e];
    lane.sliding = cap(limit, kt, lane.tx, lane.ty, lane.tz, sx, sy, sz);
    double ux, uy, uz;  // the powers' lead
    leadTangential(c, e, lane, ux, uy, uz);
    c.template energy<TangentialSpring>(3)[e] =
        lane.tx * (lane.vtx + ux) + lane.ty * (lane.vty + uy) + lane.tz * (lane.vtz + uz);
    c.template energy<TangentialSpring>(0)[e] = 0.5 * kt * (sx * sx + sy * sy + sz * sz);
    if constexpr (kAdvance) {
      sxs[e] = sx;
      sys[e] = sy;
      szs[e] = sz;
      c.template history<TangentialSpring>(3)[e] = kt;
    }
  }

  /// Its spring in the network's linearisation: k_t at the contact points.
  template <class ModelConstants>
  static void linearise(const ModelConstants& k, LinearContact& c) {
    const Constants& own = k.template of<TangentialSpring>();
    c.stiffness.tangential += stiffness(own.coefficient, own.stiffness, c.radius, c.overlap);
  }

  /// Why a stored history is not a state this term can have come to (nullptr: it can).
  static const char* historyProblem(const double* slot) {
    for (int k = 0; k < 4; ++k) {
      if (!std::isfinite(slot[k])) return "a tangential spring is not finite";
    }
    return slot[3] >= 0.0 ? nullptr : "a tangential stiffness is negative";
  }

  /// k_t [N/m]: `constant` when positive (the constant law), else Mindlin's
  /// (8/3) G/(2−ν) √(R h) (coefficient: (8/3) G/(2−ν)). A select of two computed values, not a
  /// branch, so that the contact loops stay vector code; Mindlin's value is the same bits as
  /// without the constant law.
  [[gnu::always_inline]] static double stiffness(double coefficient, double constant, double radius,
                                                 double h) {
    const double mindlin = coefficient * std::sqrt(radius * h);
    return constant > 0.0 ? constant : mindlin;
  }

  /// The stored stretch s turned into the tangent plane of n keeping its length; with kAdvance
  /// advanced by v_t Δt. Returns |s|² before the turn (the stored spring's energy is ½ k |s|²).
  template <bool kAdvance>
  [[gnu::always_inline]] static double turnAndAdvance(double nx, double ny, double nz, double vtx,
                                                      double vty, double vtz, double dt, double& sx,
                                                      double& sy, double& sz) {
    const double length2 = sx * sx + sy * sy + sz * sz;
    const double sn = sx * nx + sy * ny + sz * nz;
    sx -= sn * nx;
    sy -= sn * ny;
    sz -= sn * nz;
    const double projected2 = sx * sx + sy * sy + sz * sz;
    const double ratio = std::sqrt(length2 / (projected2 > 0.0 ? projected2 : 1.0));
    const double turn = projected2 > 0.0 ? ratio : 0.0;
    sx *= turn;
    sy *= turn;
    sz *= turn;
    if constexpr (kAdvance) {
      sx += vtx * dt;
      sy += vty * dt;
      sz += vtz * dt;
    }
    return length2;
  }

  /// The trial force caps at `limit` = μ|F_n|: returns true when it slides, t then scaled to
  /// the cap and s reset so that the spring alone carries it (s = −t/k_t).
  [[gnu::always_inline]] static bool cap(double limit, double kt, double& tx, double& ty,
                                         double& tz, double& sx, double& sy, double& sz) {
    const double ft2 = tx * tx + ty * ty + tz * tz;
    const bool sliding = ft2 > limit * limit;
    // Branch-free: every lane computes both, a select keeps one (contact_law.hpp).
    const double scaled = limit / std::sqrt(sliding ? ft2 : 1.0);
    const double factor = sliding ? scaled : 1.0;
    tx *= factor;
    ty *= factor;
    tz *= factor;
    const double inverse = 1.0 / (kt > 0.0 ? kt : 1.0);
    const double compliance = kt > 0.0 ? inverse : 0.0;
    sx = sliding ? -tx * compliance : sx;
    sy = sliding ? -ty * compliance : sy;
    sz = sliding ? -tz * compliance : sz;
    return sliding;
  }
};

}  // namespace granular
