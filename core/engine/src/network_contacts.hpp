#pragma once
/// The contacts the step control counts (visitNetworkContacts, network_bound.hpp), walked in
/// pieces: the bound and the scan run the list's rows on threads, each part into its own
/// buffers, and put the parts together in the walk's one order.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "granular/wall_mesh.hpp"
#include "network_bound.hpp"
#include "simulation_state.hpp"
#include "triangle_grid.hpp"
#include "wall_contact.hpp"

namespace granular {

/// Whether the neighbour list is built for the particles there are (a rank's list before its
/// first build is not).
bool isListed(const SimulationState& s);

/// Whether the touching pairs come from the listed pairs' geometry alone: listed, and no mesh
/// wall (NetworkWalk::touchingFromPass).
bool pairsFromGeometry(const SimulationState& s);

/// One walk over the contacts, in its order: the touching pairs from their first side (rows
/// ascending), the touching wall contacts (wall by wall), then the pairs about to touch (rows
/// ascending), then the walls' (wall by wall). Touching contacts come from the geometry alone
/// where no mesh wall is: spheres and analytic walls touch where their surfaces overlap, and
/// the forces, which a measuring pass would evaluate (serially) besides, are not needed. A
/// mesh's sphere may touch several of its triangles: the measuring pass finds them as the
/// force pass does, and the pairs' walk then looks for candidates only.
class NetworkWalk {
 public:
  NetworkWalk(const SimulationState& s, double lookahead);

  bool listed() const { return listed_; }
  /// Whether contacts about to touch count (a lookahead > 0 and a list).
  bool ahead() const { return ahead_; }
  /// Whether the touching contacts come from the geometry (pairsFromGeometry).
  bool geometric() const { return geometric_; }
  /// Whether the pairs' walk has anything to find.
  bool walksPairs() const { return listed_ && (geometric_ || ahead_); }

  /// Rows [begin, end) of the list: touching pairs (from the geometry) to `touching`, pairs
  /// about to touch, which close their gap within the lookahead at their present closing
  /// speed, to `approaching`. A pair apart and separating is neither, and is passed over before
  /// its distance's square root (the margin keeps the comparison of squares on the safe side
  /// of the rounding).
  template <class Touching, class Approaching>
  void pairs(std::size_t begin, std::size_t end, Touching&& touching,
             Approaching&& approaching) const {
    const Particles& p = s_.particles;
    const NeighbourList& list = s_.neighbours;
    for (std::size_t i = begin; i < end; ++i) {
      for (std::uint32_t k = list.rowStart[i]; k < list.rowStart[i + 1]; ++k) {
        const std::size_t j = list.second[k];
        const Vec3 d = p.position[j] - p.position[i];
        const Vec3 v = p.velocity[i] - p.velocity[j];
        const double reach = p.radius[i] + p.radius[j], distance2 = d.squaredNorm();
        if (distance2 > reach * reach * (1.0 + 1e-12) && !(ahead_ && v.dot(d) > 0.0)) continue;
        const double distance = std::sqrt(distance2);
        const double h = reach - distance;
        if (geometric_ && h > 0.0) {
          const Vec3 normal = d / distance;
          touching(pair(i, j, normal, v.dot(normal), h, true, v.norm()));
        }
        if (!ahead_) continue;
        const double gap = distance - p.radius[i] - p.radius[j];
        if (!(gap > 0.0)) continue;
        const double u = v.dot(d) / distance;
        if (!(u > 0.0) || gap > u * lookahead_) continue;
        approaching(pair(i, j, d / distance, u, 0.0, false, v.norm()));
      }
    }
  }

  /// The touching contacts of the analytic walls, from the geometry: of each wall's
  /// candidates, part `part` of `parts` (parts of equal length, in order).
  template <class Visit>
  void touchingWalls(Visit&& visit, std::size_t part = 0, std::size_t parts = 1) const {
    const Particles& p = s_.particles;
    eachWallCandidate(part, parts, [&](const Wall& wall, std::size_t, std::size_t, std::size_t i) {
      if (wall.removed) return;
      const WallTouch touch = touchOf(wall, p.position[i]);
      const double h = p.radius[i] - touch.distance;
      if (!(h > 0.0)) return;
      const Vec3 normal = -touch.normal;  // out of i into the wall
      const Vec3 point = p.position[i] + (p.radius[i] - 0.5 * h) * normal;  // midway
      const Vec3 v = p.velocity[i] - wall.velocityAt(point);
      visit(this->wall(i, normal, v.dot(normal), h, true, v.norm()));
    });
  }

  /// The touching contacts, pairs (from their first side) and walls, as the measuring pass
  /// finds them (a scene with a mesh wall).
  void touchingFromPass(const std::function<void(const NetworkContact&)>& visit) const;

  /// The wall candidates about to touch, within the lookahead at their present closing speed:
  /// of each wall's candidates, part `part` of `parts` (a mesh's first entry of each).
  template <class Visit>
  void wallCandidates(Visit&& visit, std::size_t part = 0, std::size_t parts = 1) const {
    const Particles& p = s_.particles;
    const NeighbourList& list = s_.neighbours;
    eachWallCandidate(
        part, parts, [&](const Wall& wall, std::size_t w, std::size_t k, std::size_t i) {
          const bool mesh = wall.shape == WallShape::Mesh;
          if (mesh && k % kMeshContacts != 0) return;  // a mesh's first entry
          WallTouch touch;
          if (mesh && w < list.meshGrid.size() && !list.meshGrid[w].empty()) {
            const MeshNearest nearest = nearestOnMesh(wall.mesh->world, wall.mesh->topology,
                                                      list.meshGrid[w], p.position[i]);
            touch = {nearest.distance, nearest.normal};
          } else {
            touch = touchOf(wall, p.position[i]);
          }
          const double gap = touch.distance - p.radius[i];
          if (!(gap > 0.0)) return;
          const Vec3 closest = p.position[i] - touch.distance * touch.normal;
          const Vec3 v = p.velocity[i] - wall.velocityAt(closest);
          const double u = -v.dot(touch.normal);
          if (!(u > 0.0) || gap > u * lookahead_) return;
          visit(this->wall(i, -touch.normal, u, 0.0, false, v.norm()));
        });
  }

  /// Pair (i, j) at overlap h [m] (under Hertz's law with the overlap an impact at closing
  /// speed u adds), normal from i towards j, its relative speed [m/s].
  NetworkContact pair(std::size_t i, std::size_t j, const Vec3& normal, double u, double h,
                      bool touching, double relative) const;
  /// Particle i's contact with a wall, the normal out of i into the wall.
  NetworkContact wall(std::size_t i, const Vec3& normal, double u, double h, bool touching,
                      double relative) const;

 private:
  /// Calls `visit(wall, w, k, i)` for entry k of each wall w's candidates, particle i, of part
  /// `part` of `parts` of each wall's list (parts of equal length, in order).
  template <class Visit>
  void eachWallCandidate(std::size_t part, std::size_t parts, Visit&& visit) const {
    const NeighbourList& list = s_.neighbours;
    for (std::size_t w = 0; w < list.wallParticles.size() && w < s_.walls.size(); ++w) {
      const std::vector<std::uint32_t>& candidates = list.wallParticles[w];
      const std::size_t size = candidates.size();
      for (std::size_t k = size * part / parts; k < size * (part + 1) / parts; ++k) {
        if (candidates[k] < s_.particles.size()) visit(s_.walls[w], w, k, candidates[k]);
      }
    }
  }
  /// The overlap an impact at closing speed u adds under Hertz's law (Hooke's k_n does not
  /// depend on it): ½ m u² = (2/5) κ √R h^(5/2).
  double impactOverlap(double mass, double reduced, double u) const;

  const SimulationState& s_;
  double lookahead_;
  bool listed_, ahead_, geometric_, hertz_;
  double kappa_;
};

/// visitNetworkContacts with the visitor's type known, so that it is called inline (once a
/// contact), on one thread.
template <class Visit>
void walkNetworkContacts(const SimulationState& s, double lookahead, Visit&& visit) {
  const NetworkWalk walk(s, lookahead);
  std::vector<NetworkContact> approaching;  // visited after the touching contacts
  if (walk.walksPairs()) {
    walk.pairs(0, s.particles.size(), visit,
               [&](const NetworkContact& c) { approaching.push_back(c); });
  }
  if (walk.geometric()) {
    walk.touchingWalls(visit);
  } else {
    walk.touchingFromPass(visit);
  }
  if (!walk.ahead()) return;
  for (const NetworkContact& c : approaching) visit(c);
  walk.wallCandidates(visit);
}

/// The threads a walk over `pairs` listed pairs runs on: below kPairsForThreads (a scan of some
/// 60 µs on one thread) one, as their start and the merge would be a large share of what they
/// save; else the pass's.
int networkThreads(const SimulationState& s, std::size_t pairs);

}  // namespace granular
