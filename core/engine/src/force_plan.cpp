/// The force pass's plan (force_plan.hpp).
#include "force_plan.hpp"

#include <algorithm>

#include "granular/wall_mesh.hpp"
#include "simulation_state.hpp"

namespace granular {

namespace {

/// A mesh triangle a candidate looks at costs about this many pairs' work.
constexpr std::size_t kTriangleWork = 6;

}  // namespace

void buildForcePlan(NeighbourList& list, std::size_t walls, int threads) {
  ForcePlan& plan = list.plan;
  const std::vector<std::uint32_t>& blockParticle = list.blockParticle;
  const std::vector<std::uint32_t>& blockPair = list.blockPair;
  const std::size_t blocks = blockParticle.size() - 1;
  // Each block's wall candidates (ascending particle in each wall's list).
  plan.blockWall.resize((blocks + 1) * walls);
  for (std::size_t w = 0; w < walls; ++w) {
    const std::vector<std::uint32_t>& candidates = list.wallParticles[w];
    for (std::size_t b = 0; b <= blocks; ++b) {
      plan.blockWall[b * walls + w] = static_cast<std::uint32_t>(
          std::lower_bound(candidates.begin(), candidates.end(), blockParticle[b]) -
          candidates.begin());
    }
  }
  // Threads: runs of blocks of about equal work (contacts and particles, and a mesh's
  // candidates by their triangles: a silo's mesh contacts cost as much as its pairs, from a
  // tenth of the entries).
  auto workBefore = [&](std::size_t b) {
    std::size_t work = blockPair[b] + blockParticle[b];
    for (std::size_t w = 0; w < walls; ++w) {
      const std::uint32_t entries = plan.blockWall[b * walls + w];
      work += entries;
      if (w < list.meshTriangleStart.size() &&
          list.meshTriangleStart[w].size() == list.wallParticles[w].size() / kMeshContacts + 1) {
        work += kTriangleWork * list.meshTriangleStart[w][entries / kMeshContacts];
      }
    }
    return work;
  };
  const std::size_t total = workBefore(blocks);
  plan.threadBlock.assign(static_cast<std::size_t>(threads) + 1,
                          static_cast<std::uint32_t>(blocks));
  plan.threadBlock[0] = 0;
  for (std::size_t t = 1, b = 0; t < static_cast<std::size_t>(threads); ++t) {
    while (b < blocks && workBefore(b) * threads < total * t) ++b;
    plan.threadBlock[t] = static_cast<std::uint32_t>(b);
  }
  // Crossing pairs, by the thread of their first; then by the thread of their second.
  plan.crossing.clear();
  plan.crossingFirst.clear();
  for (int t = 0; t < threads; ++t) {
    const std::uint32_t ownEnd = blockParticle[plan.threadBlock[t + 1]];
    for (std::uint32_t i = blockParticle[plan.threadBlock[t]]; i < ownEnd; ++i) {
      for (std::uint32_t k = list.rowStart[i]; k < list.rowStart[i + 1]; ++k) {
        if (list.second[k] < ownEnd) continue;
        plan.crossing.push_back(k);
        plan.crossingFirst.push_back(i);
      }
    }
  }
  plan.incoming.resize(plan.crossing.size());
  for (std::size_t q = 0; q < plan.crossing.size(); ++q)
    plan.incoming[q] = static_cast<std::uint32_t>(q);
  auto secondOf = [&](std::uint32_t q) { return list.second[plan.crossing[q]]; };
  // Stable: pairs with the same second stay in ascending first.
  std::stable_sort(plan.incoming.begin(), plan.incoming.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return secondOf(a) < secondOf(b); });
  plan.incomingStart.resize(static_cast<std::size_t>(threads) + 1);
  for (int t = 0; t <= threads; ++t) {
    const std::uint32_t ownBegin = blockParticle[plan.threadBlock[t]];
    plan.incomingStart[t] = static_cast<std::uint32_t>(
        std::partition_point(plan.incoming.begin(), plan.incoming.end(),
                             [&](std::uint32_t q) { return secondOf(q) < ownBegin; }) -
        plan.incoming.begin());
  }
  plan.incomingStart[threads] = static_cast<std::uint32_t>(plan.incoming.size());
  plan.threads = threads;
  plan.valid = true;
}

}  // namespace granular
