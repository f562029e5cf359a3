/// Coarse-grained fields (coarse_grain.hpp). Sections: 1. binning the snapshot; 2. the fields;
/// 3. the balance.
#include "granular/coarse_grain.hpp"

#include <algorithm>
#include <cmath>

#include "granular/error.hpp"

namespace granular {

// ---- 1. Binning ---------------------------------------------------------------------------

/// Items are binned by the midpoint of their segment (or their position); a query at r visits
/// the cells within the kernel width plus the longest half branch.
template <class T>
void CoarseGrainer::bin(Bins<T>& bins, const std::vector<T>& items, const Vec3& lo,
                        const Vec3& hi) const {
  bins.origin = lo;
  bins.size = width() + 2.0 * halfBranch_;
  std::size_t total = 1;
  for (int a = 0; a < 3; ++a) {
    bins.dims[a] = std::max(1L, static_cast<long>((hi[a] - lo[a]) / bins.size) + 1);
    total *= static_cast<std::size_t>(bins.dims[a]);
  }
  bins.cells.assign(total, {});
  for (const T& item : items) {
    Vec3 at;
    if constexpr (std::is_same_v<T, Segment>) {
      at = 0.5 * (item.a + item.b);
    } else {
      at = item.x;
    }
    std::array<long, 3> c;
    for (int a = 0; a < 3; ++a) {
      c[a] = std::clamp(static_cast<long>((at[a] - lo[a]) / bins.size), 0L, bins.dims[a] - 1);
    }
    bins.cells[(c[2] * bins.dims[1] + c[1]) * bins.dims[0] + c[0]].push_back(item);
  }
}

template <class T, class F>
void CoarseGrainer::visit(const Bins<T>& bins, const Vec3& r, double reach, F&& f) const {
  std::array<long, 3> lo, hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] =
        std::max(0L, static_cast<long>(std::floor((r[a] - reach - bins.origin[a]) / bins.size)));
    hi[a] = std::min(bins.dims[a] - 1,
                     static_cast<long>(std::floor((r[a] + reach - bins.origin[a]) / bins.size)));
  }
  for (long z = lo[2]; z <= hi[2]; ++z) {
    for (long y = lo[1]; y <= hi[1]; ++y) {
      for (long x = lo[0]; x <= hi[0]; ++x) {
        for (const T& item : bins.cells[(z * bins.dims[1] + y) * bins.dims[0] + x]) f(item);
      }
    }
  }
}

CoarseGrainer::CoarseGrainer(const Simulation& sim, double width)
    : kernel_(width), gravity_(sim.config().gravity) {
  const Particles& p = sim.particles();
  std::vector<Point> points;
  Vec3 lo = Vec3::Constant(1e300), hi = -lo;
  const std::vector<Vec3> net = sim.netContactForces();
  for (std::size_t i = 0; i < p.size(); ++i) {
    points.push_back({p.position[i], p.velocity[i], p.mass[i], net[i]});
    lo = lo.cwiseMin(p.position[i]);
    hi = hi.cwiseMax(p.position[i]);
  }
  std::vector<Segment> pairs, walls;
  sim.forEachContact([&](const ContactView& c) {
    const Vec3& xi = p.position[c.particle];
    if (c.isWall()) {
      walls.push_back({xi, c.point, c.force});
    } else if (c.otherParticle() > c.particle) {  // each pair once, i < j
      pairs.push_back({xi, p.position[c.otherParticle()], c.force});
    }
  });
  for (const auto* list : {&pairs, &walls}) {
    for (const Segment& s : *list) {
      halfBranch_ = std::max(halfBranch_, 0.5 * (s.b - s.a).norm());
      lo = lo.cwiseMin(s.b);
      hi = hi.cwiseMax(s.b);
    }
  }
  bin(particles_, points, lo, hi);
  bin(pairs_, pairs, lo, hi);
  bin(walls_, walls, lo, hi);
}

// ---- 2. The fields ------------------------------------------------------------------------

CoarseGrainedFields CoarseGrainer::at(const Vec3& r) const {
  CoarseGrainedFields f;
  const double c = width();
  visit(particles_, r, c, [&](const Point& q) {
    const double w = kernel_(r - q.x);
    f.density += q.m * w;
    f.momentum += q.m * w * q.v;
  });
  const double reach = c + halfBranch_;
  visit(pairs_, r, reach, [&](const Segment& s) {
    const double psi = kernel_.lineIntegral(r, s.a, s.b);
    if (psi != 0.0) f.contactStress += psi * s.force * (s.b - s.a).transpose();
  });
  visit(walls_, r, reach, [&](const Segment& s) {
    const double psi = kernel_.lineIntegral(r, s.a, s.b);
    if (psi != 0.0) f.contactStress += psi * s.force * (s.b - s.a).transpose();
    f.boundaryForce += kernel_(r - s.b) * s.force;
  });
  if (f.density > 0.0) {
    const Vec3 mean = f.momentum / f.density;
    visit(particles_, r, c, [&](const Point& q) {
      const Vec3 fluctuation = q.v - mean;
      f.kineticStress -= q.m * kernel_(r - q.x) * fluctuation * fluctuation.transpose();
    });
  }
  return f;
}

// ---- 3. The balance -----------------------------------------------------------------------

Vec3 CoarseGrainer::stressDivergence(const Vec3& r, double h, bool withKinetic) const {
  auto stress = [&](const Vec3& x) {
    const CoarseGrainedFields f = at(x);
    return withKinetic ? f.stress() : f.contactStress;
  };
  Vec3 div = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    Vec3 step = Vec3::Zero();
    step[k] = h;
    const Mat3 plus = stress(r + step), minus = stress(r - step);
    div += (plus.col(k) - minus.col(k)) / (2.0 * h);
  }
  return div;
}

Vec3 CoarseGrainer::unbalancedForce(const Vec3& r) const {
  Vec3 sum = Vec3::Zero();
  visit(particles_, r, width(),
        [&](const Point& q) { sum += kernel_(r - q.x) * (q.force + q.m * gravity_); });
  return sum;
}

Vec3 CoarseGrainer::closureError(const Vec3& r, double h) const {
  Vec3 force = Vec3::Zero();
  visit(particles_, r, width(), [&](const Point& q) { force += kernel_(r - q.x) * q.force; });
  return stressDivergence(r, h, false) + at(r).boundaryForce - force;
}

Vec3 CoarseGrainer::balanceResidual(const Vec3& r, double h) const {
  const CoarseGrainedFields f = at(r);
  return stressDivergence(r, h) + f.density * gravity_ + f.boundaryForce;
}

}  // namespace granular
