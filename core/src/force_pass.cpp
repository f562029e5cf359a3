/// The force pass: contact forces and torques of every contact at the current state (Eqs. 3-5).
/// Specialised at compile time for the friction path and the normal law, so the frictionless
/// scene carries no tangential history, no torques and no per-contact test of either.
///
/// Sections: 0. the law's kernels in two builds; 1. chunks of contacts in and out of the law
/// (contact_law.hpp); 2. the hot pass, parallel and deterministic; 3. the measuring pass that
/// visits every contact; 4. dispatch.
///
/// On several threads the hot pass runs in two phases so that no two threads add to the same
/// particle: (a) every contact's force is computed into its own slot (pairs in fixed blocks,
/// powers summed per block in order); (b) each particle gathers its contacts' forces in a fixed
/// order. On one thread each contact adds to its particles directly, in that same order, so
/// the result does not depend on the thread count, bit for bit.
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "contact_law.hpp"
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

// ---- 0. The chunk kernels, built twice ----------------------------------------------------

/// The law's loops (contact_law.hpp) are built twice: for the baseline x86-64 (SSE2, 2 doubles
/// per instruction) and for AVX2 (4), chosen once by what the CPU has; elsewhere only the
/// plain build exists. Both builds give the same bits (no reductions, no fused multiply-add in
/// the loops); tests/test_force_kernels.cpp checks it. Each wrapper inlines the kernels, so the
/// whole loop is compiled for its target, while nothing shared (std::, Eigen) is.
struct ChunkKernels {
  void (*geometry)(ContactChunk&, std::size_t, bool friction);
  void (*law)(const ContactConstants&, ContactChunk&, std::size_t, bool friction, NormalLaw,
              bool advance);
};

[[gnu::always_inline]] inline void geometryBody(ContactChunk& c, std::size_t m, bool friction) {
  friction ? pairGeometry<true>(c, m) : pairGeometry<false>(c, m);
}

[[gnu::always_inline]] inline void lawBody(const ContactConstants& k, ContactChunk& c,
                                           std::size_t m, bool friction, NormalLaw law,
                                           bool advance) {
  const bool hertz = law == NormalLaw::Hertz;
  if (friction) {
    if (hertz) {
      advance ? contactLaw<true, NormalLaw::Hertz, true>(k, c, m)
              : contactLaw<true, NormalLaw::Hertz, false>(k, c, m);
    } else {
      advance ? contactLaw<true, NormalLaw::Hooke, true>(k, c, m)
              : contactLaw<true, NormalLaw::Hooke, false>(k, c, m);
    }
  } else {  // no spring: advancing or not is the same
    hertz ? contactLaw<false, NormalLaw::Hertz, true>(k, c, m)
          : contactLaw<false, NormalLaw::Hooke, true>(k, c, m);
  }
}

void geometryBaseline(ContactChunk& c, std::size_t m, bool friction) {
  geometryBody(c, m, friction);
}
void lawBaseline(const ContactConstants& k, ContactChunk& c, std::size_t m, bool friction,
                 NormalLaw law, bool advance) {
  lawBody(k, c, m, friction, law, advance);
}

#if defined(__x86_64__)
[[gnu::target("avx2")]] void geometryAvx2(ContactChunk& c, std::size_t m, bool friction) {
  geometryBody(c, m, friction);
}
[[gnu::target("avx2")]] void lawAvx2(const ContactConstants& k, ContactChunk& c, std::size_t m,
                                     bool friction, NormalLaw law, bool advance) {
  lawBody(k, c, m, friction, law, advance);
}
#endif

bool cpuHasAvx2() {
#if defined(__x86_64__)
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

ForceKernelBuild& selectedBuild() {
  static ForceKernelBuild build =
      cpuHasAvx2() ? ForceKernelBuild::Avx2 : ForceKernelBuild::Baseline;
  return build;
}

ChunkKernels kernels() {
#if defined(__x86_64__)
  if (selectedBuild() == ForceKernelBuild::Avx2) return {geometryAvx2, lawAvx2};
#endif
  return {geometryBaseline, lawBaseline};
}

// ---- 1. Chunks of contacts in and out -----------------------------------------------------

/// Picks the touching pairs among the candidates [begin, begin + count) into c.slot; returns
/// how many. Branch-free: the slot is always written and kept only when the pair touches.
inline std::size_t pickTouchingPairs(const Particles& p, const NeighbourList& list,
                                     std::size_t begin, std::size_t count, ContactChunk& c) {
  std::size_t m = 0;
  for (std::size_t k = begin; k < begin + count; ++k) {
    const std::uint32_t i = list.first[k], j = list.second[k];
    const double reach = p.radius[i] + p.radius[j];
    c.slot[m] = static_cast<std::uint32_t>(k);
    m += (p.position[j] - p.position[i]).squaredNorm() < reach * reach ? 1 : 0;
  }
  return m;
}

/// Same for wall w's candidates: touching when the overlap R_i - distance is positive.
inline std::size_t pickTouchingWallContacts(const Particles& p, const NeighbourList& list,
                                            const Wall& wall, std::size_t w, std::size_t begin,
                                            std::size_t count, ContactChunk& c) {
  std::size_t m = 0;
  for (std::size_t k = begin; k < begin + count; ++k) {
    const std::uint32_t i = list.wallParticles[w][k];
    const double distance = (p.position[i] - wall.point).dot(wall.normal);
    c.slot[m] = static_cast<std::uint32_t>(k);
    m += p.radius[i] - distance > 0.0 ? 1 : 0;
  }
  return m;
}

/// Copies a contact's stored tangential spring into entry e of the chunk.
inline void loadSpring(const TangentialHistory& spring, ContactChunk& c, std::size_t e) {
  c.sx[e] = spring.stretch.x();
  c.sy[e] = spring.stretch.y();
  c.sz[e] = spring.stretch.z();
  c.stiffness[e] = spring.stiffness;
}

/// Copies the m picked pairs into the chunk (their geometry is computed next, by the kernel).
template <bool kFriction>
void loadPairs(const Particles& p, const NeighbourList& list, ContactChunk& c, std::size_t m) {
  for (std::size_t e = 0; e < m; ++e) {
    const std::uint32_t k = c.slot[e];
    const std::uint32_t i = list.first[k], j = list.second[k];
    const Vec3 d = p.position[j] - p.position[i];
    const Vec3 v = p.velocity[i] - p.velocity[j];
    c.dx[e] = d.x();
    c.dy[e] = d.y();
    c.dz[e] = d.z();
    c.ri[e] = p.radius[i];
    c.rj[e] = p.radius[j];
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
      loadSpring(list.history[k], c, e);
    }
  }
}

/// Copies the m picked contacts of wall w into the chunk with their geometry: the wall is a
/// body of infinite radius and mass (R_ij = R_i, m_ij = m_i) moving with its prescribed
/// velocity; n points from the particle towards the wall.
template <bool kFriction>
void loadWallContacts(const Particles& p, const NeighbourList& list, const Wall& wall,
                      std::size_t w, ContactChunk& c, std::size_t m) {
  const Vec3 n = -wall.normal;
  for (std::size_t e = 0; e < m; ++e) {
    const std::uint32_t k = c.slot[e];
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
      loadSpring(list.wallHistory[w][k], c, e);
    }
  }
}

inline Vec3 forceOf(const ContactChunk& c, std::size_t e) {
  return {c.fx[e], c.fy[e], c.fz[e]};
}
inline Vec3 normalOf(const ContactChunk& c, std::size_t e) {
  return {c.nx[e], c.ny[e], c.nz[e]};
}

/// Adds the powers of the chunk's m contacts to `powers` in contact order (so the sums are the
/// same for any thread count and any vector width).
template <bool kFriction>
void addChunkPowers(const ContactChunk& c, std::size_t m, ContactPowers& powers) {
  for (std::size_t e = 0; e < m; ++e) {
    powers.elasticNormal += c.elasticNormal[e];
    powers.normalDampingPower += c.normalDampingPower[e];
    if constexpr (kFriction) {
      powers.elasticTangential += c.elasticTangential[e];
      powers.tangentialDampingPower += c.tangentialDampingPower[e];
      powers.tangentialPower += c.tangentialPower[e];
      powers.stiffnessWork += c.stiffnessWork[e];
    }
  }
  if constexpr (kFriction) powers.tangentialEvaluations += m;
}

/// Writes the advanced springs of the chunk's m contacts back to their slots.
inline void storeSprings(const ContactChunk& c, std::size_t m, TangentialHistory* springs) {
  for (std::size_t e = 0; e < m; ++e) {
    springs[c.slot[e]] = TangentialHistory{Vec3(c.sx[e], c.sy[e], c.sz[e]), c.stiffness[e]};
  }
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

/// The pass for one thread (kDirect: each contact adds to its particles as it is computed) or
/// several (each contact into its own slot, then every particle gathers its slots). Both add a
/// particle's contacts in the same order: the pairs where it is second (they come before its
/// own, since the list is sorted by first and first < second), then those where it is first,
/// each in list order, then its wall contacts by wall and candidate. So they give the same bits,
/// and one thread skips the slots and the gather.
template <bool kFriction, NormalLaw kLaw, bool kDirect>
void forcePass(SimulationState& s, double dt, int threads) {
  const ContactConstants c = constantsOf(s.config, dt);
  const Particles& p = s.particles;
  NeighbourList& list = s.neighbours;
  ContactScratch& out = s.contactScratch;
  const std::size_t pairs = list.first.size(), n = p.size();
  const ChunkKernels kern = kernels();

  if constexpr (kDirect) {
    s.force.assign(n, Vec3::Zero());
    if constexpr (kFriction) s.torque.assign(n, Vec3::Zero());
  } else {
    resizeScratch(out.pairForce, pairs);
    if constexpr (kFriction) {
      resizeScratch(out.pairMoment, pairs);
      resizeScratch(out.pairOverlap, pairs);
    }
  }
  // (a) Particle pairs.
  const std::size_t pairBlocks = (pairs + kBlock - 1) / kBlock;
  out.blockPowers.assign(pairBlocks, ContactPowers{});
#pragma omp parallel num_threads(threads)
  {
    ContactChunk chunk;  // per thread, on its stack
#pragma omp for schedule(static)
    for (std::size_t b = 0; b < pairBlocks; ++b) {
      // A local sum: the compiler keeps it in registers (the output arrays are doubles too, so
      // a sum in memory would be reloaded after every store for fear of aliasing).
      ContactPowers powers;
      const std::size_t end = std::min(pairs, (b + 1) * kBlock);
      for (std::size_t begin = b * kBlock; begin < end; begin += kChunk) {
        const std::size_t count = std::min(kChunk, end - begin);
        const std::size_t m = pickTouchingPairs(p, list, begin, count, chunk);
        loadPairs<kFriction>(p, list, chunk, m);
        kern.geometry(chunk, m, kFriction);
        kern.law(c, chunk, m, kFriction, kLaw, true);
        addChunkPowers<kFriction>(chunk, m, powers);
        powers.particleContacts += m;
        if constexpr (kDirect) {
          for (std::size_t e = 0; e < m; ++e) {
            const std::uint32_t i = list.first[chunk.slot[e]], j = list.second[chunk.slot[e]];
            const Vec3 f = forceOf(chunk, e);
            s.force[i] += f;
            s.force[j] -= f;
            if constexpr (kFriction) {
              // d_ci × F = a_i n × F on i; (-a_j n) × (-F) = a_j n × F on j.
              const Vec3 moment(chunk.mx[e], chunk.my[e], chunk.mz[e]);
              s.torque[i] += (p.radius[i] - 0.5 * chunk.overlap[e]) * moment;
              s.torque[j] += (p.radius[j] - 0.5 * chunk.overlap[e]) * moment;
            }
          }
        } else {
          // Candidates apart carry no force.
          std::fill_n(out.pairForce.begin() + begin, count, Vec3::Zero());
          for (std::size_t e = 0; e < m; ++e) out.pairForce[chunk.slot[e]] = forceOf(chunk, e);
          if constexpr (kFriction) {
            std::fill_n(out.pairMoment.begin() + begin, count, Vec3::Zero());
            std::fill_n(out.pairOverlap.begin() + begin, count, 0.0);
            for (std::size_t e = 0; e < m; ++e) {
              out.pairMoment[chunk.slot[e]] = Vec3(chunk.mx[e], chunk.my[e], chunk.mz[e]);
              out.pairOverlap[chunk.slot[e]] = chunk.overlap[e];
            }
          }
        }
        if constexpr (kFriction) {  // a contact that opened forgets its spring
          std::fill_n(list.history.begin() + begin, count, TangentialHistory{});
          storeSprings(chunk, m, list.history.data());
        }
      }
      out.blockPowers[b] = powers;
    }
  }
  // (b) Wall contacts, in blocks of candidates per wall; each block sums its powers and its
  // push on the wall in order, and the blocks are summed in order (thread-count independent).
  if constexpr (!kDirect) {
    out.wallForce.resize(s.walls.size());
    out.wallTorque.resize(s.walls.size());
  }
  out.wallBlocks.clear();
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    const std::size_t candidates = list.wallParticles[w].size();
    if constexpr (!kDirect) {
      resizeScratch(out.wallForce[w], candidates);
      if constexpr (kFriction) resizeScratch(out.wallTorque[w], candidates);
    }
    for (std::size_t begin = 0; begin < candidates; begin += kBlock) {
      out.wallBlocks.push_back({static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(begin),
                                static_cast<std::uint32_t>(std::min(candidates, begin + kBlock))});
    }
  }
  const std::size_t wallBlocks = out.wallBlocks.size();
  out.wallBlockPowers.assign(wallBlocks, ContactPowers{});
  out.wallBlockReaction.assign(wallBlocks, Vec3::Zero());
#pragma omp parallel num_threads(kDirect ? 1 : threads)
  {
    ContactChunk chunk;
#pragma omp for schedule(static)
    for (std::size_t b = 0; b < wallBlocks; ++b) {
      const auto [w, blockBegin, blockEnd] = out.wallBlocks[b];
      const Wall& wall = s.walls[w];
      ContactPowers powers;
      Vec3 reaction = Vec3::Zero();
      for (std::size_t begin = blockBegin; begin < blockEnd; begin += kChunk) {
        const std::size_t count = std::min<std::size_t>(kChunk, blockEnd - begin);
        const std::size_t m = pickTouchingWallContacts(p, list, wall, w, begin, count, chunk);
        loadWallContacts<kFriction>(p, list, wall, w, chunk, m);
        kern.law(c, chunk, m, kFriction, kLaw, true);
        addChunkPowers<kFriction>(chunk, m, powers);
        powers.wallContacts += m;
        if constexpr (!kDirect) {
          std::fill_n(out.wallForce[w].begin() + begin, count, Vec3::Zero());
          if constexpr (kFriction) {
            std::fill_n(out.wallTorque[w].begin() + begin, count, Vec3::Zero());
          }
        }
        for (std::size_t e = 0; e < m; ++e) {
          const std::uint32_t k = chunk.slot[e];
          const Vec3 f = forceOf(chunk, e);
          // d_ci × F on the particle, d_ci = a n.
          const Vec3 torque =
              kFriction ? Vec3(chunk.armI[e] * normalOf(chunk, e).cross(f)) : Vec3(Vec3::Zero());
          if constexpr (kDirect) {
            const std::uint32_t i = list.wallParticles[w][k];
            s.force[i] += f;
            if constexpr (kFriction) s.torque[i] += torque;
          } else {
            out.wallForce[w][k] = f;
            if constexpr (kFriction) out.wallTorque[w][k] = torque;
          }
          powers.wallPower += f.dot(wall.velocity);
          reaction -= f;
        }
        if constexpr (kFriction) {
          std::fill_n(list.wallHistory[w].begin() + begin, count, TangentialHistory{});
          storeSprings(chunk, m, list.wallHistory[w].data());
        }
      }
      out.wallBlockPowers[b] = powers;
      out.wallBlockReaction[b] = reaction;
    }
  }
  ContactPowers powers;
  for (const ContactPowers& part : out.blockPowers) addPowers(powers, part);
  for (const ContactPowers& part : out.wallBlockPowers) addPowers(powers, part);
  for (Wall& wall : s.walls) wall.reaction = Vec3::Zero();
  for (std::size_t b = 0; b < wallBlocks; ++b) {
    s.walls[out.wallBlocks[b].wall].reaction += out.wallBlockReaction[b];
  }
  s.powers = powers;
  if constexpr (kDirect) return;

  // (c) Each particle gathers its slots, in the order stated above.
  if (!list.index.valid) buildContactIndex(list, n);
  const ContactIndex& index = list.index;
  s.force.resize(n);
  if constexpr (kFriction) s.torque.resize(n);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 f = Vec3::Zero(), t = Vec3::Zero();
    const double radius = p.radius[i];
    for (std::uint32_t e = index.secondStart[i]; e < index.secondStart[i + 1]; ++e) {
      const std::uint32_t k = index.secondPairs[e];
      f -= out.pairForce[k];
      if constexpr (kFriction) t += (radius - 0.5 * out.pairOverlap[k]) * out.pairMoment[k];
    }
    for (std::uint32_t k = index.firstStart[i]; k < index.firstStart[i + 1]; ++k) {
      f += out.pairForce[k];
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
  const SimulationState& s = state;
  const ContactConstants c = constantsOf(s.config, s.config.timeStep);
  const Particles& p = s.particles;
  const NeighbourList& list = s.neighbours;
  const ChunkKernels kern = kernels();
  ContactChunk chunk;
  force.assign(p.size(), Vec3::Zero());
  for (std::size_t begin = 0; begin < list.first.size(); begin += kChunk) {
    const std::size_t count = std::min(kChunk, list.first.size() - begin);
    const std::size_t m = pickTouchingPairs(p, list, begin, count, chunk);
    loadPairs<kFriction>(p, list, chunk, m);
    kern.geometry(chunk, m, kFriction);
    kern.law(c, chunk, m, kFriction, kLaw, false);
    for (std::size_t e = 0; e < m; ++e) {
      const std::uint32_t i = list.first[chunk.slot[e]], j = list.second[chunk.slot[e]];
      const Vec3 f = forceOf(chunk, e);
      force[i] += f;
      force[j] -= f;
      visit(i, static_cast<long>(j), Vec3(p.position[i] + chunk.armI[e] * normalOf(chunk, e)), f);
    }
  }
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    const std::size_t candidates = list.wallParticles[w].size();
    for (std::size_t begin = 0; begin < candidates; begin += kChunk) {
      const std::size_t count = std::min(kChunk, candidates - begin);
      const std::size_t m = pickTouchingWallContacts(p, list, s.walls[w], w, begin, count, chunk);
      loadWallContacts<kFriction>(p, list, s.walls[w], w, chunk, m);
      kern.law(c, chunk, m, kFriction, kLaw, false);
      for (std::size_t e = 0; e < m; ++e) {
        const std::uint32_t i = list.wallParticles[w][chunk.slot[e]];
        const Vec3 f = forceOf(chunk, e);
        force[i] += f;
        visit(i, -static_cast<long>(w) - 1,
              Vec3(p.position[i] + chunk.armI[e] * normalOf(chunk, e)), f);
      }
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

ForceKernelBuild forceKernelBuild() {
  return selectedBuild();
}

bool setForceKernelBuild(ForceKernelBuild build) {
  if (build == ForceKernelBuild::Avx2 && !cpuHasAvx2()) return false;
  selectedBuild() = build;
  return true;
}

void computeContactForces(SimulationState& s, double dt) {
  const int threads = s.config.threads > 0 ? s.config.threads : omp_get_max_threads();
  withLaw(s, [&]<bool kFriction, NormalLaw kLaw>() {
    if (threads == 1) {
      forcePass<kFriction, kLaw, true>(s, dt, threads);
    } else {
      forcePass<kFriction, kLaw, false>(s, dt, threads);
    }
  });
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
