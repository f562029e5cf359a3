/// The force pass: contact forces and torques of every contact at the current state (Eqs. 3-5).
/// Specialised at compile time for the friction path, the normal law and the optional terms, so
/// the frictionless scene carries no tangential history, no torques and no per-contact test of
/// either. Each chunk of contacts runs the pipeline gather → law → scatter (contact_gather.hpp,
/// throughLaw): the thread part's incoming pairs, its blocks' pairs, then their wall contacts.
///
/// On several threads each thread owns a run of particles and adds their contacts' forces
/// straight to them; the few pairs that straddle two threads are computed by both, each adding
/// its own particle's share (ForcePlan, force_plan.hpp), so no thread waits. Every
/// particle receives its contacts in the same order for any thread count, and the sums run in
/// fixed blocks, so the result does not depend on the thread count, bit for bit.
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "contact_gather.hpp"
#include "contact_law.hpp"
#include "contact_sums.hpp"
#include "force_pass.hpp"
#include "granular/simd_build.hpp"
#include "mesh_gather.hpp"
#include "pair_springs.hpp"

namespace granular {
namespace {

/// The power of the force f on a particle from a shell's material point at `at`. Out of line,
/// so that the planes' path stays as small as it was.
[[gnu::noinline]] double shellPower(const Wall& wall, const Vec3& f, const Vec3& at) {
  return f.dot(wall.velocityAt(at));
}

// ---- The hot pass ------------------------------------------------------------------------

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
  static constexpr bool kReach = kReaches<kFriction, kOptional>;

 public:
  /// `aside`: this thread's array for the springs of a block set aside (SpringCursor).
  PlannedPass(SimulationState& s, double dt, std::vector<double>* aside)
      : s_(s),
        p_(s.particles),
        list_(s.neighbours),
        plan_(s.neighbours.plan),
        scratch_(s.contactScratch),
        constants_(s.config.material, dt),
        wallConstants_(s.walls, s.config.material, dt, constants_),
        walls_(s.walls.size()),
        anyMesh_(std::any_of(s.walls.begin(), s.walls.end(),
                             [](const Wall& w) { return w.shape == WallShape::Mesh; })),
        aside_(aside),
        lead_(powerLeadOf(s, dt)) {}

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
      auto gather = [&](ContactChunk& c) {
        std::size_t m = 0;
        for (std::size_t e = begin; e < begin + count; ++e) {
          const std::uint32_t q = plan_.incoming[e];
          at[m] = q;
          m += pickPair<kReach>(p_, list_, plan_.crossingFirst[q], plan_.crossing[q], c, m,
                                constants_.reach);
        }
        loadPairs<kFriction, kOptional>(
            p_, lead_, c, m,
            [&](std::size_t e) -> const ContactHistory& { return scratch_.crossingSpring[at[e]]; });
        return m;
      };
      auto scatter = [&](const ContactChunk& c, std::size_t m) {
        for (std::size_t e = 0; e < m; ++e) {
          const std::uint32_t j = c.second[e];
          s_.force[j] -= forceOf(c, e);
          if constexpr (kFriction) {
            s_.torque[j] += c.armJ[e] * Vec3(c.mx[e], c.my[e], c.mz[e]);
            if constexpr (kPureTorque<kFriction, kOptional>) s_.torque[j] -= pureTorqueOf(c, e);
          }
        }
      };
      throughLaw<ChunkOf::Pairs, kFriction, kLaw, kOptional, true>(constants_, chunk, gather,
                                                                   scatter);
    }
  }

  /// Out of line: inlined into the thread part's loop it moves the wall chunk's code and costs
  /// stage 2 2-3 % (bench/CHANGELOG.md).
  template <class Sums>
  [[gnu::noinline]] void blockPairs(std::size_t b, ContactChunk& chunk, Sums& sums) {
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
      auto gather = [&](ContactChunk& c) {
        std::size_t m = 0;
        if constexpr (kFriction) {
          const double* spring[kChunk];  // each touching pair's stored record
          // Locals, not the cursor's fields, which the c's stores might alias for the compiler.
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
            const std::size_t touching = pickPair<kReach>(
                p_, list_, i, static_cast<std::uint32_t>(k), c, m, constants_.reach);
            heldNow |= std::uint64_t{touching} << bit;
            m += touching;
          }
          rows.reached(i);
          *heldWord++ = heldNow;
          springs.read += read;
          loadPairs<kFriction, kOptional>(
              p_, lead_, c, m, [&](std::size_t e) -> const double* { return spring[e]; });
        } else {
          m = pickTouchingPairs<kReach>(p_, list_, begin, count, rows, c, constants_.reach);
          loadPairs<kFriction, kOptional>(
              p_, lead_, c, m, [](std::size_t) -> const ContactHistory& { return kNoSpring; });
        }
        return m;
      };
      auto scatter = [&](const ContactChunk& c, std::size_t m) {
        sums.pairs(c, m);
        // Pairs come by ascending first particle: i's force and torque stay in registers over
        // its run of contacts (stored once when i changes), which breaks the chain of stores and
        // reloads of one address. The adds are the same, in the same order: the same bits.
        // j > i, so no j of the run is i.
        std::uint32_t current = 0;
        Vec3 forceI = Vec3::Zero(), torqueI = Vec3::Zero();
        if (m > 0) {
          current = c.first[0];
          forceI = s_.force[current];
          if constexpr (kFriction) torqueI = s_.torque[current];
        }
        for (std::size_t e = 0; e < m; ++e) {
          const std::uint32_t i = c.first[e], j = c.second[e];
          if (i != current) {
            s_.force[current] = forceI;
            if constexpr (kFriction) s_.torque[current] = torqueI;
            current = i;
            forceI = s_.force[i];
            if constexpr (kFriction) torqueI = s_.torque[i];
          }
          const Vec3 f = forceOf(c, e);
          const bool ownsJ = j < ownEnd_;  // else j's part computes and adds j's share
          forceI += f;
          if (ownsJ) s_.force[j] -= f;
          if constexpr (kFriction) {
            // d_ci × F = a_i n × F on i; (-a_j n) × (-F) = a_j n × F on j.
            const Vec3 moment(c.mx[e], c.my[e], c.mz[e]);
            torqueI += c.armI[e] * moment;
            if (ownsJ) s_.torque[j] += c.armJ[e] * moment;
            if constexpr (kPureTorque<kFriction, kOptional>) {  // +q on i, −q on j
              const Vec3 q = pureTorqueOf(c, e);
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
          for (std::size_t e = 0; e < m; ++e) storeRecord<kOptional>(c, e, out + e * S);
        }
      };
      throughLaw<ChunkOf::Pairs, kFriction, kLaw, kOptional, true>(constants_, chunk, gather,
                                                                   scatter);
    }
    if constexpr (kFriction) springs.finish();
  }

  /// The block's wall contacts, wall by wall, in chunks that may hold several walls of one law.
  template <class Sums>
  void blockWalls(std::size_t b, ContactChunk& chunk, Sums& sums) {
    std::size_t m = 0;
    spans_.clear();
    wallLaw_ = &constants_;
    for (std::size_t w = 0; w < walls_; ++w) {
      const std::size_t end = plan_.blockWall[(b + 1) * walls_ + w];
      if (const ContactConstants* law = &wallConstants_.of(w); law != wallLaw_) {
        if (m > 0) wallChunk(chunk, m, sums);  // the chunk so far under its own law
        m = 0;
        wallLaw_ = law;
      }
      if (s_.walls[w].shape == WallShape::Mesh) {
        m = blockMesh(w, plan_.blockWall[b * walls_ + w], end, chunk, m, sums);
        continue;
      }
      for (std::size_t k = plan_.blockWall[b * walls_ + w]; k < end;) {
        const std::size_t count = std::min(kChunk - m, end - k);
        m = pickTouchingWallContacts<kReach>(p_, list_, s_.walls[w], w, k, count, chunk, m,
                                             constants_.reach);
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

  /// Mesh wall w's candidates [begin, end) (kMeshContacts entries each) into the chunk, which
  /// holds m contacts; returns how many it holds after. Out of line: planes pay nothing for it.
  template <class Sums>
  [[gnu::noinline]] std::size_t blockMesh(std::size_t w, std::size_t begin, std::size_t end,
                                          ContactChunk& chunk, std::size_t m, Sums& sums) {
    for (std::size_t k = begin; k < end; k += kMeshContacts) {
      if (m + kMeshContacts > kChunk) {
        wallChunk(chunk, m, sums);
        m = 0;
      }
      m = pickMeshContacts<kReach>(p_, list_, s_.walls[w], list_.meshGrid[w], w, k, chunk, m,
                                   constants_.reach, meshContacts_);
      const auto from = static_cast<std::uint32_t>(k);
      const auto to = static_cast<std::uint32_t>(k + kMeshContacts);
      if (!spans_.empty() && spans_.back().wall == w && spans_.back().end == from) {
        spans_.back().end = to;
      } else {
        spans_.push_back({static_cast<std::uint32_t>(w), from, to});
      }
    }
    return m;
  }

  /// The chunk under its walls' law: the pairs' law read as the pairs read it, or (a wall with
  /// its own friction) out of line, so that the planes' chunks keep their code (a law reached
  /// through a pointer here costs stage 2 about 3 %).
  template <class Sums>
  void wallChunk(ContactChunk& chunk, std::size_t m, Sums& sums) {
    if (wallLaw_ != &constants_) [[unlikely]] {
      ownLawChunk(chunk, m, sums);
      return;
    }
    lawChunk(constants_, chunk, m, sums);
  }
  template <class Sums>
  [[gnu::noinline]] void ownLawChunk(ContactChunk& chunk, std::size_t m, Sums& sums) {
    lawChunk(*wallLaw_, chunk, m, sums);
  }

  /// Flattened: the scatter's small vector sums stay inline whatever else the file instantiates
  /// (a build per mask of optional terms).
  template <class Sums>
  [[gnu::flatten]] void lawChunk(const ContactConstants& law, ContactChunk& chunk, std::size_t m,
                                 Sums& sums) {
    auto gather = [&](ContactChunk& c) {
      loadWallContacts<kFriction, kOptional>(p_, list_, s_.walls, lead_, c, m);
      return m;
    };
    auto scatter = [&](const ContactChunk& c, std::size_t) {
      std::uint32_t who[kChunk];  // each contact's particle
      for (std::size_t e = 0; e < m; ++e) who[e] = list_.wallParticles[c.wall[e]][c.slot[e]];
      sums.wallContacts(c, m, who);
      for (std::size_t e = 0; e < m; ++e) {
        const std::uint32_t w = c.wall[e], i = list_.wallParticles[w][c.slot[e]];
        const Vec3 f = forceOf(c, e);
        s_.force[i] += f;
        // d_ci × F on the particle, d_ci = a n.
        if constexpr (kFriction) s_.torque[i] += c.armI[e] * normalOf(c, e).cross(f);
        if constexpr (kPureTorque<kFriction, kOptional>) s_.torque[i] += pureTorqueOf(c, e);
        const Wall& wall = s_.walls[w];
        sums.wall(w, f,
                  wall.shell() ? shellPower(wall, f, p_.position[i] + c.armI[e] * normalOf(c, e))
                               : f.dot(wall.velocity),
                  i);
      }
      if constexpr (kFriction) {  // the examined candidates forget their springs, then keep these
        for (const CandidateSpan& span : spans_) {
          std::fill(list_.wallHistory[span.wall].begin() + span.begin,
                    list_.wallHistory[span.wall].begin() + span.end, ContactHistory{});
        }
        for (std::size_t e = 0; e < m; ++e) {
          list_.wallHistory[c.wall[e]][c.slot[e]] = springOf<kFriction, kOptional>(c, e);
        }
        if (anyMesh_) keepMeshNormals(c, m);
      }
    };
    throughLaw<ChunkOf::Walls, kFriction, kLaw, kOptional, true>(law, chunk, gather, scatter);
    spans_.clear();
  }

  /// A mesh's examined entries forget their contacts' normals, then its contacts keep theirs
  /// (from the mesh towards the particle), by which they find their entries at the next step.
  [[gnu::noinline]] void keepMeshNormals(const ContactChunk& c, std::size_t m) {
    for (const CandidateSpan& span : spans_) {
      if (s_.walls[span.wall].shape != WallShape::Mesh) continue;
      std::fill(list_.wallNormal[span.wall].begin() + span.begin,
                list_.wallNormal[span.wall].begin() + span.end, Vec3::Zero());
    }
    for (std::size_t e = 0; e < m; ++e) {
      if (s_.walls[c.wall[e]].shape == WallShape::Mesh) {
        list_.wallNormal[c.wall[e]][c.slot[e]] = -normalOf(c, e);
      }
    }
  }

  SimulationState& s_;
  const Particles& p_;
  NeighbourList& list_;
  const ForcePlan& plan_;
  ContactScratch& scratch_;
  const ContactConstants constants_;
  const WallConstants wallConstants_;
  const ContactConstants* wallLaw_ = &constants_;  // the law of the wall chunk being filled
  const std::size_t walls_;
  const bool anyMesh_;
  std::vector<double>* const aside_;
  const PowerLead lead_;  // the powers' lead (Verlet)
  std::size_t ownEnd_ = 0;
  std::vector<CandidateSpan> spans_;       // the candidates examined since the last wall chunk
  std::vector<MeshContact> meshContacts_;  // scratch of pickMeshContacts
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

}  // namespace

int computeContactForces(SimulationState& s, double dt, const ParticleRangeLoop* after) {
  const int threads = passThreads(s) > 0 ? passThreads(s) : omp_get_max_threads();
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    if (s.walls[w].shape == WallShape::Mesh) {
      ensureMeshGrid(s.neighbours, s.particles, s.walls[w], w, reachBeyondTouch(s.config.material));
    }
  }
  int failures = 0;
  withLaw(s, [&]<bool kFriction, NormalLaw kLaw, unsigned kOptional>() {
    failures = forcePass<kFriction, kLaw, kOptional>(s, dt, threads, after);
  });
  return failures;
}

}  // namespace granular
