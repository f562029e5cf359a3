#pragma once
/// A mesh wall's contacts into a chunk (docs/physics.md §2.20): each candidate's contacts with
/// the mesh (mesh_contact.hpp), each matched to the entry whose stored normal is nearest its
/// own, so that a contact keeps its spring as it slides from one triangle to the next.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "chunk_kernels.hpp"
#include "granular/wall_mesh.hpp"
#include "mesh_contact.hpp"
#include "simulation_state.hpp"
#include "triangle_grid.hpp"

namespace granular {

/// A contact takes an entry whose last contact's normal is within this of its own [cos 60°].
inline constexpr double kSameContactCos = 0.5;

/// The triangles mesh wall w's candidate whose entries start at `entry` may touch: those the
/// list's build found near it, or where the list holds none (NeighbourList::meshTriangles), the
/// grid's cell's. The contacts are the same from either: each holds every triangle within reach.
inline std::span<const std::uint32_t> meshCandidatesOf(const NeighbourList& list,
                                                       const TriangleGrid& grid, std::size_t w,
                                                       std::size_t entry, const Vec3& x) {
  if (w < list.meshTriangleStart.size()) {
    const std::vector<std::uint32_t>& start = list.meshTriangleStart[w];
    if (start.size() == list.wallParticles[w].size() / kMeshContacts + 1) {
      const std::size_t c = entry / kMeshContacts;
      return {list.meshTriangles[w].data() + start[c], start[c + 1] - start[c]};
    }
  }
  return grid.near(x);
}

/// Appends the contacts of mesh wall w's candidate whose kMeshContacts entries start at `entry`
/// (touching, or with kReach within `beyond`) to the chunk's m entries: slot (its entry), wall,
/// normal out of the particle and overlap set, and `first` 1 where the entry starts a new
/// contact (its stored spring is not this contact's). Returns the new count. `contacts` is
/// scratch.
template <bool kReach>
std::size_t pickMeshContacts(const Particles& p, const NeighbourList& list, const Wall& wall,
                             const TriangleGrid& grid, std::size_t w, std::size_t entry,
                             ContactChunk& c, std::size_t m, double beyond,
                             std::vector<MeshContact>& contacts) {
  const std::uint32_t i = list.wallParticles[w][entry];
  const WallMesh& mesh = *wall.mesh;
  double reach = p.radius[i];
  if constexpr (kReach) reach += beyond;
  meshContacts(mesh.world, mesh.topology, meshCandidatesOf(list, grid, w, entry, p.position[i]),
               p.position[i], reach, contacts);
  if (contacts.size() > kMeshContacts) contacts.resize(kMeshContacts);
  // Each contact, nearest first, takes the free entry whose last normal is nearest its own
  // (within 60°); the others then take the free entries that held no contact, then any.
  const bool stored = w < list.wallNormal.size() && list.wallNormal[w].size() > entry;
  int entryOf[kMeshContacts] = {-1, -1, -1};
  bool taken[kMeshContacts] = {false, false, false};
  if (stored) {
    for (std::size_t k = 0; k < contacts.size(); ++k) {
      double best = kSameContactCos;
      for (std::size_t e = 0; e < kMeshContacts; ++e) {
        const Vec3& last = list.wallNormal[w][entry + e];
        const double cosine = last.dot(contacts[k].normal);
        if (!taken[e] && !last.isZero(0.0) && cosine > best) {
          best = cosine;
          entryOf[k] = int(e);
        }
      }
      if (entryOf[k] >= 0) taken[entryOf[k]] = true;
    }
  }
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t k = 0; k < contacts.size(); ++k) {
      for (std::size_t e = 0; e < kMeshContacts && entryOf[k] < 0; ++e) {
        const bool empty = !stored || list.wallNormal[w][entry + e].isZero(0.0);
        if (!taken[e] && (pass == 1 || empty)) {
          entryOf[k] = int(e);
          taken[e] = true;
        }
      }
    }
  }
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const std::size_t slot = entry + std::size_t(entryOf[k]);
    const Vec3 n = -contacts[k].normal;
    c.slot[m] = static_cast<std::uint32_t>(slot);
    c.wall[m] = static_cast<std::uint32_t>(w);
    c.nx[m] = n.x();
    c.ny[m] = n.y();
    c.nz[m] = n.z();
    c.overlap[m] = p.radius[i] - contacts[k].distance;
    // A spring is this contact's if its entry last held a contact on the same surface.
    c.first[m] =
        stored && list.wallNormal[w][slot].dot(contacts[k].normal) > kSameContactCos ? 0u : 1u;
    ++m;
  }
  return m;
}

/// The grid of mesh wall w's triangles, binned where the list needs it (a list read from a
/// checkpoint has none: binned from the mesh as it is, which gives the same contacts, since a
/// grid lists a superset of the triangles within reach and the contacts do not depend on it).
inline TriangleGrid meshGridFor(const NeighbourList& list, const Particles& p, const Wall& wall,
                                double beyond) {
  double rMax = 0.0;
  for (double r : p.radius) rMax = std::max(rMax, r);
  return listGrid(wall.mesh->world, rMax, list.skin + beyond);
}
inline void ensureMeshGrid(NeighbourList& list, const Particles& p, const Wall& wall, std::size_t w,
                           double beyond) {
  if (list.meshGrid.size() <= w) list.meshGrid.resize(w + 1);
  if (list.meshGrid[w].empty()) list.meshGrid[w] = meshGridFor(list, p, wall, beyond);
}

}  // namespace granular
