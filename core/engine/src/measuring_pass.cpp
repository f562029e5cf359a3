/// The measuring pass: every contact at the current state, without advancing any history
/// (force_pass.hpp, visitContacts).
#include <optional>

#include "contact_gather.hpp"
#include "force_pass.hpp"
#include "mesh_gather.hpp"

namespace granular {
namespace {

/// Every contact at the current state, serially and without advancing any spring: forces go to
/// `force`, and `visit(i, other, point, F, n, h[, kind])` sees each contact once (kind: a wall;
/// by default the other is a particle).
template <bool kFriction, NormalLaw kLaw, unsigned kOptional, class Visitor>
void measuringPass(const SimulationState& state, std::vector<Vec3>& force, Visitor&& visit) {
  constexpr bool kReach = kReaches<kFriction, kOptional>;
  const SimulationState& s = state;
  const ContactConstants constants(s.config.material, s.config.timeStep);
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
    auto gather = [&](ContactChunk& c) {
      const std::size_t m =
          pickTouchingPairs<kReach>(p, list, begin, count, rows, c, constants.reach);
      loadPairs<kFriction, kOptional>(p, PowerLead{}, c, m, [&](std::size_t e) -> ContactHistory {
        return springs->at(c.slot[e]);
      });
      return m;
    };
    auto scatter = [&](const ContactChunk& c, std::size_t m) {
      for (std::size_t e = 0; e < m; ++e) {
        const std::uint32_t i = c.first[e], j = c.second[e];
        const Vec3 f = forceOf(c, e);
        force[i] += f;
        force[j] -= f;
        const Vec3 n = normalOf(c, e);
        visit(i, j, Vec3(p.position[i] + c.armI[e] * n), f, n, c.overlap[e]);
      }
    };
    throughLaw<ChunkOf::Pairs, kFriction, kLaw, kOptional, false>(constants, chunk, gather,
                                                                  scatter);
  }
  std::vector<MeshContact> meshScratch;
  const WallConstants wallConstants(s.walls, s.config.material, s.config.timeStep, constants);
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    const std::size_t candidates = list.wallParticles[w].size();
    const ContactConstants& law = wallConstants.of(w);
    auto scatter = [&](const ContactChunk& c, std::size_t m) {
      for (std::size_t e = 0; e < m; ++e) {
        const std::uint32_t i = list.wallParticles[w][c.slot[e]];
        const Vec3 f = forceOf(c, e);
        force[i] += f;
        const Vec3 n = normalOf(c, e);
        visit(i, w, Vec3(p.position[i] + c.armI[e] * n), f, n, c.overlap[e],
              ContactView::Other::Wall);
      }
    };
    if (s.walls[w].shape == WallShape::Mesh) {
      // A mesh's candidates, whole (kMeshContacts entries each), as many as a chunk holds.
      std::optional<TriangleGrid> own;
      if (w >= list.meshGrid.size() || list.meshGrid[w].empty()) {
        own = meshGridFor(list, p, s.walls[w], constants.reach);
      }
      const TriangleGrid& grid = own ? *own : list.meshGrid[w];
      std::size_t begin = 0;  // the next candidate; the gather moves it on
      while (begin < candidates) {
        auto gather = [&](ContactChunk& c) {
          std::size_t m = 0;
          for (; begin < candidates && m + kMeshContacts <= kChunk; begin += kMeshContacts) {
            m = pickMeshContacts<kReach>(p, list, s.walls[w], grid, w, begin, c, m, constants.reach,
                                         meshScratch);
          }
          loadWallContacts<kFriction, kOptional>(p, list, s.walls, PowerLead{}, c, m);
          return m;
        };
        throughLaw<ChunkOf::Walls, kFriction, kLaw, kOptional, false>(law, chunk, gather, scatter);
      }
      continue;
    }
    for (std::size_t begin = 0; begin < candidates; begin += kChunk) {
      const std::size_t count = std::min(kChunk, candidates - begin);
      auto gather = [&](ContactChunk& c) {
        const std::size_t m = pickTouchingWallContacts<kReach>(p, list, s.walls[w], w, begin, count,
                                                               c, 0, constants.reach);
        loadWallContacts<kFriction, kOptional>(p, list, s.walls, PowerLead{}, c, m);
        return m;
      };
      throughLaw<ChunkOf::Walls, kFriction, kLaw, kOptional, false>(law, chunk, gather, scatter);
    }
  }
}

}  // namespace

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
