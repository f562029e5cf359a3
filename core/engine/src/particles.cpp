#include "granular/particles.hpp"

#include <numbers>

namespace granular {

std::size_t Particles::add(const Vec3& x, double r, double density, const Vec3& v) {
  position.push_back(x);
  velocity.push_back(v);
  angularVelocity.push_back(Vec3::Zero());
  radius.push_back(r);
  mass.push_back(density * 4.0 / 3.0 * std::numbers::pi * r * r * r);
  return position.size() - 1;
}

}  // namespace granular
