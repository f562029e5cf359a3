#pragma once
/// The box cut into bricks, one per rank: nx × ny × nz bricks (rank = ix + nx (iy + ny iz)) whose
/// cut planes lie on each axis at positions shared by every brick of a slab. The counts are
/// chosen from the rank count and the box's shape (the least cut area); the cut positions start
/// even and may move so that each slab holds as many particles as the others (balance). Pure
/// geometry, the same on every rank for the same inputs: every rank decides alike who owns what.
#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "granular/domain_map.hpp"
#include "granular/vec3.hpp"

namespace granular {

class Bricks : public DomainMap {
 public:
  /// `ranks` bricks over the box [lo, hi] (hi > lo on every axis; ranks >= 1): the counts
  /// nx ny nz = ranks with the least total area of cut planes, ties to more cuts along z, then
  /// y (a bed is deep before it is wide). Throws std::invalid_argument on a bad argument.
  Bricks(int ranks, const Vec3& lo, const Vec3& hi);

  int ranks() const override { return counts_[0] * counts_[1] * counts_[2]; }
  /// Bricks along x, y, z.
  const std::array<int, 3>& counts() const { return counts_; }
  /// The cut positions along an axis: counts()[axis] − 1 ascending values inside the box [m].
  const std::vector<double>& cuts(int axis) const { return cuts_[axis]; }

  /// The rank whose brick holds x. A point on a cut plane belongs to the brick above it; a point
  /// outside the box to the nearest brick (the outer bricks reach to infinity), so that every
  /// particle has one owner wherever it goes.
  int owner(const Vec3& x) const override;
  /// The ranks whose bricks lie within `halo` of x [m], apart from x's own owner: the ranks
  /// that hold x as a ghost. Ascending.
  std::vector<int> ghostRanks(const Vec3& x, double halo) const override;
  /// Brick `rank`'s bounds, lo and hi (±infinity on the box's outer faces) [m].
  std::array<Vec3, 2> bounds(int rank) const;

  /// Moves the cuts so that the slabs along each axis hold as equal particle counts as the
  /// positions allow, each cut at least `minWidth` [m] from its neighbours and the box's
  /// faces. Counting along each axis alone keeps the shared planes; a bed whose load varies
  /// across a slab is balanced only on the average. Deterministic: the same positions (in any
  /// order) give the same cuts.
  void balance(const std::vector<Vec3>& positions, double minWidth);
  /// The same bricks with the cuts moved to balance the particles that the ranks own, counted
  /// over the ranks in 4096 bins an axis (one integer reduction: every rank gets the same cuts),
  /// each cut on a bin's edge, at least the last balance()'s minWidth from its neighbours.
  std::shared_ptr<const DomainMap> rebalanced(const std::vector<Vec3>& owned,
                                              const Communicator& ranks) const override;

 private:
  /// The cuts along one axis at the k/slabs quantiles of `count` values, from where `lowest`
  /// and the cuts found so far allow, kept minWidth_ apart and from the faces; `quantile(at)`
  /// gives the position of the value of rank `at` (0-based) in ascending order.
  template <class Quantile>
  std::vector<double> cutsAt(int axis, std::size_t count, Quantile quantile) const;

  double minWidth_ = 0.0;  ///< the last balance()'s
  std::array<int, 3> counts_{1, 1, 1};
  std::array<std::vector<double>, 3> cuts_;
  Vec3 lo_, hi_;
};

}  // namespace granular
