#pragma once
/// Where the particles of a run split by space live: each point of space in one rank's domain,
/// and the ranks near a point that hold a copy of a particle there (its ghosts). The interface
/// lives in the base so that the engine can split a run; the box cut into bricks
/// (granular/bricks.hpp, core/parallel) implements it. Pure geometry: every rank answers alike
/// for the same point, so every rank decides alike who owns and who copies a particle.
#include <memory>
#include <vector>

#include "granular/communicator.hpp"
#include "granular/vec3.hpp"

namespace granular {

class DomainMap {
 public:
  virtual ~DomainMap() = default;
  /// How many ranks share the space.
  virtual int ranks() const = 0;
  /// The rank whose domain holds x; every point has one.
  virtual int owner(const Vec3& x) const = 0;
  /// The ranks other than owner(x) whose domains lie within `halo` of x [m], ascending.
  virtual std::vector<int> ghostRanks(const Vec3& x, double halo) const = 0;
  /// A map of the same kind whose domains share the particles at these positions about equally
  /// (each rank passes the positions of the particles it owns; every rank gets the same map),
  /// or null where this map cannot move its boundaries. Collective: every rank calls it.
  virtual std::shared_ptr<const DomainMap> rebalanced(const std::vector<Vec3>& owned,
                                                      const Communicator& ranks) const {
    static_cast<void>(owned);
    static_cast<void>(ranks);
    return nullptr;
  }
};

}  // namespace granular
