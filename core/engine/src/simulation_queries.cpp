/// What a Simulation tells of its state beside the particles and the energy: its contacts,
/// its memory, and a hash of its motion.
#include <cstring>

#include "force_pass.hpp"
#include "particle_fields.hpp"
#include "rollback.hpp"
#include "simulation_state.hpp"

namespace granular {

void Simulation::forEachContact(const std::function<void(const ContactView&)>& visit) const {
  visitContacts(*state_, visit, nullptr);
}

std::vector<Vec3> Simulation::netContactForces() const {
  std::vector<Vec3> net;
  visitContacts(*state_, nullptr, &net);
  return net;
}

namespace {

template <class T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}
template <class T>
std::size_t bytes(const std::vector<std::vector<T>>& v) {
  std::size_t total = v.capacity() * sizeof(std::vector<T>);
  for (const auto& inner : v) total += bytes(inner);
  return total;
}

/// The arrays of one state, its rollback's left out.
MemoryUse memoryOf(const SimulationState& s) {
  const Particles& p = s.particles;
  MemoryUse m;
  forEachParticleField(p,
                       [&](const FieldSpec&, const auto& array) { m.particles += bytes(array); });
  forEachMotionField(s, [&](const FieldSpec&, const auto& array) { m.integrator += bytes(array); });
  const NeighbourList& l = s.neighbours;
  m.neighbours = bytes(l.rowStart) + bytes(l.second) + bytes(l.wallParticles) +
                 bytes(l.referencePosition) + bytes(l.referenceWallPoint);
  m.history = bytes(l.springs.held) + bytes(l.springs.block) + bytes(l.wallHistory);
  const ForcePlan& x = l.plan;
  m.forcePlan = bytes(l.blockParticle) + bytes(l.blockPair) + bytes(l.blockWord) +
                bytes(x.blockWall) + bytes(x.threadBlock) + bytes(x.crossing) +
                bytes(x.crossingFirst) + bytes(x.incoming) + bytes(x.incomingStart);
  const ContactScratch& c = s.contactScratch;
  m.scratch = bytes(c.crossingSpring) + bytes(c.springsSetAside) + bytes(c.blockPowers) +
              bytes(c.blockReaction) + bytes(c.partPowers);
  for (const ExactPowers& part : c.partPowers) m.scratch += bytes(part.reaction);
  return m;
}

}  // namespace

MemoryUse Simulation::memoryUse() const {
  MemoryUse m = memoryOf(*state_);
  if (const SimulationState* kept = rollbackState(*state_)) m.rollback = memoryOf(*kept).total();
  return m;
}

std::uint64_t Simulation::stateHash() const {
  const Particles& p = state_->particles;
  std::uint64_t h = 1469598103934665603ULL;
  auto mix = [&h](const Vec3& v) {
    for (int k = 0; k < 3; ++k) {
      std::uint64_t bits;
      const double x = v[k];
      std::memcpy(&bits, &x, sizeof bits);
      for (int b = 0; b < 8; ++b) {
        h ^= (bits >> (8 * b)) & 0xffU;
        h *= 1099511628211ULL;
      }
    }
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    mix(p.position[i]);
    mix(p.velocity[i]);
    mix(p.angularVelocity[i]);
  }
  return h;
}

}  // namespace granular
