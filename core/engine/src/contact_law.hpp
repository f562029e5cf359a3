#pragma once
/// The contact law of docs/physics.md §1 (Eqs. 3-5), composed of the contact model's terms
/// (granular/contact_terms/), evaluated for a chunk of contacts at once.
///
/// Why chunks: the law is a chain of square roots and divisions (distance, normal, reduced
/// radius and mass, the spring's rotation, k_t ∝ √(R h), the Coulomb scaling) with
/// data-dependent branches (sliding or sticking, a spring or none). One contact at a time, the
/// CPU waits on those latencies and mispredicts the branches. Here the force pass copies the
/// interacting contacts of a chunk of candidates (touching, or within a term's reach beyond
/// touch) into arrays (`ContactChunk`), and two branch-free
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
#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "contact_constants.hpp"
#include "granular/contact_model.hpp"
#include "simulation_state.hpp"

namespace granular {

/// The per-contact values terms keep between the law's two loops (their `betweenLoops`), and
/// where term T's begin.
template <class T>
constexpr std::size_t betweenCount() {
  if constexpr (requires { T::betweenLoops; }) {
    return T::betweenLoops.size();
  } else {
    return 0;
  }
}
template <class... Terms>
constexpr std::size_t betweenSlotsIn(TermList<Terms...>) {
  return (betweenCount<Terms>() + ... + 0);
}
template <class T, class... Terms>
constexpr std::size_t betweenOffsetIn(TermList<Terms...>) {
  return runOffset<T, Terms...>([](auto t) { return betweenCount<typename decltype(t)::type>(); });
}
inline constexpr std::size_t kBetweenSlots = betweenSlotsIn(ContactModel{});

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
  // Geometry (contactLaw's input); every contact in a chunk touches, or in a build with a term
  // that reaches beyond touch is within its reach.
  alignas(64) double nx[kChunk], ny[kChunk], nz[kChunk];  ///< unit normal from i to the other
  alignas(64) double overlap[kChunk];                     ///< h [m]
  alignas(64) double armI[kChunk];                        ///< lever arm R_i - h/2 [m]
  alignas(64) double armJ[kChunk];  ///< pairs with friction: lever arm R_j - h/2 [m]
  alignas(64) double radius[kChunk], mass[kChunk];        ///< R_ij [m], m_ij [kg]
  alignas(64) double vx[kChunk], vy[kChunk], vz[kChunk];  ///< v_i - v_other [m/s]
  alignas(64) double cx[kChunk], cy[kChunk], cz[kChunk];  ///< contact-point velocity [m/s]
  // The powers' lead (contact_gather.hpp, PowerLead): the velocity a force works on over its
  // step is the one the law reads plus this. Pairs: the gather loads the centres' lead
  // (Δt/2)(a_i − a_j) and, with friction, the spins' (Δt/2) α_i and α_j; the geometry then adds
  // the arms' part, as it does to v. Walls: loaded as the contact point's lead.
  alignas(64) double ux[kChunk], uy[kChunk], uz[kChunk];     ///< contact point's lead [m/s]
  alignas(64) double uix[kChunk], uiy[kChunk], uiz[kChunk];  ///< i's spin's lead [rad/s]
  alignas(64) double ujx[kChunk], ujy[kChunk], ujz[kChunk];  ///< the other's spin's lead [rad/s]
  // The contact's history, every term's slots (ContactHistory): the stored one in, the advanced
  // one out.
  alignas(64) double historyRows[kHistorySlots][kChunk];
  // Between the law's two loops (friction only): the lane's trial tangential force [N] and
  // tangential velocity [m/s], and the terms' own values (betweenLoops).
  alignas(64) double tx[kChunk], ty[kChunk], tz[kChunk];
  alignas(64) double vtx[kChunk], vty[kChunk], vtz[kChunk];
  alignas(64) double betweenRows[kBetweenSlots > 0 ? kBetweenSlots : 1][kChunk];
  // Outputs: force on i [N], n × F [N] (friction only), and this contact's value of each
  // energy account (kEnergySlotTable: an energy, a power or an increment, by its kind).
  alignas(64) double fx[kChunk], fy[kChunk], fz[kChunk];
  alignas(64) double mx[kChunk], my[kChunk], mz[kChunk];
  /// The terms' couple on i [N m] (−it on the other body), where the build includes a term
  /// that declares `pureTorque` (kPureTorque).
  alignas(64) double qx[kChunk], qy[kChunk], qz[kChunk];
  alignas(64) double energyRows[kEnergySlots][kChunk];

  /// Term T's history slot `slot` (its declared order), one entry per contact.
  template <class T>
  double* history(std::size_t slot) {
    return historyRows[kHistoryOffset<T> + slot];
  }
  /// Term T's value `slot` kept between the law's loops (its betweenLoops), one per contact.
  template <class T>
  double* between(std::size_t slot) {
    return betweenRows[betweenOffsetIn<T>(ContactModel{}) + slot];
  }
  /// Term T's energy account `slot` (its declared order), one entry per contact.
  template <class T>
  double* energy(std::size_t slot) {
    return energyRows[kEnergyOffset<T> + slot];
  }
};

/// Pair geometry from the raw columns dx..mj of the picked pairs (and the angular velocities with
/// friction; v is already v_i - v_j): n, h, lever arm, R_ij, m_ij, contact-point velocity and,
/// with friction, the arms' part of the powers' lead.
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
      const double bx = armI * c.uix[k] + armJ * c.ujx[k];
      const double by = armI * c.uiy[k] + armJ * c.ujy[k];
      const double bz = armI * c.uiz[k] + armJ * c.ujz[k];
      c.ux[k] += by * nz - bz * ny;
      c.uy[k] += bz * nx - bx * nz;
      c.uz[k] += bx * ny - by * nx;
    }
  }
}

/// A term is optional when it says when it acts (`static bool active(const Material&)`): the
/// law is then built with and without it, and a scene that does not use it runs the build
/// without (no code, no rows, no cost). kOptional holds one bit per optional term, in the model's
/// order.
template <class T>
concept OptionalTerm = requires(const Material& m) {
  T::active(m);
};

template <class T, class... Terms>
constexpr int optionalIndexIn(TermList<Terms...>) {
  int index = -1, at = 0;
  ((std::is_same_v<T, Terms> ? (index = OptionalTerm<Terms> ? at : -1) : 0,
    at += OptionalTerm<Terms> ? 1 : 0),
   ...);
  return index;
}
/// Term T's bit in kOptional, or −1 when T always acts.
template <class T>
inline constexpr int kOptionalIndex = optionalIndexIn<T>(ContactModel{});

template <class... Terms>
constexpr unsigned optionalCountIn(TermList<Terms...>) {
  return ((OptionalTerm<Terms> ? 1u : 0u) + ... + 0u);
}
/// How many optional terms the model has (the law is built for 2^this masks).
inline constexpr unsigned kOptionalTerms = optionalCountIn(ContactModel{});

/// Whether a build (friction on or off, the optional terms in kOptional) includes term T.
template <class T, bool kFriction, unsigned kOptional>
inline constexpr bool kIncludes = (kFriction || !T::needsFriction) &&
                                  (kOptionalIndex<T> < 0 || ((kOptional >> kOptionalIndex<T>)&1));

/// The optional terms a material uses, as kOptional's bits.
template <class... Terms>
unsigned optionalMaskIn(TermList<Terms...>, const Material& m) {
  unsigned mask = 0;
  (
      [&] {
        if constexpr (OptionalTerm<Terms>) {
          if (Terms::active(m)) mask |= 1u << kOptionalIndex<Terms>;
        }
      }(),
      ...);
  return mask;
}
inline unsigned optionalMask(const Material& m) {
  return optionalMaskIn(ContactModel{}, m);
}

/// Whether a build (friction, optional terms) includes a term for which `has` is true.
template <bool kFriction, unsigned kOptional, class... Terms, class Has>
constexpr bool includesAnyIn(TermList<Terms...>, Has has) {
  return ((kIncludes<Terms, kFriction, kOptional> && has(std::type_identity<Terms>{})) || ...);
}

/// Whether a build includes a term that puts a pure torque on the bodies (rolling resistance:
/// +q on i, −q on the other), which the force pass then adds beside the forces' moments.
template <bool kFriction, unsigned kOptional>
inline constexpr bool kPureTorque = includesAnyIn<kFriction, kOptional>(ContactModel{}, [](auto t) {
  return requires {
    decltype(t)::type::pureTorque;
  };
});

/// Whether a build includes a term that reads the bodies' own radii, masses and (with friction)
/// spins, the raw rows ri, rj, mi, mj, w: a wall contact then gets the particle's as i's and
/// the wall's as j's (no spin, infinite radius and mass).
template <bool kFriction, unsigned kOptional>
inline constexpr bool kReadsBodies =
    includesAnyIn<kFriction, kOptional>(ContactModel{}, [](auto t) {
      return requires {
        decltype(t)::type::readsBodies;
      };
    });

/// A term that acts beyond touch (its `reach`, granular/contact_terms/term.hpp).
template <class T>
concept ReachingTerm = requires(const Material& m) {
  T::reach(m);
};

template <class... Terms>
constexpr bool reachingTermsLastIn(TermList<Terms...>) {
  bool seen = false, last = true;
  ((last = last && (ReachingTerm<Terms> || !seen), seen = seen || ReachingTerm<Terms>), ...);
  return last;
}
/// The force pass carries history and runs the second loop in frictional builds only: a term
/// with history or a second loop acts with friction only (needsFriction).
template <class... Terms>
constexpr bool historyNeedsFrictionIn(TermList<Terms...>) {
  return ((Terms::needsFriction ||
           (Terms::history.empty() &&
            !requires { &Terms::template second<true, ContactConstants, ContactChunk>; })) &&
          ...);
}
static_assert(historyNeedsFrictionIn(ContactModel{}),
              "a term with history or a second loop must need friction (the frictionless "
              "builds carry no history and run the first loop only)");

static_assert(reachingTermsLastIn(ContactModel{}),
              "the terms that act beyond touch are listed after every term that does not: the "
              "law drops the contact terms' parts on a gap before the reaching terms add theirs");

/// Whether a build includes a term that acts beyond touch: it then takes the pairs and wall
/// contacts within the reach (ContactConstants::reach), and on a gap drops the parts of the
/// terms that need contact.
template <bool kFriction, unsigned kOptional>
inline constexpr bool kReaches = includesAnyIn<kFriction, kOptional>(ContactModel{}, [](auto t) {
  return ReachingTerm<typename decltype(t)::type>;
});

/// Whether a contact at overlap h [m] touches (else it is a gap that a reaching term spans).
[[gnu::always_inline]] inline bool touches(double h) {
  return h > 0.0;
}

/// Per slot of a term's run (energy or history, `sizeOf` slots a term), whether the build
/// includes the term and, with kContactOnly, whether the term also acts in contact only.
template <bool kFriction, unsigned kOptional, bool kContactOnly, std::size_t N, class... Terms,
          class SizeOf>
constexpr std::array<bool, N> slotsIn(TermList<Terms...>, SizeOf sizeOf) {
  std::array<bool, N> out{};
  std::size_t at = 0;
  (
      [&] {
        for (std::size_t k = 0; k < sizeOf(std::type_identity<Terms>{}); ++k) {
          out[at++] =
              kIncludes<Terms, kFriction, kOptional> && !(kContactOnly && ReachingTerm<Terms>);
        }
      }(),
      ...);
  return out;
}
template <bool kFriction, unsigned kOptional, bool kContactOnly>
inline constexpr auto kEnergySlotsOf = slotsIn<kFriction, kOptional, kContactOnly, kEnergySlots>(
    ContactModel{}, [](auto t) { return decltype(t)::type::energy.size(); });
template <bool kFriction, unsigned kOptional, bool kContactOnly>
inline constexpr auto kHistorySlotsOf = slotsIn<kFriction, kOptional, kContactOnly, kHistorySlots>(
    ContactModel{}, [](auto t) { return decltype(t)::type::history.size(); });

/// Per energy slot: whether a build includes its term (the slots of the others hold nothing
/// the pass wrote, and are not summed).
template <bool kFriction, unsigned kOptional>
inline constexpr auto kIncludedEnergySlots = kEnergySlotsOf<kFriction, kOptional, false>;

/// Per history slot: whether a build includes its term (the force pass moves only those).
template <bool kFriction, unsigned kOptional>
inline constexpr auto kIncludedHistorySlots = kHistorySlotsOf<kFriction, kOptional, false>;

/// Doubles in a stored spring record of a frictional build with optional terms kOptional (the
/// slots of the terms it includes; PairSprings).
template <unsigned kOptional>
inline constexpr std::size_t kRecordSlots = [] {
  std::size_t n = 0;
  for (bool included : kIncludedHistorySlots<true, kOptional>) n += included ? 1 : 0;
  return n;
}();

template <unsigned... kMasks>
constexpr auto historySlotsByMaskIn(std::integer_sequence<unsigned, kMasks...>) {
  return std::array<std::array<bool, kHistorySlots>, sizeof...(kMasks)>{
      kIncludedHistorySlots<true, kMasks>...};
}
/// Per mask of optional terms: the history slots a frictional build includes.
inline constexpr auto kHistorySlotsByMask =
    historySlotsByMaskIn(std::make_integer_sequence<unsigned, (1u << kOptionalTerms)>{});

/// Term T's first and second loop, where it has them and the build includes it (the first
/// loop's: of the terms that reach beyond touch, or of the others, by kReaching).
template <class T, bool kFriction, unsigned kOptional, NormalLaw kLaw, bool kAdvance,
          bool kReaching>
[[gnu::always_inline]] inline void firstOf(const ContactConstants& k, ContactChunk& c,
                                           std::size_t e, ContactLane& lane) {
  if constexpr (requires { T::template first<kLaw, kAdvance>(k, c, e, lane); }) {
    if constexpr (kIncludes<T, kFriction, kOptional> && ReachingTerm<T> == kReaching) {
      T::template first<kLaw, kAdvance>(k, c, e, lane);
    }
  }
}
template <class T, unsigned kOptional, bool kAdvance>
[[gnu::always_inline]] inline void secondOf(const ContactConstants& k, ContactChunk& c,
                                            std::size_t e, ContactLane& lane) {
  if constexpr (requires { T::template second<kAdvance>(k, c, e, lane); }) {
    if constexpr (kIncludes<T, true, kOptional>) T::template second<kAdvance>(k, c, e, lane);
  }
}

/// On a gap (not `touching`), the energies and history of the terms that need contact are
/// zero: the contact has opened, and forgets what it held.
template <bool kFriction, unsigned kOptional>
[[gnu::always_inline]] inline void dropOnGap(ContactChunk& c, std::size_t e, bool touching) {
  for (std::size_t k = 0; k < kEnergySlots; ++k) {  // a Slip account has no per-contact value
    if (kEnergySlotsOf<kFriction, kOptional, true>[k] &&
        kEnergySlotTable[k].kind != EnergyKind::Slip) {
      c.energyRows[k][e] = touching ? c.energyRows[k][e] : 0.0;
    }
  }
  for (std::size_t k = 0; k < kHistorySlots; ++k) {
    if (kFriction && kHistorySlotsOf<kFriction, kOptional, true>[k]) {
      c.historyRows[k][e] = touching ? c.historyRows[k][e] : 0.0;
    }
  }
}

/// One contact through every term's first loop: the normal force, and with friction the trial
/// tangential force. A function of its own, not the loop's body: the lane is then a local of an
/// inlined call, which the compiler splits into registers, rather than a variable of the simd
/// loop, which OpenMP would keep as an array of structs per lane and the vectoriser refuse.
///
/// In a build with a term that reaches beyond touch, the terms that need contact see h⁺ =
/// max(h, 0); on a gap their forces and couples are dropped before the reaching terms add
/// theirs (dropOnGap drops their energies and history after the last loop).
template <bool kFriction, unsigned kOptional, NormalLaw kLaw, bool kAdvance, class... Terms>
[[gnu::always_inline]] inline void firstLoopBody(TermList<Terms...>, const ContactConstants& k,
                                                 ContactChunk& c, std::size_t e) {
  constexpr bool kReach = kReaches<kFriction, kOptional>;
  const double h = c.overlap[e];
  ContactLane lane{
      kReach ? (h > 0.0 ? h : 0.0) : h, c.nx[e], c.ny[e], c.nz[e], c.radius[e], c.mass[e]};
  (firstOf<Terms, kFriction, kOptional, kLaw, kAdvance, false>(k, c, e, lane), ...);
  if constexpr (kReach) {
    const bool touching = touches(h);
    lane.normal = touching ? lane.normal : -0.0;
    lane.qx = touching ? lane.qx : -0.0;
    lane.qy = touching ? lane.qy : -0.0;
    lane.qz = touching ? lane.qz : -0.0;
    lane.h = h;
    (firstOf<Terms, kFriction, kOptional, kLaw, kAdvance, true>(k, c, e, lane), ...);
    if constexpr (!kFriction) dropOnGap<kFriction, kOptional>(c, e, touching);
  }
  c.fx[e] = -lane.normal * lane.nx;
  c.fy[e] = -lane.normal * lane.ny;
  c.fz[e] = -lane.normal * lane.nz;
  if constexpr (kFriction) {
    c.tx[e] = lane.tx;
    c.ty[e] = lane.ty;
    c.tz[e] = lane.tz;
    c.vtx[e] = lane.vtx;
    c.vty[e] = lane.vty;
    c.vtz[e] = lane.vtz;
  }
  if constexpr (kPureTorque<kFriction, kOptional>) {
    c.qx[e] = lane.qx;
    c.qy[e] = lane.qy;
    c.qz[e] = lane.qz;
  }
}

/// One contact through every term's second loop: the caps; then the total force and n × F.
template <unsigned kOptional, bool kAdvance, class... Terms>
[[gnu::always_inline]] inline void secondLoopBody(TermList<Terms...>, const ContactConstants& k,
                                                  ContactChunk& c, std::size_t e) {
  const double h = c.overlap[e];  // h⁺ in a build that reaches beyond touch, as in the first
  ContactLane lane{kReaches<true, kOptional> ? (h > 0.0 ? h : 0.0) : h,
                   c.nx[e],
                   c.ny[e],
                   c.nz[e],
                   c.radius[e],
                   c.mass[e]};
  lane.tx = c.tx[e];
  lane.ty = c.ty[e];
  lane.tz = c.tz[e];
  lane.vtx = c.vtx[e];
  lane.vty = c.vty[e];
  lane.vtz = c.vtz[e];
  (secondOf<Terms, kOptional, kAdvance>(k, c, e, lane), ...);
  if constexpr (kReaches<true, kOptional>) {
    const bool touching = touches(h);
    lane.tx = touching ? lane.tx : -0.0;
    lane.ty = touching ? lane.ty : -0.0;
    lane.tz = touching ? lane.tz : -0.0;
    dropOnGap<true, kOptional>(c, e, touching);
  }
  const double fx = c.fx[e] + lane.tx, fy = c.fy[e] + lane.ty, fz = c.fz[e] + lane.tz;
  c.fx[e] = fx;
  c.fy[e] = fy;
  c.fz[e] = fz;
  // n × F: the torques' common factor (d_ci × F with d_ci = a_i n).
  const double nx = lane.nx, ny = lane.ny, nz = lane.nz;
  c.mx[e] = ny * fz - nz * fy;
  c.my[e] = nz * fx - nx * fz;
  c.mz[e] = nx * fy - ny * fx;
}

/// F_ij of Eq. (5) for every contact of the chunk, with n pointing from i to the other body: the
/// contact model's terms (ContactModel, granular/contact_terms/) applied in their order, each
/// through its `first` and `second` functions: the normal elastic law and dashpot (clamped at
/// zero unless the scene allows a pull), and with friction the tangential spring and dashpot
/// capped at μ |F_n|. With kAdvance the history is advanced and written back; without, the
/// force is evaluated for the stored history (measurements between steps). The composition is
/// fixed at compile time, and a frictionless scene's build has no tangential code at all.
template <bool kFriction, unsigned kOptional, NormalLaw kLaw, bool kAdvance>
[[gnu::always_inline]] inline void contactLaw(const ContactConstants& k, ContactChunk& c,
                                              std::size_t count) {
  // Two loops rather than one: each contact's chain of roots and divisions is long (the
  // spring's rotation, k_t, then the Coulomb scaling), and with the loop split the CPU overlaps
  // more contacts' chains; and the caps of the second need every force of the first.
#pragma omp simd
  for (std::size_t e = 0; e < count; ++e) {
    firstLoopBody<kFriction, kOptional, kLaw, kAdvance>(ContactModel{}, k, c, e);
  }
  if constexpr (kFriction) {
#pragma omp simd
    for (std::size_t e = 0; e < count; ++e) {
      secondLoopBody<kOptional, kAdvance>(ContactModel{}, k, c, e);
    }
  }
}

}  // namespace granular
