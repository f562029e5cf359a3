/// A run split by space among processes (domain_split.hpp). Sections: 1. records of the state;
/// 2. assembling a state from records; 3. the split and the redistribution at rebuilds; 4. ghosts;
/// 5. the whole state.
#include "domain_split.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <iterator>
#include <numeric>
#include <stdexcept>
#include <string>

#include "granular/error.hpp"
#include "granular/wall_mesh.hpp"
#include "message_bytes.hpp"
#include "pair_springs.hpp"

namespace granular {
namespace {

// ---- 1. Records of the state --------------------------------------------------------------

/// Walls a split run may have: a particle's wall candidacies are the bits of one word.
constexpr std::size_t kMaxWalls = 64;

void require(bool ok, const std::string& what) {
  if (!ok) throw ConfigError(what);
}

/// A wall's entries per candidate in the neighbour list: a mesh's kMeshContacts, else one.
std::size_t entriesPerCandidate(const Wall& w) {
  return w.shape == WallShape::Mesh ? kMeshContacts : 1;
}

/// The entries a record with these wall candidacies carries (friction only).
std::size_t entriesOf(const SimulationState& s, std::uint64_t candidate) {
  std::size_t entries = 0;
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    if (candidate >> w & 1) entries += entriesPerCandidate(s.walls[w]);
  }
  return entries;
}

/// Entry k of wall w's list as a record: its spring and, where the list keeps them, its normal.
WallEntryRecord entryRecord(const NeighbourList& list, std::size_t w, std::size_t k) {
  WallEntryRecord e{};
  if (w < list.wallHistory.size() && k < list.wallHistory[w].size()) {
    e.spring = list.wallHistory[w][k];
  }
  if (w < list.wallNormal.size() && k < list.wallNormal[w].size()) {
    for (int a = 0; a < 3; ++a) e.normal[a] = list.wallNormal[w][k][a];
  }
  return e;
}

std::uint64_t idOf(const SimulationState& s, std::size_t i) {
  return s.split.globalId.empty() ? i : s.split.globalId[i];
}

/// Appends the records of the particles `keep` selects, ascending, to `batch`.
template <class Keep>
void recordParticles(const SimulationState& s, Keep keep, RecordBatch& batch) {
  const Particles& p = s.particles;
  const NeighbourList& list = s.neighbours;
  const bool references = list.referencePosition.size() == p.size();
  const std::size_t walls = list.wallParticles.size();
  std::vector<std::size_t> cursor(walls, 0);  // per wall: the next candidate not yet passed
  for (std::size_t i = 0; i < p.size(); ++i) {
    // Every wall's cursor passes the candidates below i, kept or not.
    std::uint64_t candidate = 0;
    std::size_t historyOf[kMaxWalls];
    for (std::size_t w = 0; w < walls; ++w) {
      const std::vector<std::uint32_t>& on = list.wallParticles[w];
      while (cursor[w] < on.size() && on[cursor[w]] < i) ++cursor[w];
      if (cursor[w] < on.size() && on[cursor[w]] == i) {
        candidate |= std::uint64_t{1} << w;
        historyOf[w] = cursor[w];
      }
    }
    if (!keep(i)) continue;
    ParticleRecord r{};
    r.id = idOf(s, i);
    forEachRecordField([&](const auto& field, std::size_t at) {
      const auto& values = arrayOf(field, s);
      if (values.size() == p.size()) storeDoubles(r.value + at, values[i]);
    });
    if (references) {
      for (int a = 0; a < 3; ++a) r.reference[a] = list.referencePosition[i][a];
    }
    r.wallCandidate = candidate;
    r.wallHistoryAt = batch.wallEntries.size();
    for (std::size_t w = 0; w < walls; ++w) {
      if ((candidate >> w & 1) == 0 || !s.frictional) continue;
      for (std::size_t e = 0; e < entriesPerCandidate(s.walls[w]); ++e) {
        batch.wallEntries.push_back(entryRecord(list, w, historyOf[w] + e));
      }
    }
    batch.particles.push_back(r);
  }
}

/// Calls pair(i, j, k, spring) for every candidate pair k = (i, j) of the list, ascending.
template <class Visit>
void forEachPair(const SimulationState& s, Visit pair) {
  const NeighbourList& list = s.neighbours;
  const bool springs = !list.springs.block.empty() && !list.blockWord.empty() &&
                       list.springs.held.size() == list.blockWord.back();
  SpringReader reader(list);
  for (std::size_t i = 0; i + 1 < list.rowStart.size(); ++i) {
    for (std::uint32_t k = list.rowStart[i]; k < list.rowStart[i + 1]; ++k) {
      pair(i, std::size_t{list.second[k]}, springs ? reader.at(k) : kNoSpring);
    }
  }
}

// ---- 2. Assembling a state ----------------------------------------------------------------

/// Resizes an array about to be rewritten whole to n elements, with its capacity near n: a rank
/// that held the whole run before the split, or many more particles before a redistribution,
/// gives the memory back.
template <class T>
void fitted(std::vector<T>& v, std::size_t n) {
  if (n > v.capacity() || v.capacity() > n + n / 8 + 1024) {
    std::vector<T> fresh;
    fresh.reserve(n + n / 16);
    fresh.resize(n);
    v.swap(fresh);
  } else {
    v.resize(n);
  }
}

/// A new array of n values, value k from get(k), replacing v (capacity near n: a rank that held
/// the whole run before the split, or many more particles before a redistribution, gives the
/// memory back).
template <class T, class Get>
void regather(std::vector<T>& v, std::size_t n, Get get) {
  std::vector<T> out;
  out.reserve(n + n / 16);
  out.resize(n);
  for (std::size_t k = 0; k < n; ++k) out[k] = get(k);
  v.swap(out);
}

/// Replaces the particles of `s`, their derivatives and forces and the neighbour list by its
/// particles `stay` (indices, ascending) and those of the records (any order, none of them held
/// in `stay`), all ascending by id, with the batch's pairs (any pair among them). The stayers'
/// values move within the state's arrays: no record is made of them. The list's skin, wall
/// points, validity and rounding stay: the records come from one build of it.
void assemble(SimulationState& s, const std::vector<std::uint32_t>& stay,
              const RecordBatch& batch) {
  // The records sorted by id through a permutation (a record is 400 bytes, an entry 4), then
  // merged with the stayers (ascending in id already): entry k of the new state comes from
  // record from[k] when isRecord[k], else from particle from[k].
  const std::vector<ParticleRecord>& records = batch.particles;
  std::vector<std::uint32_t> order(records.size());
  std::iota(order.begin(), order.end(), 0U);
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return records[a].id < records[b].id; });
  const std::size_t n = stay.size() + records.size();
  std::vector<std::uint32_t> from(n);
  std::vector<std::uint8_t> isRecord(n);
  {
    std::size_t a = 0, b = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const bool record =
          a == stay.size() || (b < order.size() && records[order[b]].id < idOf(s, stay[a]));
      if (!record && b < order.size() && records[order[b]].id == idOf(s, stay[a])) {
        throw std::logic_error("split run: particle " + std::to_string(records[order[b]].id) +
                               " arrives at a rank that keeps it");
      }
      isRecord[k] = record ? 1 : 0;
      from[k] = record ? order[b++] : stay[a++];
    }
  }
  auto pick = [&](std::size_t k, auto ofRecord, auto ofStayer) {
    return isRecord[k] ? ofRecord(records[from[k]]) : ofStayer(std::size_t{from[k]});
  };
  // The wall candidates and their springs, before the list's are replaced: a stayer's from the
  // list (one cursor a wall: the stayers come ascending), a record's from its bits.
  NeighbourList& list = s.neighbours;
  const std::size_t walls = s.walls.size();
  const bool wallSprings = s.frictional;
  std::vector<std::vector<std::uint32_t>> wallParticles(walls);
  std::vector<std::vector<ContactHistory>> wallHistory(wallSprings ? walls : 0);
  // Meshes keep their entries' normals where they have friction (as the list's build does).
  std::vector<std::vector<Vec3>> wallNormal(walls);
  auto keepsNormals = [&](std::size_t w) {
    return wallSprings && s.walls[w].shape == WallShape::Mesh;
  };
  auto addEntry = [&](std::size_t w, std::uint32_t at, const WallEntryRecord& e) {
    wallParticles[w].push_back(at);
    if (!wallSprings) return;
    wallHistory[w].push_back(e.spring);
    if (keepsNormals(w)) wallNormal[w].push_back(Vec3(e.normal[0], e.normal[1], e.normal[2]));
  };
  {
    std::vector<std::size_t> cursor(walls, 0);
    for (std::size_t k = 0; k < n; ++k) {
      const auto at = static_cast<std::uint32_t>(k);
      if (isRecord[k]) {
        const ParticleRecord& r = records[from[k]];
        std::size_t entry = r.wallHistoryAt;
        for (std::size_t w = 0; w < walls; ++w) {
          if ((r.wallCandidate >> w & 1) == 0) continue;
          for (std::size_t e = 0; e < entriesPerCandidate(s.walls[w]); ++e) {
            addEntry(w, at, wallSprings ? batch.wallEntries.at(entry++) : WallEntryRecord{});
          }
        }
        continue;
      }
      const std::uint32_t i = from[k];
      for (std::size_t w = 0; w < walls && w < list.wallParticles.size(); ++w) {
        const std::vector<std::uint32_t>& on = list.wallParticles[w];
        std::size_t& c = cursor[w];
        while (c < on.size() && on[c] < i) ++c;
        if (c == on.size() || on[c] != i) continue;
        for (std::size_t e = 0; e < entriesPerCandidate(s.walls[w]); ++e) {
          addEntry(w, at, entryRecord(list, w, c + e));
        }
      }
    }
  }
  regather(s.split.globalId, n, [&](std::size_t k) {
    return pick(
        k, [](const ParticleRecord& r) { return r.id; }, [&](std::size_t i) { return idOf(s, i); });
  });
  // A field the run does not hold (rotations without friction) stays empty; one it holds is
  // gathered even where this rank held no particles (a run that starts empty and is filled).
  forEachRecordField([&](const auto& field, std::size_t at) {
    using Field = std::remove_cvref_t<decltype(field)>;
    auto& values = arrayOf(field, s);
    if (!holds(s, Field::needs & ~unsigned{kGhost})) return;
    regather(values, n, [&](std::size_t k) -> typename Field::Value {
      if (isRecord[k]) return loadDoubles<typename Field::Value>(records[from[k]].value + at);
      return values[from[k]];
    });
  });
  regather(list.referencePosition, n, [&](std::size_t k) {
    return pick(
        k,
        [](const ParticleRecord& r) {
          return Eigen::Vector3f(r.reference[0], r.reference[1], r.reference[2]);
        },
        [&](std::size_t i) { return Eigen::Vector3f(list.referencePosition[i]); });
  });
  // The pairs in local indices, sorted by (first, second) as the list keeps them.
  const std::vector<std::uint64_t>& id = s.split.globalId;
  auto local = [&](std::uint64_t of) {
    const auto it = std::lower_bound(id.begin(), id.end(), of);
    if (it == id.end() || *it != of) {
      throw std::logic_error("split run: a pair names particle " + std::to_string(of) +
                             ", which this rank does not hold");
    }
    return static_cast<std::uint32_t>(it - id.begin());
  };
  const std::vector<PairRecord>& pairs = batch.pairs;
  std::vector<std::uint32_t> byPair(pairs.size());
  std::iota(byPair.begin(), byPair.end(), 0U);
  std::sort(byPair.begin(), byPair.end(), [&](std::uint32_t a, std::uint32_t b) {
    return pairs[a].first != pairs[b].first ? pairs[a].first < pairs[b].first
                                            : pairs[a].second < pairs[b].second;
  });
  std::vector<std::uint32_t> first(pairs.size());
  fitted(list.second, pairs.size());
  std::vector<ContactHistory> springs;
  if (s.frictional) springs.resize(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const PairRecord& pair = pairs[byPair[k]];
    first[k] = local(pair.first);
    list.second[k] = local(pair.second);
    if (s.frictional) springs[k] = pair.spring;
  }
  rowsFromFirst(list, first, n);
  buildPairBlocks(list, n);
  layOutPairSprings(list, springs, list.springs.optional);
  list.wallParticles = std::move(wallParticles);
  list.wallHistory = std::move(wallHistory);
  list.wallNormal = std::move(wallNormal);
  // Not carried: the candidates take the grid's triangles until the list's next build.
  list.meshTriangleStart.clear();
  list.meshTriangles.clear();
  list.plan.valid = false;
  s.owned.assign(n, 1);
}

/// This rank's particles and the ghost maps (DomainSplit), from the positions now: a particle
/// is this rank's if its domain holds it, and a ghost of the ranks within `halo`.
void mapGhosts(SimulationState& s, double halo) {
  const DomainMap& domains = *s.split.domains;
  const int me = s.ranks->rank();
  const std::size_t ranks = static_cast<std::size_t>(s.ranks->size());
  s.split.sendTo.assign(ranks, {});
  s.split.receiveFrom.assign(ranks, {});
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const Vec3& x = s.particles.position[i];
    const int owner = domains.owner(x);
    s.owned[i] = owner == me ? 1 : 0;
    const auto index = static_cast<std::uint32_t>(i);
    if (owner != me) {
      s.split.receiveFrom[static_cast<std::size_t>(owner)].push_back(index);
      continue;
    }
    for (int r : domains.ghostRanks(x, halo)) {
      s.split.sendTo[static_cast<std::size_t>(r)].push_back(index);
    }
  }
}

// ---- Bytes (message_bytes.hpp) ------------------------------------------------------------

std::vector<std::byte> serialise(const RecordBatch& batch) {
  std::vector<std::byte> out;
  putArray(out, batch.particles);
  putArray(out, batch.wallEntries);
  putArray(out, batch.pairs);
  return out;
}

/// Appends the batches other ranks sent here to `all` (wall springs re-indexed).
void mergeInto(RecordBatch& all, const std::vector<std::vector<std::byte>>& received) {
  for (const std::vector<std::byte>& bytes : received) {
    if (bytes.empty()) continue;
    std::size_t at = 0;
    const std::size_t firstParticle = all.particles.size();
    const std::uint64_t springBase = all.wallEntries.size();
    getArray(bytes, at, all.particles);
    getArray(bytes, at, all.wallEntries);
    getArray(bytes, at, all.pairs);
    for (std::size_t k = firstParticle; k < all.particles.size(); ++k) {
      all.particles[k].wallHistoryAt += springBase;
    }
  }
}

/// Appends to `out` the ranks that hold a particle at x after a rebuild: its owner and those it
/// is a ghost of, ascending.
void appendHolders(const DomainMap& domains, const Vec3& x, double halo, std::vector<int>& out) {
  const int owner = domains.owner(x);
  const std::vector<int> ghosts = domains.ghostRanks(x, halo);  // mostly empty: not allocated
  const auto at = std::upper_bound(ghosts.begin(), ghosts.end(), owner);
  out.insert(out.end(), ghosts.begin(), at);
  out.push_back(owner);
  out.insert(out.end(), at, ghosts.end());
}

}  // namespace

// ---- 3. The split and the redistribution --------------------------------------------------

namespace {

/// What the contact model's reach beyond touch adds to the halo (a hair over it, as the pairs'
/// distance): a pull across a gap needs the partner as a ghost too. Read from the material at
/// each use, so a stage that changes the reach has it at the rebuild that follows.
double reachHalo(const SimulationState& s) {
  return reachBeyondTouch(s.config.material) * (1.0 + 1e-9);
}

}  // namespace

void splitState(SimulationState& s, std::shared_ptr<const DomainMap> domains,
                std::shared_ptr<const Communicator> ranks) {
  require(domains != nullptr && ranks != nullptr, "split: the domains and the ranks must be given");
  require(domains->ranks() == ranks->size(), "split: " + std::to_string(domains->ranks()) +
                                                 " domains for " + std::to_string(ranks->size()) +
                                                 " ranks");
  require(s.walls.size() <= kMaxWalls,
          "split: " + std::to_string(s.walls.size()) + " walls; a split run takes at most 64");
  require(s.split.domains == nullptr, "split: the run is split already");
  s.split.domains = std::move(domains);
  s.ranks = std::move(ranks);
  const Particles& p = s.particles;
  const double rMax =
      p.size() ? *std::max_element(p.radius.begin(), p.radius.end()) : s.contactScale.radius;
  // A hair over the pairs' largest distance, 2 R_max + skin, for the rounding of the brick's cut
  // planes against x ± halo.
  s.split.halo = (2.0 * rMax + s.neighbours.skin) * (1.0 + 1e-9);
  // The list stands as built: the partners of a particle are within the reach of where it
  // was then, and the two have moved less than the skin together since.
  const double halo = s.split.halo + reachHalo(s) + s.neighbours.skin;
  const DomainMap& map = *s.split.domains;
  const int me = s.ranks->rank();
  std::vector<std::uint8_t> kept(p.size(), 0);
  std::vector<int> near;
  for (std::size_t i = 0; i < p.size(); ++i) {
    near.clear();
    appendHolders(map, p.position[i], halo, near);
    kept[i] = std::binary_search(near.begin(), near.end(), me) ? 1 : 0;
  }
  RecordBatch batch;
  recordParticles(
      s, [&](std::size_t i) { return kept[i] != 0; }, batch);
  forEachPair(s, [&](std::size_t i, std::size_t j, const ContactHistory& spring) {
    if (kept[i] && kept[j]) batch.pairs.push_back({idOf(s, i), idOf(s, j), spring});
  });
  s.split.pairs = s.neighbours.second.size();
  assemble(s, {}, batch);
  mapGhosts(s, halo);
  s.config.exactSums = true;
  s.predictedAhead = false;
}

void redistribute(SimulationState& s) {
  if (s.split.rebalanceDue) {
    // Every rank reaches here alike (the due flag comes from reductions).
    s.split.rebalanceDue = false;
    std::vector<Vec3> owned;
    for (std::size_t i = 0; i < s.particles.size(); ++i) {
      if (s.owned[i]) owned.push_back(s.particles.position[i]);
    }
    if (std::shared_ptr<const DomainMap> moved = s.split.domains->rebalanced(owned, *s.ranks)) {
      s.split.domains = std::move(moved);
      s.split.justMoved = true;  // the bar is set from the imbalance this move leaves
    }
  }
  const DomainMap& domains = *s.split.domains;
  const double halo = s.split.halo + reachHalo(s);
  const Particles& p = s.particles;
  const std::size_t n = p.size();
  // Per particle held, the ranks that will hold it (appendHolders), in one array:
  // near[nearStart[i], nearStart[i + 1]) (one allocation, not one a particle).
  std::vector<int> near;
  std::vector<std::uint32_t> nearStart(n + 1, 0);
  near.reserve(n + n / 8);
  for (std::size_t i = 0; i < n; ++i) {
    appendHolders(domains, p.position[i], halo, near);
    nearStart[i + 1] = static_cast<std::uint32_t>(near.size());
  }
  auto nearBegin = [&](std::size_t i) { return near.begin() + std::ptrdiff_t(nearStart[i]); };
  auto nearEnd = [&](std::size_t i) { return near.begin() + std::ptrdiff_t(nearStart[i + 1]); };
  const std::size_t ranks = static_cast<std::size_t>(s.ranks->size());
  const int me = s.ranks->rank();
  // Each rank sends what it owns: its particles, and the springs of the pairs they are first of
  // to the ranks that will hold both. What stays here stays in the state's arrays (assemble
  // moves it); only what goes elsewhere (the ghost layers, the particles that left) becomes
  // records, copied into the messages.
  std::vector<std::uint32_t> stay;
  std::vector<std::uint8_t> leaves(n, 0);  // owned, and held by another rank after this
  for (std::size_t i = 0; i < n; ++i) {
    if (!s.owned[i]) continue;
    for (auto it = nearBegin(i); it != nearEnd(i); ++it) {
      if (*it == me) {
        stay.push_back(static_cast<std::uint32_t>(i));
      } else {
        leaves[i] = 1;
      }
    }
  }
  RecordBatch leaving;
  recordParticles(
      s, [&](std::size_t i) { return leaves[i] != 0; }, leaving);
  std::vector<RecordBatch> away(ranks);
  for (std::size_t i = 0, k = 0; i < n; ++i) {
    if (!leaves[i]) continue;
    const ParticleRecord& r = leaving.particles[k++];
    const std::size_t springs = s.frictional ? entriesOf(s, r.wallCandidate) : 0;
    const auto from = leaving.wallEntries.begin() + std::ptrdiff_t(r.wallHistoryAt);
    for (auto it = nearBegin(i); it != nearEnd(i); ++it) {
      if (*it == me) continue;
      RecordBatch& to = away[std::size_t(*it)];
      to.particles.push_back(r);
      to.particles.back().wallHistoryAt = to.wallEntries.size();
      to.wallEntries.insert(to.wallEntries.end(), from, from + std::ptrdiff_t(springs));
    }
  }
  std::vector<ParticleRecord>().swap(leaving.particles);  // copied into the messages
  RecordBatch mine;  // the pairs whose ends both stay or arrive here, then what arrives
  if (s.frictional) {
    std::vector<int> both;
    forEachPair(s, [&](std::size_t i, std::size_t j, const ContactHistory& spring) {
      if (!s.owned[i] || !spring.holdsSomething()) return;
      both.clear();
      std::set_intersection(nearBegin(i), nearEnd(i), nearBegin(j), nearEnd(j),
                            std::back_inserter(both));
      for (int r : both) {
        (r == me ? mine : away[std::size_t(r)]).pairs.push_back({idOf(s, i), idOf(s, j), spring});
      }
    });
  }
  std::vector<std::vector<std::byte>> bytes(ranks);
  for (std::size_t r = 0; r < ranks; ++r) {
    if (static_cast<int>(r) != me) bytes[r] = serialise(away[r]);
  }
  std::vector<RecordBatch>().swap(away);
  mergeInto(mine, s.ranks->exchange(bytes));
  assemble(s, stay, mine);
  mapGhosts(s, halo);
}

void afterSplitRebuild(SimulationState& s) {
  NeighbourList& list = s.neighbours;
  list.referenceRounding = s.ranks->maxOverRanks(list.referenceRounding);
  std::vector<std::uint64_t> mine{0, 0};  // candidate pairs, particles owned
  for (std::size_t i = 0; i + 1 < list.rowStart.size(); ++i) {
    if (s.owned[i]) mine[0] += list.rowStart[i + 1] - list.rowStart[i];
  }
  for (std::uint8_t o : s.owned) mine[1] += o;
  const double largest = s.ranks->maxOverRanks(static_cast<double>(mine[1]));
  s.ranks->sumOverRanks(mine);
  s.split.pairs = mine[0];
  DomainSplit& split = s.split;
  const double mean = static_cast<double>(mine[1]) / s.ranks->size();
  const double imbalance = mean > 0.0 ? largest / mean : 1.0;
  // A bar a twentieth above what the last move left, and never below 1.10: no move while the
  // domains cannot do better (the cuts are shared planes), nor for a few particles' drift.
  if (split.justMoved) split.rebalanceAbove = std::max(1.10, 1.05 * imbalance);
  split.justMoved = false;
  split.rebalanceDue = imbalance > split.rebalanceAbove;
}

// ---- 4. Ghosts ----------------------------------------------------------------------------

namespace {

/// Sends `width` doubles per particle of sendTo and writes what comes back into receiveFrom's.
template <class Put, class Get>
void exchangeGhosts(const SimulationState& s, std::size_t width, Put put, Get get) {
  const std::size_t ranks = s.split.sendTo.size();
  std::vector<std::vector<std::byte>> out(ranks);
  std::vector<double> values(width);
  for (std::size_t r = 0; r < ranks; ++r) {
    out[r].resize(s.split.sendTo[r].size() * width * sizeof(double));
    std::byte* at = out[r].data();
    for (std::uint32_t i : s.split.sendTo[r]) {
      put(i, values.data());
      std::memcpy(at, values.data(), width * sizeof(double));
      at += width * sizeof(double);
    }
  }
  std::vector<std::size_t> expected(ranks);
  for (std::size_t r = 0; r < ranks; ++r) {
    expected[r] = s.split.receiveFrom[r].size() * width * sizeof(double);
  }
  const std::vector<std::vector<std::byte>> in = s.ranks->exchangeKnown(out, expected);
  for (std::size_t r = 0; r < ranks; ++r) {
    const std::vector<std::uint32_t>& ghosts = s.split.receiveFrom[r];
    if (in[r].size() != ghosts.size() * width * sizeof(double)) {
      throw std::logic_error("split run: rank " + std::to_string(r) + " sent " +
                             std::to_string(in[r].size()) + " bytes of ghosts for " +
                             std::to_string(ghosts.size()));
    }
    const std::byte* at = in[r].data();
    for (std::uint32_t g : ghosts) {
      std::memcpy(values.data(), at, width * sizeof(double));
      at += width * sizeof(double);
      get(g, values.data());
    }
  }
}

}  // namespace

void refreshSplitGhosts(SimulationState& s) {
  exchangeGhosts(
      s, ghostDoubles(),
      [&](std::uint32_t i, double* v) {
        forEachGhostField([&](const auto& field, std::size_t at) {
          using Entry = std::remove_cvref_t<decltype(field)>;
          if (holds(s, field.needs)) {
            storeDoubles(v + at, arrayOf(field, s)[i]);
          } else {
            std::fill_n(v + at, Entry::doubles, 0.0);
          }
        });
      },
      [&](std::uint32_t g, const double* v) {
        forEachGhostField([&](const auto& field, std::size_t at) {
          using Value = typename std::remove_cvref_t<decltype(field)>::Value;
          if (holds(s, field.needs)) arrayOf(field, s)[g] = loadDoubles<Value>(v + at);
        });
      });
}

void refreshGhostValues(const SimulationState& s, std::vector<double>& values) {
  exchangeGhosts(
      s, 1, [&](std::uint32_t i, double* v) { v[0] = values[i]; },
      [&](std::uint32_t g, const double* v) { values[g] = v[0]; });
}

// ---- 5. The whole state -------------------------------------------------------------------

std::unique_ptr<SimulationState> gatherWhole(const SimulationState& s) {
  // Each rank's particles and the pairs they are first of: the owner of a pair's first particle
  // holds its partner (a ghost within the halo), so the pairs are the whole list's.
  RecordBatch mine;
  recordParticles(
      s, [&](std::size_t i) { return s.owned[i] != 0; }, mine);
  forEachPair(s, [&](std::size_t i, std::size_t j, const ContactHistory& spring) {
    if (s.owned[i]) mine.pairs.push_back({idOf(s, i), idOf(s, j), spring});
  });
  const std::vector<std::vector<std::byte>> bytes(static_cast<std::size_t>(s.ranks->size()),
                                                  serialise(mine));
  RecordBatch all;
  mergeInto(all, s.ranks->exchange(bytes));
  auto whole = std::make_unique<SimulationState>(s);
  assemble(*whole, {}, all);
  whole->split = DomainSplit{};
  whole->owned.clear();
  whole->ranks = nullptr;
  whole->contactScratch = ContactScratch{};
  return whole;
}

}  // namespace granular
