/// Region: the box or cylinder of an insert or an outlet (granular/scene.hpp).
#include <algorithm>
#include <cmath>

#include "granular/scene.hpp"

namespace granular {

bool Region::holds(const Vec3& x, double r) const {
  if (shape == Shape::Box) {
    return ((x.array() - r) >= min.array()).all() && ((x.array() + r) <= max.array()).all();
  }
  const Vec3 d = x - base;
  const double along = d.dot(axis);
  const double across = (d - along * axis).norm();
  return along >= r && along <= length - r && across <= radius - r;
}

Vec3 Region::lower() const {
  if (shape == Shape::Box) return min;
  // A disc of radius R about unit axis a reaches R·sqrt(1 − a_k²) along axis k.
  const Vec3 reach = radius * (Vec3::Ones() - axis.cwiseProduct(axis)).cwiseMax(0.0).cwiseSqrt();
  return base.cwiseMin(base + length * axis) - reach;
}

Vec3 Region::upper() const {
  if (shape == Shape::Box) return max;
  const Vec3 reach = radius * (Vec3::Ones() - axis.cwiseProduct(axis)).cwiseMax(0.0).cwiseSqrt();
  return base.cwiseMax(base + length * axis) + reach;
}

}  // namespace granular
