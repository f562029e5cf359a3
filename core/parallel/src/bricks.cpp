/// The box cut into bricks (granular/bricks.hpp).
#include "granular/bricks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace granular {
namespace {

/// The slab along one axis that holds coordinate c: the number of cuts at or below it.
int slabOf(const std::vector<double>& cuts, double c) {
  return static_cast<int>(std::upper_bound(cuts.begin(), cuts.end(), c) - cuts.begin());
}

}  // namespace

Bricks::Bricks(int ranks, const Vec3& lo, const Vec3& hi) : lo_(lo), hi_(hi) {
  if (ranks < 1) {
    throw std::invalid_argument("bricks: " + std::to_string(ranks) + " ranks; at least 1 needed");
  }
  for (int a = 0; a < 3; ++a) {
    if (!(hi[a] > lo[a]) || !std::isfinite(hi[a] - lo[a])) {
      throw std::invalid_argument("bricks: the box must have a finite positive extent on axis " +
                                  std::to_string(a));
    }
  }
  const Vec3 l = hi - lo;
  double best = std::numeric_limits<double>::infinity();
  // Every factorisation nx ny nz = ranks; z varies slowest in the loop and wins ties last
  // (<=), so among equal areas the one with the most cuts along z, then y, is kept.
  for (int nx = 1; nx <= ranks; ++nx) {
    if (ranks % nx != 0) continue;
    for (int ny = 1; ny <= ranks / nx; ++ny) {
      if ((ranks / nx) % ny != 0) continue;
      const int nz = ranks / nx / ny;
      const double area =
          (nx - 1) * l.y() * l.z() + (ny - 1) * l.x() * l.z() + (nz - 1) * l.x() * l.y();
      if (area < best || (area == best && nz > counts_[2]) ||
          (area == best && nz == counts_[2] && ny > counts_[1])) {
        best = area;
        counts_ = {nx, ny, nz};
      }
    }
  }
  for (int a = 0; a < 3; ++a) {
    for (int k = 1; k < counts_[a]; ++k) cuts_[a].push_back(lo[a] + l[a] * k / counts_[a]);
  }
}

int Bricks::owner(const Vec3& x) const {
  const int ix = slabOf(cuts_[0], x.x()), iy = slabOf(cuts_[1], x.y()),
            iz = slabOf(cuts_[2], x.z());
  return ix + counts_[0] * (iy + counts_[1] * iz);
}

std::vector<int> Bricks::ghostRanks(const Vec3& x, double halo) const {
  std::array<int, 3> from{}, to{};
  for (int a = 0; a < 3; ++a) {
    from[a] = slabOf(cuts_[a], x[a] - halo);
    to[a] = slabOf(cuts_[a], x[a] + halo);
  }
  const int self = owner(x);
  std::vector<int> ranks;
  for (int iz = from[2]; iz <= to[2]; ++iz) {
    for (int iy = from[1]; iy <= to[1]; ++iy) {
      for (int ix = from[0]; ix <= to[0]; ++ix) {
        const int r = ix + counts_[0] * (iy + counts_[1] * iz);
        if (r != self) ranks.push_back(r);
      }
    }
  }
  std::sort(ranks.begin(), ranks.end());
  return ranks;
}

std::array<Vec3, 2> Bricks::bounds(int rank) const {
  if (rank < 0 || rank >= ranks()) {
    throw std::invalid_argument("bricks: no rank " + std::to_string(rank));
  }
  const int index[3] = {rank % counts_[0], (rank / counts_[0]) % counts_[1],
                        rank / (counts_[0] * counts_[1])};
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::array<Vec3, 2> b;
  for (int a = 0; a < 3; ++a) {
    const int i = index[a];
    b[0][a] = i == 0 ? -kInf : cuts_[a][i - 1];
    b[1][a] = i + 1 == counts_[a] ? kInf : cuts_[a][i];
  }
  return b;
}

template <class Quantile>
std::vector<double> Bricks::cutsAt(int a, std::size_t n, Quantile quantile) const {
  const int slabs = counts_[a];
  std::vector<double> cuts;
  double below = lo_[a];
  for (int k = 1; k < slabs; ++k) {
    // The k-th quantile, then kept minWidth from the last cut and from the room the cuts still
    // to come need.
    const std::size_t at = n * static_cast<std::size_t>(k) / static_cast<std::size_t>(slabs);
    double cut = quantile(at);
    const double highest = hi_[a] - (slabs - k) * minWidth_;
    cut = std::min(std::max(cut, below + minWidth_), highest);
    cuts.push_back(cut);
    below = cut;
  }
  return cuts;
}

void Bricks::balance(const std::vector<Vec3>& positions, double minWidth) {
  minWidth_ = minWidth;
  const std::size_t n = positions.size();
  if (n == 0) return;
  std::vector<double> c(n);
  for (int a = 0; a < 3; ++a) {
    const int slabs = counts_[a];
    if (slabs == 1) continue;
    for (std::size_t i = 0; i < n; ++i) c[i] = positions[i][a];
    if (hi_[a] - lo_[a] < slabs * minWidth) continue;  // no room to move them: they stay
    std::sort(c.begin(), c.end());                     // the same for any order of the positions
    // Halfway between the neighbouring coordinates.
    cuts_[a] = cutsAt(a, n, [&](std::size_t at) {
      return at == 0 ? c[0] : 0.5 * (c[at - 1] + c[std::min(at, n - 1)]);
    });
  }
}

std::shared_ptr<const DomainMap> Bricks::rebalanced(const std::vector<Vec3>& owned,
                                                    const Communicator& ranks) const {
  constexpr std::size_t kBins = 4096;
  std::vector<std::uint64_t> histogram(3 * kBins, 0);
  auto binOf = [&](int a, double x) {  // outside the box (or NaN): the nearest end bin
    const double t = (x - lo_[a]) / (hi_[a] - lo_[a]) * static_cast<double>(kBins);
    if (!(t > 0.0)) return std::size_t{0};
    return t >= static_cast<double>(kBins) ? kBins - 1 : static_cast<std::size_t>(t);
  };
  for (const Vec3& x : owned) {
    for (int a = 0; a < 3; ++a) {
      if (counts_[a] > 1) ++histogram[static_cast<std::size_t>(a) * kBins + binOf(a, x[a])];
    }
  }
  ranks.sumOverRanks(histogram);
  auto out = std::make_shared<Bricks>(*this);
  for (int a = 0; a < 3; ++a) {
    if (counts_[a] == 1 || hi_[a] - lo_[a] < counts_[a] * minWidth_) continue;
    const std::uint64_t* h = histogram.data() + static_cast<std::size_t>(a) * kBins;
    std::uint64_t n = 0;
    for (std::size_t b = 0; b < kBins; ++b) n += h[b];
    if (n == 0) continue;
    // The value of rank `at` lies in the first bin whose running count passes it: the cut goes
    // to that bin's upper edge.
    out->cuts_[a] = cutsAt(a, n, [&](std::size_t at) {
      std::uint64_t below = 0;
      std::size_t b = 0;
      while (b + 1 < kBins && below + h[b] <= at) below += h[b++];
      return lo_[a] + (hi_[a] - lo_[a]) * static_cast<double>(b + 1) / static_cast<double>(kBins);
    });
  }
  return out;
}

}  // namespace granular
