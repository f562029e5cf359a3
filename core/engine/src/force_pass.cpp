/// The force pass: contact forces and torques of every contact at the current state (Eqs. 3-5).
/// Specialised at compile time for the friction path and the normal law, so the frictionless
/// scene carries no tangential history, no torques and no per-contact test of either.
///
/// Sections: 0. the law's kernels in two builds; 1. chunks of contacts in and out of the law
/// (contact_law.hpp); 2. the hot pass, parallel and deterministic; 3. the measuring pass that
/// visits every contact; 4. dispatch.
///
/// On several threads each thread owns a run of particles and adds their contacts' forces
/// straight to them; the few pairs that straddle two threads are computed by both, each adding
/// its own particle's share (ForcePlan, force_plan.hpp), so no thread waits. Every
/// particle receives its contacts in the same order for any thread count, and the sums run in
/// fixed blocks, so the result does not depend on the thread count, bit for bit.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "contact_law.hpp"
#include "contact_sums.hpp"
#include "force_pass.hpp"
#include "granular/simd_build.hpp"
#include "pair_springs.hpp"

namespace granular {
namespace {

// ---- 0. The chunk kernels, built twice ----------------------------------------------------

/// The law's loops (contact_law.hpp) run in the process's vector build (simdDispatch,
/// granular/simd_build.hpp): each body below inlines the kernels, so the whole loop is compiled
/// for that target; tests/test_force_kernels.cpp checks that the builds give the same bits.
[[gnu::always_inline]] inline void geometryBody(ContactChunk& c, std::size_t m, bool friction) {
  friction ? pairGeometry<true>(c, m) : pairGeometry<false>(c, m);
}

/// The law's build for one mask of optional terms (contact_law.hpp, kOptional).
template <unsigned kOptional>
[[gnu::always_inline]] inline void lawOf(const ContactConstants& constants, ContactChunk& c,
                                         std::size_t m, bool friction, NormalLaw law,
                                         bool advance) {
  const bool hertz = law == NormalLaw::Hertz;
  if (friction) {
    if (hertz) {
      advance ? contactLaw<true, kOptional, NormalLaw::Hertz, true>(constants, c, m)
              : contactLaw<true, kOptional, NormalLaw::Hertz, false>(constants, c, m);
    } else {
      advance ? contactLaw<true, kOptional, NormalLaw::Hooke, true>(constants, c, m)
              : contactLaw<true, kOptional, NormalLaw::Hooke, false>(constants, c, m);
    }
  } else {  // no spring: advancing or not is the same
    hertz ? contactLaw<false, kOptional, NormalLaw::Hertz, true>(constants, c, m)
          : contactLaw<false, kOptional, NormalLaw::Hooke, true>(constants, c, m);
  }
}

template <unsigned... kMasks>
[[gnu::always_inline]] inline void lawOfMask(std::integer_sequence<unsigned, kMasks...>,
                                             const ContactConstants& constants, ContactChunk& c,
                                             std::size_t m, bool friction, NormalLaw law,
                                             bool advance, unsigned optional) {
  ((optional == kMasks ? lawOf<kMasks>(constants, c, m, friction, law, advance) : void()), ...);
}

/// Every mask of the model's optional terms: 2^kOptionalTerms builds of the law.
using OptionalMasks = std::make_integer_sequence<unsigned, (1u << kOptionalTerms)>;

[[gnu::always_inline]] inline void lawBody(const ContactConstants& constants, ContactChunk& c,
                                           std::size_t m, bool friction, NormalLaw law,
                                           bool advance, unsigned optional) {
  lawOfMask(OptionalMasks{}, constants, c, m, friction, law, advance, optional);
}

/// The chunk's geometry (pairs), then the law, in the process's build.
void geometry(ContactChunk& c, std::size_t m, bool friction) {
  simdDispatch<geometryBody>(c, m, friction);
}
void law(const ContactConstants& constants, ContactChunk& c, std::size_t m, bool friction,
         NormalLaw normalLaw, bool advance, unsigned optional) {
  simdDispatch<lawBody>(constants, c, m, friction, normalLaw, advance, optional);
}

// ---- 1. Chunks of contacts in and out -----------------------------------------------------

/// Writes pair k's slot and particles i and j, centre offset x_j - x_i and radii into entry m of
/// the chunk; returns 1 if the spheres touch, else 0 (the entry is then overwritten by the next
/// one). The particles kept in the chunk spare the later loops a load through the slot.
[[gnu::always_inline]] inline std::size_t pickPair(const Particles& p, const NeighbourList& list,
                                                   std::uint32_t i, std::uint32_t k,
                                                   ContactChunk& c, std::size_t m) {
  const std::uint32_t j = list.second[k];
  const Vec3 d = p.position[j] - p.position[i];
  const double ri = p.radius[i], rj = p.radius[j], reach = ri + rj;
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

/// Picks the touching pairs among the candidates [begin, begin + count) into the chunk (slot,
/// particles, offset and radii; loadPairs adds the rest); returns how many. Branch-free; `rows`
/// walks the list's rows, its next run starting at `begin`.
inline std::size_t pickTouchingPairs(const Particles& p, const NeighbourList& list,
                                     std::size_t begin, std::size_t count, RowWalker& rows,
                                     ContactChunk& c) {
  std::uint32_t starts[RowWalker::kMaxRun];
  std::uint32_t i = rows.mark(begin, count, starts);
  std::size_t m = 0;
  for (std::size_t k = begin; k < begin + count; ++k) {
    i += starts[k - begin];
    m += pickPair(p, list, i, static_cast<std::uint32_t>(k), c, m);
  }
  rows.reached(i);
  return m;
}

/// Appends the touching ones among wall w's candidates [begin, begin + count) to the chunk's m
/// entries (slot: candidate, wall: w); returns the new count. Touching when the overlap
/// R_i - distance is positive.
inline std::size_t pickTouchingWallContacts(const Particles& p, const NeighbourList& list,
                                            const Wall& wall, std::size_t w, std::size_t begin,
                                            std::size_t count, ContactChunk& c, std::size_t m = 0) {
  for (std::size_t k = begin; k < begin + count; ++k) {
    const std::uint32_t i = list.wallParticles[w][k];
    const double distance = (p.position[i] - wall.point).dot(wall.normal);
    c.slot[m] = static_cast<std::uint32_t>(k);
    c.wall[m] = static_cast<std::uint32_t>(w);
    m += p.radius[i] - distance > 0.0 ? 1 : 0;
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

/// Completes the m picked pairs in the chunk with masses, velocities and springs (their
/// geometry is computed next, by the kernel). `springOf(e)` gives entry e's stored spring.
template <bool kFriction, unsigned kOptional, class SpringOf>
void loadPairs(const Particles& p, ContactChunk& c, std::size_t m, SpringOf&& springOf) {
  for (std::size_t e = 0; e < m; ++e) {
    const std::uint32_t i = c.first[e], j = c.second[e];
    const Vec3 v = p.velocity[i] - p.velocity[j];
    c.mi[e] = p.mass[i];
    c.mj[e] = p.mass[j];
    c.vx[e] = v.x();
    c.vy[e] = v.y();
    c.vz[e] = v.z();
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
}

/// Copies the m picked wall contacts into the chunk with their geometry: the wall is a body of
/// infinite radius and mass (R_ij = R_i, m_ij = m_i) moving with its prescribed velocity; n
/// points from the particle towards the wall. In a build with a term that reads the bodies
/// (kReadsBodies) the raw columns get the particle's radius, mass and spin as i's, and the
/// wall's as j's: infinite radius and mass, no spin.
template <bool kFriction, unsigned kOptional>
void loadWallContacts(const Particles& p, const NeighbourList& list, const std::vector<Wall>& walls,
                      ContactChunk& c, std::size_t m) {
  for (std::size_t e = 0; e < m; ++e) {
    const std::uint32_t k = c.slot[e], w = c.wall[e];
    const Wall& wall = walls[w];
    const Vec3 n = -wall.normal;
    const std::uint32_t i = list.wallParticles[w][k];
    const double h = p.radius[i] - (p.position[i] - wall.point).dot(wall.normal);
    const double arm = p.radius[i] - 0.5 * h;
    const Vec3 v = p.velocity[i] - wall.velocity;
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
    if constexpr (kFriction) {
      const Vec3 contactVelocity = v + arm * p.angularVelocity[i].cross(n);
      c.cx[e] = contactVelocity.x();
      c.cy[e] = contactVelocity.y();
      c.cz[e] = contactVelocity.z();
      loadSpring<kFriction, kOptional>(list.wallHistory[w][k], c, e);
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

// ---- 2. The hot pass ----------------------------------------------------------------------

/// One block's springs rewritten in place by blockPairs, as records of S doubles: the stored
/// record of the pair holding the `read`-th one is at source + (read - sourceOffset) S; the
/// advanced records of the pairs that touch now are written to the array's front, `written` of
/// them so far.
template <std::size_t S>
struct SpringCursor {
  std::vector<double>* array = nullptr;
  const double* source = nullptr;
  std::size_t sourceOffset = 0, read = 0, written = 0, stored = 0;  // in records
  bool setAside = false;

  void start(std::vector<double>& springs) {
    array = &springs;
    source = springs.data();
    stored = springs.size() / S;
  }
  /// The record of the `index`-th held spring (index >= read).
  const double* at(std::size_t index) const { return source + (index - sourceOffset) * S; }
  /// Room for m new records after those written, once the records up to `read` are loaded.
  double* write(std::size_t m, std::vector<double>& aside) {
    if (!setAside && written + m > read && read < stored) {
      aside.assign(array->begin() + static_cast<std::ptrdiff_t>(read * S),
                   array->begin() + static_cast<std::ptrdiff_t>(stored * S));
      source = aside.data();
      sourceOffset = read;
      setAside = true;
    }
    if ((written + m) * S > array->size()) {
      // An eighth more, not double: the springs are the largest array of a frictional bed, and
      // between two rebuilds (which lay every array out afresh) a block gains a few contacts.
      if ((written + m) * S > array->capacity()) array->reserve(((written + m) * 9 / 8 + 4) * S);
      array->resize((written + m) * S);
      if (!setAside) source = array->data();  // what is left to read kept its place
    }
    double* out = array->data() + written * S;
    written += m;
    return out;
  }
  void finish() { array->resize(written * S); }
};

/// Wall candidates [begin, end) of one wall, examined for the chunk being filled.
struct CandidateSpan {
  std::uint32_t wall, begin, end;
};

/// One force pass over a plan (ForcePlan): `ownedPhase` computes thread part t's pairs and
/// walls, adding every contact straight to its own particles. A pair straddling two parts is
/// computed by both: by its first's part as any other pair (which advances and stores its
/// spring) and, with the same inputs, by its second's part, which adds only the second's share.
/// The second's part reads the spring from a copy taken before the pass (crossingSpring), so
/// the parts need no barrier and never write the same memory.
template <bool kFriction, NormalLaw kLaw, unsigned kOptional>
class PlannedPass {
 public:
  /// `aside`: this thread's array for the springs of a block set aside (SpringCursor).
  PlannedPass(SimulationState& s, double dt, std::vector<double>* aside)
      : s_(s),
        p_(s.particles),
        list_(s.neighbours),
        plan_(s.neighbours.plan),
        scratch_(s.contactScratch),
        constants_(s.config.material, dt),
        walls_(s.walls.size()),
        aside_(aside) {}

  void ownedPhase(std::size_t t, ContactChunk& chunk) {
    const std::size_t ownBegin = list_.blockParticle[plan_.threadBlock[t]];
    ownEnd_ = list_.blockParticle[plan_.threadBlock[t + 1]];
    std::fill(s_.force.begin() + ownBegin, s_.force.begin() + ownEnd_, Vec3::Zero());
    if constexpr (kFriction) {
      std::fill(s_.torque.begin() + ownBegin, s_.torque.begin() + ownEnd_, Vec3::Zero());
    }
    incomingPairs(t, chunk);
    const std::size_t first = plan_.threadBlock[t], last = plan_.threadBlock[t + 1];
    if (s_.config.exactSums) {
      ExactPowers& part = scratch_.partPowers[t];
      part.clear(walls_);
      ExactSums<kFriction, kOptional> sums(part, s_.owned.empty() ? nullptr : s_.owned.data());
      for (std::size_t b = first; b < last; ++b) {
        blockPairs(b, chunk, sums);
        sums.endBlock();
        blockWalls(b, chunk, sums);
      }
      sums.endPart();
    } else {
      for (std::size_t b = first; b < last; ++b) {
        Vec3* reaction = scratch_.blockReaction.data() + b * walls_;
        std::fill_n(reaction, walls_, Vec3::Zero());
        BlockSums<kFriction, kOptional> sums{{}, reaction};
        blockPairs(b, chunk, sums);
        blockWalls(b, chunk, sums);
        scratch_.blockPowers[b] = sums.powers;
      }
    }
  }

 private:
  /// Pairs with their first on an earlier part, before any of our own (by second, then
  /// ascending first): the second's share only, as one thread adds it. Advanced as the first's
  /// part advances them (the force uses the new spring), but not stored.
  void incomingPairs(std::size_t t, ContactChunk& chunk) {
    const std::size_t end = plan_.incomingStart[t + 1];
    for (std::size_t begin = plan_.incomingStart[t]; begin < end; begin += kChunk) {
      const std::size_t count = std::min(kChunk, end - begin);
      std::uint32_t at[kChunk];  // each picked pair's crossing slot
      std::size_t m = 0;
      for (std::size_t e = begin; e < begin + count; ++e) {
        const std::uint32_t q = plan_.incoming[e];
        at[m] = q;
        m += pickPair(p_, list_, plan_.crossingFirst[q], plan_.crossing[q], chunk, m);
      }
      loadPairs<kFriction, kOptional>(p_, chunk, m, [&](std::size_t e) -> const ContactHistory& {
        return scratch_.crossingSpring[at[e]];
      });
      geometry(chunk, m, kFriction);
      law(constants_, chunk, m, kFriction, kLaw, true, kOptional);
      for (std::size_t e = 0; e < m; ++e) {
        const std::uint32_t j = chunk.second[e];
        s_.force[j] -= forceOf(chunk, e);
        if constexpr (kFriction) {
          s_.torque[j] += chunk.armJ[e] * Vec3(chunk.mx[e], chunk.my[e], chunk.mz[e]);
          if constexpr (kPureTorque<kFriction, kOptional>) s_.torque[j] -= pureTorqueOf(chunk, e);
        }
      }
    }
  }

  template <class Sums>
  void blockPairs(std::size_t b, ContactChunk& chunk, Sums& sums) {
    const std::size_t end = list_.blockPair[b + 1];
    // Friction: the block's springs (in pair order, of the pairs holding one) are read and
    // rewritten in place: the springs of a chunk's touching pairs go to the array's front once
    // the chunk has read its own. Where they would overwrite springs not yet read (more pairs
    // touch than held springs so far), those are first set aside in *aside_.
    constexpr std::size_t S = kRecordSlots<kOptional>;
    SpringCursor<S> springs;
    std::uint64_t* heldWord = nullptr;  // the chunk's bits (PairSprings)
    if constexpr (kFriction) {
      static_assert(kChunk == 64, "a chunk's pairs are the bits of one word");
      springs.start(list_.springs.block[b]);
      heldWord = list_.springs.held.data() + list_.blockWord[b];
    }
    RowWalker rows(list_.rowStart, list_.blockParticle[b]);
    for (std::size_t begin = list_.blockPair[b]; begin < end; begin += kChunk) {
      const std::size_t count = std::min(kChunk, end - begin);
      std::size_t m = 0;
      if constexpr (kFriction) {
        const double* spring[kChunk];  // each touching pair's stored record
        // Locals, not the cursor's fields, which the chunk's stores might alias for the compiler.
        const std::uint64_t heldBefore = *heldWord;
        std::uint64_t heldNow = 0;  // a contact that opened forgets its spring
        const double* next = springs.at(springs.read);
        std::size_t read = 0;
        std::uint32_t starts[RowWalker::kMaxRun];
        std::uint32_t i = rows.mark(begin, count, starts);
        for (std::size_t k = begin; k < begin + count; ++k) {
          const std::size_t bit = k - begin, holds = (heldBefore >> bit) & 1;
          spring[m] = holds ? next + read * S : kNoRecord;
          read += holds;
          i += starts[bit];
          const std::size_t touching =
              pickPair(p_, list_, i, static_cast<std::uint32_t>(k), chunk, m);
          heldNow |= std::uint64_t{touching} << bit;
          m += touching;
        }
        rows.reached(i);
        *heldWord++ = heldNow;
        springs.read += read;
        loadPairs<kFriction, kOptional>(p_, chunk, m,
                                        [&](std::size_t e) -> const double* { return spring[e]; });
      } else {
        m = pickTouchingPairs(p_, list_, begin, count, rows, chunk);
        loadPairs<kFriction, kOptional>(
            p_, chunk, m, [](std::size_t) -> const ContactHistory& { return kNoSpring; });
      }
      geometry(chunk, m, kFriction);
      law(constants_, chunk, m, kFriction, kLaw, true, kOptional);
      sums.pairs(chunk, m);
      // Pairs come by ascending first particle: i's force and torque stay in registers over
      // its run of contacts (stored once when i changes), which breaks the chain of stores and
      // reloads of one address. The adds are the same, in the same order: the same bits.
      // j > i, so no j of the run is i.
      std::uint32_t current = 0;
      Vec3 forceI = Vec3::Zero(), torqueI = Vec3::Zero();
      if (m > 0) {
        current = chunk.first[0];
        forceI = s_.force[current];
        if constexpr (kFriction) torqueI = s_.torque[current];
      }
      for (std::size_t e = 0; e < m; ++e) {
        const std::uint32_t i = chunk.first[e], j = chunk.second[e];
        if (i != current) {
          s_.force[current] = forceI;
          if constexpr (kFriction) s_.torque[current] = torqueI;
          current = i;
          forceI = s_.force[i];
          if constexpr (kFriction) torqueI = s_.torque[i];
        }
        const Vec3 f = forceOf(chunk, e);
        const bool ownsJ = j < ownEnd_;  // else j's part computes and adds j's share
        forceI += f;
        if (ownsJ) s_.force[j] -= f;
        if constexpr (kFriction) {
          // d_ci × F = a_i n × F on i; (-a_j n) × (-F) = a_j n × F on j.
          const Vec3 moment(chunk.mx[e], chunk.my[e], chunk.mz[e]);
          torqueI += chunk.armI[e] * moment;
          if (ownsJ) s_.torque[j] += chunk.armJ[e] * moment;
          if constexpr (kPureTorque<kFriction, kOptional>) {  // +q on i, −q on j
            const Vec3 q = pureTorqueOf(chunk, e);
            torqueI += q;
            if (ownsJ) s_.torque[j] -= q;
          }
        }
      }
      if (m > 0) {
        s_.force[current] = forceI;
        if constexpr (kFriction) s_.torque[current] = torqueI;
      }
      if constexpr (kFriction) {
        double* out = springs.write(m, *aside_);
        for (std::size_t e = 0; e < m; ++e) storeRecord<kOptional>(chunk, e, out + e * S);
      }
    }
    if constexpr (kFriction) springs.finish();
  }

  /// The block's wall contacts, wall by wall, in chunks that may hold several walls.
  template <class Sums>
  void blockWalls(std::size_t b, ContactChunk& chunk, Sums& sums) {
    std::size_t m = 0;
    spans_.clear();
    for (std::size_t w = 0; w < walls_; ++w) {
      const std::size_t end = plan_.blockWall[(b + 1) * walls_ + w];
      for (std::size_t k = plan_.blockWall[b * walls_ + w]; k < end;) {
        const std::size_t count = std::min(kChunk - m, end - k);
        m = pickTouchingWallContacts(p_, list_, s_.walls[w], w, k, count, chunk, m);
        spans_.push_back({static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(k),
                          static_cast<std::uint32_t>(k + count)});
        k += count;
        if (m == kChunk) {
          wallChunk(chunk, m, sums);
          m = 0;
        }
      }
    }
    if (!spans_.empty()) wallChunk(chunk, m, sums);
  }

  template <class Sums>
  void wallChunk(ContactChunk& chunk, std::size_t m, Sums& sums) {
    loadWallContacts<kFriction, kOptional>(p_, list_, s_.walls, chunk, m);
    law(constants_, chunk, m, kFriction, kLaw, true, kOptional);
    std::uint32_t who[kChunk];  // each contact's particle
    for (std::size_t e = 0; e < m; ++e) who[e] = list_.wallParticles[chunk.wall[e]][chunk.slot[e]];
    sums.wallContacts(chunk, m, who);
    for (std::size_t e = 0; e < m; ++e) {
      const std::uint32_t w = chunk.wall[e], i = list_.wallParticles[w][chunk.slot[e]];
      const Vec3 f = forceOf(chunk, e);
      s_.force[i] += f;
      // d_ci × F on the particle, d_ci = a n.
      if constexpr (kFriction) s_.torque[i] += chunk.armI[e] * normalOf(chunk, e).cross(f);
      if constexpr (kPureTorque<kFriction, kOptional>) s_.torque[i] += pureTorqueOf(chunk, e);
      sums.wall(w, f, f.dot(s_.walls[w].velocity), i);
    }
    if constexpr (kFriction) {  // the examined candidates forget their springs, then keep these
      for (const CandidateSpan& span : spans_) {
        std::fill(list_.wallHistory[span.wall].begin() + span.begin,
                  list_.wallHistory[span.wall].begin() + span.end, ContactHistory{});
      }
      for (std::size_t e = 0; e < m; ++e) {
        list_.wallHistory[chunk.wall[e]][chunk.slot[e]] = springOf<kFriction, kOptional>(chunk, e);
      }
    }
    spans_.clear();
  }

  SimulationState& s_;
  const Particles& p_;
  NeighbourList& list_;
  const ForcePlan& plan_;
  ContactScratch& scratch_;
  const ContactConstants constants_;
  const std::size_t walls_;
  std::vector<double>* const aside_;
  std::size_t ownEnd_ = 0;
  std::vector<CandidateSpan> spans_;  // at most walls + 1 between two wall chunks
};

/// The hot pass. On one thread, one part owns every block. On several, each part computes its
/// incoming pairs (the second's share), then its own contacts, with no barrier between parts:
/// every particle receives its contacts in the same order for any thread count
/// (ForcePlan), and the powers and wall reactions are summed per block and then in block
/// order, so the result is the same bits.
template <bool kFriction, NormalLaw kLaw, unsigned kOptional>
int forcePass(SimulationState& s, double dt, int threads, const ParticleRangeLoop* after) {
  NeighbourList& list = s.neighbours;
  const std::size_t n = s.particles.size(), walls = s.walls.size();
  if (!list.plan.valid || list.plan.threads != threads) {
    buildForcePlan(list, walls, threads);
  }
  const ForcePlan& plan = list.plan;
  const std::size_t blocks = list.blockParticle.size() - 1, crossings = plan.crossing.size();
  ContactScratch& out = s.contactScratch;
  if constexpr (kFriction) {
    // The records hold the slots of this build's terms (a material that switched an optional
    // term on or off since the last pass: laid out again).
    if (list.springs.optional != kOptional || list.springs.slots != kRecordSlots<kOptional>) {
      relayOutPairSprings(list, kOptional);
    }
  }
  if constexpr (kFriction) {  // the straddling pairs' springs as they are before the pass
    resizeScratch(out.crossingSpring, crossings);
    SpringReader reader(list);  // crossing pairs come in ascending pair order
    for (std::size_t q = 0; q < crossings; ++q) out.crossingSpring[q] = reader.at(plan.crossing[q]);
  }
  if (s.config.exactSums) {
    out.partPowers.resize(static_cast<std::size_t>(threads));
  } else {
    out.blockPowers.resize(blocks);
    out.blockReaction.resize(blocks * walls);
  }
  resizeExactly(s.force, n);
  if constexpr (kFriction) resizeExactly(s.torque, n);

  out.springsSetAside.resize(static_cast<std::size_t>(threads));
  int failures = 0;  // the OR of `after`'s results
  if (threads == 1) {
    PlannedPass<kFriction, kLaw, kOptional> pass(s, dt, &out.springsSetAside[0]);
    ContactChunk chunk;
    pass.ownedPhase(0, chunk);
    if (after) failures = (*after)(0, n);
  } else {
#pragma omp parallel num_threads(threads) reduction(| : failures)
    {
      // Parts are dealt round-robin, so the result holds if the runtime grants fewer threads.
      const std::size_t team = static_cast<std::size_t>(omp_get_num_threads());
      const std::size_t parts = static_cast<std::size_t>(threads);
      PlannedPass<kFriction, kLaw, kOptional> pass(s, dt,
                                                   &out.springsSetAside[omp_get_thread_num()]);
      ContactChunk chunk;  // per thread, on its stack
      for (std::size_t t = omp_get_thread_num(); t < parts; t += team) pass.ownedPhase(t, chunk);
      if (after) {
        // Every part has read every position it needs: each part's particles may now move.
#pragma omp barrier
        for (std::size_t t = omp_get_thread_num(); t < parts; t += team) {
          failures |= (*after)(list.blockParticle[plan.threadBlock[t]],
                               list.blockParticle[plan.threadBlock[t + 1]]);
        }
      }
    }
  }
  if (s.config.exactSums) {
    finishExactSums(s, walls);
  } else {
    finishBlockSums(s, blocks, walls);
  }
  return failures;
}

// ---- 3. The measuring pass ----------------------------------------------------------------

/// Every contact at the current state, serially and without advancing any spring: forces go to
/// `force`, and `visit(i, other, point, F, n, h[, kind])` sees each contact once (kind: a wall;
/// by default the other is a particle).
template <bool kFriction, NormalLaw kLaw, unsigned kOptional, class Visitor>
void measuringPass(const SimulationState& state, std::vector<Vec3>& force, Visitor&& visit) {
  const SimulationState& s = state;
  const ContactConstants c(s.config.material, s.config.timeStep);
  const Particles& p = s.particles;
  const NeighbourList& list = s.neighbours;
  ContactChunk chunk;
  force.assign(p.size(), Vec3::Zero());
  std::optional<SpringReader> springs;  // pairs come in ascending order
  if constexpr (kFriction) springs.emplace(list);
  RowWalker rows(list.rowStart, 0);
  const std::size_t pairs = list.second.size();
  for (std::size_t begin = 0; begin < pairs; begin += kChunk) {
    const std::size_t count = std::min(kChunk, pairs - begin);
    const std::size_t m = pickTouchingPairs(p, list, begin, count, rows, chunk);
    loadPairs<kFriction, kOptional>(
        p, chunk, m, [&](std::size_t e) -> ContactHistory { return springs->at(chunk.slot[e]); });
    geometry(chunk, m, kFriction);
    law(c, chunk, m, kFriction, kLaw, false, kOptional);
    for (std::size_t e = 0; e < m; ++e) {
      const std::uint32_t i = chunk.first[e], j = chunk.second[e];
      const Vec3 f = forceOf(chunk, e);
      force[i] += f;
      force[j] -= f;
      const Vec3 n = normalOf(chunk, e);
      visit(i, j, Vec3(p.position[i] + chunk.armI[e] * n), f, n, chunk.overlap[e]);
    }
  }
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    const std::size_t candidates = list.wallParticles[w].size();
    for (std::size_t begin = 0; begin < candidates; begin += kChunk) {
      const std::size_t count = std::min(kChunk, candidates - begin);
      const std::size_t m = pickTouchingWallContacts(p, list, s.walls[w], w, begin, count, chunk);
      loadWallContacts<kFriction, kOptional>(p, list, s.walls, chunk, m);
      law(c, chunk, m, kFriction, kLaw, false, kOptional);
      for (std::size_t e = 0; e < m; ++e) {
        const std::uint32_t i = list.wallParticles[w][chunk.slot[e]];
        const Vec3 f = forceOf(chunk, e);
        force[i] += f;
        const Vec3 n = normalOf(chunk, e);
        visit(i, w, Vec3(p.position[i] + chunk.armI[e] * n), f, n, chunk.overlap[e],
              ContactView::Other::Wall);
      }
    }
  }
}

// ---- 4. Dispatch --------------------------------------------------------------------------

template <bool kFriction, NormalLaw kLaw, class F, unsigned... kMasks>
void withMask(std::integer_sequence<unsigned, kMasks...>, unsigned optional, F&& f) {
  ((optional == kMasks ? f.template operator()<kFriction, kLaw, kMasks>() : void()), ...);
}

/// Calls f<kFriction, kLaw, kOptional>() for the scene's friction, normal law and optional terms.
template <class F>
void withLaw(const SimulationState& s, F&& f) {
  const bool hertz = s.config.material.normalLaw == NormalLaw::Hertz;
  const unsigned optional = optionalMask(s.config.material);
  if (s.frictional) {
    hertz ? withMask<true, NormalLaw::Hertz>(OptionalMasks{}, optional, f)
          : withMask<true, NormalLaw::Hooke>(OptionalMasks{}, optional, f);
  } else {
    hertz ? withMask<false, NormalLaw::Hertz>(OptionalMasks{}, optional, f)
          : withMask<false, NormalLaw::Hooke>(OptionalMasks{}, optional, f);
  }
}

}  // namespace

int computeContactForces(SimulationState& s, double dt, const ParticleRangeLoop* after) {
  const int threads = passThreads(s) > 0 ? passThreads(s) : omp_get_max_threads();
  int failures = 0;
  withLaw(s, [&]<bool kFriction, NormalLaw kLaw, unsigned kOptional>() {
    failures = forcePass<kFriction, kLaw, kOptional>(s, dt, threads, after);
  });
  return failures;
}

void visitContacts(const SimulationState& s, const std::function<void(const ContactView&)>& visit,
                   std::vector<Vec3>* netForce) {
  std::vector<Vec3> force;
  using Other = ContactView::Other;
  auto each = [&](std::uint32_t i, std::size_t other, const Vec3& point, const Vec3& f,
                  const Vec3& n, double h, Other kind = Other::Particle) {
    if (!visit) return;
    visit(ContactView{i, kind, other, point, f, n, h});
    if (kind == Other::Particle) visit(ContactView{other, Other::Particle, i, point, -f, -n, h});
  };
  withLaw(s, [&]<bool kFriction, NormalLaw kLaw, unsigned kOptional>() {
    measuringPass<kFriction, kLaw, kOptional>(s, force, each);
  });
  if (netForce) *netForce = std::move(force);
}

}  // namespace granular
