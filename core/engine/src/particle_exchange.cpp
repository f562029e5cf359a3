/// Particles and walls that come and go between steps: Simulation::exchangeParticles (a silo's
/// filling and outlet), its tallies, and Simulation::removeWall (a gate opened).
///
/// An exchange renumbers the particles: the survivors keep their order, the inserted follow. The
/// neighbour list is renumbered alike before it is rebuilt, so that the rebuild carries the
/// springs of every surviving pair and wall contact as it does between two steps.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "config_validation.hpp"
#include "domain_split.hpp"
#include "energy_ledger.hpp"
#include "force_pass.hpp"
#include "granular/contact_model.hpp"
#include "pair_springs.hpp"
#include "particle_fields.hpp"
#include "run_partition.hpp"
#include "simulation_passes.hpp"
#include "simulation_state.hpp"
#include "step_check.hpp"

namespace granular {

namespace {

constexpr std::uint32_t kGone = std::numeric_limits<std::uint32_t>::max();

/// Keeps the entries k of `v` with keep(k), in order.
template <class T, class Keep>
void keepEntries(std::vector<T>& v, Keep keep) {
  std::size_t to = 0;
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (keep(k)) v[to++] = v[k];
  }
  v.resize(to);
}

/// The list's pairs and wall entries of the surviving particles, under their new indices
/// (newIndex[i], kGone for a removed one), for n particles; marked stale, so that the next
/// rebuild carries their springs to the new list.
void renumberList(NeighbourList& list, const std::vector<std::uint32_t>& newIndex, std::size_t n,
                  bool frictional) {
  if (list.rowStart.size() == newIndex.size() + 1) {
    const std::vector<std::uint32_t> first = firstOfPairs(list);
    std::vector<ContactHistory> springs;
    if (frictional && !list.blockPair.empty()) springs = perPairSprings(list);
    const unsigned optional = list.springs.optional;
    std::vector<std::uint32_t> keptFirst, keptSecond;
    std::vector<ContactHistory> keptSprings;
    for (std::size_t k = 0; k < first.size(); ++k) {
      const std::uint32_t i = newIndex[first[k]], j = newIndex[list.second[k]];
      if (i == kGone || j == kGone) continue;
      keptFirst.push_back(i);
      keptSecond.push_back(j);
      if (!springs.empty()) keptSprings.push_back(springs[k]);
    }
    // Renumbering keeps the order (survivors keep theirs), so the pairs stay sorted.
    rowsFromFirst(list, keptFirst, n);
    list.second = std::move(keptSecond);
    buildPairBlocks(list, n);
    if (frictional) layOutPairSprings(list, keptSprings, optional);
  } else {
    list.rowStart.assign(n + 1, 0);
    list.second.clear();
    buildPairBlocks(list, n);
    list.springs = PairSprings{};
  }
  for (std::size_t w = 0; w < list.wallParticles.size(); ++w) {
    std::vector<std::uint32_t>& candidates = list.wallParticles[w];
    auto survives = [&](std::size_t k) { return newIndex[candidates[k]] != kGone; };
    if (w < list.wallHistory.size() && list.wallHistory[w].size() == candidates.size()) {
      keepEntries(list.wallHistory[w], survives);
    }
    if (w < list.wallNormal.size() && list.wallNormal[w].size() == candidates.size()) {
      keepEntries(list.wallNormal[w], survives);
    }
    keepEntries(candidates, survives);
    for (std::uint32_t& i : candidates) i = newIndex[i];
  }
  // The candidates' triangles go with the rebuild that follows.
  list.meshTriangleStart.clear();
  list.meshTriangles.clear();
  list.valid = false;
  list.plan.valid = false;
}

/// Refuses (ConfigError) an exchange whose indices are not ascending, distinct and below n, or
/// whose inserted particles are not valid for the run.
void validateExchange(const SimulationState& s, const ParticleExchange& x, std::size_t n) {
  for (std::size_t k = 0; k < x.remove.size(); ++k) {
    requireConfig(x.remove[k] < n, "exchange: particle " + std::to_string(x.remove[k]) +
                                       " to remove; the run holds " + std::to_string(n));
    requireConfig(k == 0 || x.remove[k] > x.remove[k - 1],
                  "exchange: the particles to remove are not ascending and distinct");
  }
  const Particles& add = x.insert;
  forEachParticleField(add, [&](const FieldSpec& field, const auto& array) {
    requireConfig(array.size() == add.size(),
                  "exchange: " + std::to_string(array.size()) + " " + std::string(field.name) +
                      "s for " + std::to_string(add.size()) + " inserted positions");
  });
  for (std::size_t i = 0; i < add.size(); ++i) {
    const std::string which = "exchange: inserted particle " + std::to_string(i) + ": ";
    requireConfig(std::isfinite(add.radius[i]) && add.radius[i] > 0,
                  which + "radius " + shortNumber(add.radius[i]) + " m must be > 0");
    requireConfig(add.radius[i] >= s.contactScale.radius,
                  which + "radius " + shortNumber(add.radius[i]) +
                      " m is below the smallest the run was set up for, " +
                      shortNumber(s.contactScale.radius) + " m (SimulationConfig::smallestRadius)");
    requireConfig(std::isfinite(add.mass[i]) && add.mass[i] > 0,
                  which + "mass " + shortNumber(add.mass[i]) + " kg must be > 0");
    forEachParticleField(add, [&](const FieldSpec& field, const auto& array) {
      if constexpr (std::is_same_v<std::remove_cvref_t<decltype(array[i])>, Vec3>) {
        requireConfig(array[i].allFinite(), which + std::string(field.name) + " is not finite");
      }
    });
  }
}

/// The contact forces, torques and powers at the current state for the outputs, the books and
/// the accelerations of particles that had none, leaving the springs as the last step left
/// them: a pass of dt = 0 still caps a sliding contact's spring at its dashpot of the moment,
/// which would make the next step differ from a run without the exchange.
void evaluateForcesKeepingSprings(SimulationState& s) {
  NeighbourList& list = s.neighbours;
  PairSprings springs = list.springs;
  std::vector<std::vector<ContactHistory>> wallHistory = list.wallHistory;
  std::vector<std::vector<Vec3>> wallNormal = list.wallNormal;
  computeContactForces(s, 0.0);
  list.springs = std::move(springs);
  list.wallHistory = std::move(wallHistory);
  list.wallNormal = std::move(wallNormal);
}

/// The stored energy of each Stored account in the last force evaluation [J].
std::vector<double> storedEnergies(const SimulationState& s) {
  std::vector<double> stored(kEnergySlots, 0.0);
  for (std::size_t slot = 0; slot < kEnergySlots; ++slot) {
    if (kEnergySlotTable[slot].kind == EnergyKind::Stored) stored[slot] = s.powers.energy[slot];
  }
  return stored;
}

/// The exchange on a state held whole by this process (one process's run, or a split run's
/// gathered state): the particles, the list, the forces and the books.
void exchangeWhole(SimulationState& s, const ParticleExchange& x) {
  const double totalBefore = energyBalance(s).total();
  const std::size_t n = s.particles.size();
  validateExchange(s, x, n);
  const double potentialBefore = particleSums(s).potential.value();
  const std::vector<double> storedBefore = storedEnergies(s);

  // Renumber: survivors in order, then the inserted.
  std::vector<std::uint32_t> newIndex(n);
  std::size_t next = 0, r = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool removed = r < x.remove.size() && x.remove[r] == i;
    r += removed ? 1 : 0;
    newIndex[i] = removed ? kGone : std::uint32_t(next++);
    if (removed) {
      s.exchange.removedMass.add(s.particles.mass[i]);
      s.exchange.net.add(-s.particles.mass[i]);
    }
  }
  const std::size_t kept = next, added = x.insert.size();
  auto compact = [&](const FieldSpec& field, auto& array) {
    if (!holds(s, field.needs)) return;  // a field this run does not hold (Gear's with Verlet)
    keepEntries(array, [&](std::size_t i) { return newIndex[i] != kGone; });
  };
  forEachParticleField(s.particles, compact);
  forEachMotionField(s, compact);
  forEachParticleFieldPair(x.insert, s.particles,
                           [&](const FieldSpec&, const auto& from, auto& to) {
                             to.insert(to.end(), from.begin(), from.end());
                           });
  if (!s.frictional) {  // the frictionless path holds no spins
    std::fill(s.particles.angularVelocity.begin() + std::ptrdiff_t(kept),
              s.particles.angularVelocity.end(), Vec3::Zero());
  }
  forEachMotionField(s, [&](const FieldSpec& field, auto& array) {
    if (holds(s, field.needs)) array.resize(kept + added);  // zero: value-initialised
  });
  renumberList(s.neighbours, newIndex, kept + added, s.frictional);

  // The tallies.
  for (double m : x.insert.mass) {
    s.exchange.insertedMass.add(m);
    s.exchange.net.add(m);
  }
  s.exchange.inserted += added;
  s.exchange.removed += x.remove.size();
  if (s.exchange.insertedBy.size() <= x.source) s.exchange.insertedBy.resize(x.source + 1, 0);
  s.exchange.insertedBy[x.source] += added;

  // The list and forces for the new set. The survivors keep their derivatives (the next step's
  // forces correct them); the inserted start from the forces they feel now.
  rebuildList(s);
  evaluateForcesKeepingSprings(s);
  const Particles& p = s.particles;
  for (std::size_t i = kept; i < kept + added; ++i) {
    s.translation.d2[i] = s.force[i] * (1.0 / p.mass[i]) + s.config.gravity;
    if (s.frictional) s.rotation.d2[i] = s.torque[i] * (1.0 / p.inertia(i));
  }
  s.predictedAhead = false;

  // The books: gravity's work and the slip accounts run on through the exchange; the kinetic
  // and stored energy that came and went is the exchanged account.
  s.energy.initialPotential += particleSums(s).potential.value() - potentialBefore;
  const std::vector<double> storedAfter = storedEnergies(s);
  for (std::size_t slot = 0; slot < kEnergySlots; ++slot) {
    s.energy.initialStored[slot] += storedAfter[slot] - storedBefore[slot];
  }
  s.energy.exchanged += energyBalance(s).total() - totalBefore;
}

}  // namespace

void Simulation::exchangeParticles(
    const std::function<ParticleExchange(const Particles& whole)>& decide) {
  SimulationState& s = *state_;
  requireConfig(s.owned.empty() || s.split.domains != nullptr,
                "exchange: a run whose sums are shared among processes (setOwnership) cannot "
                "exchange particles");
  if (s.split.domains == nullptr) {
    const ParticleExchange x = decide(s.particles);
    if (x.remove.empty() && x.insert.size() == 0) return;
    exchangeWhole(s, x);
  } else {
    // A split run exchanges on the gathered whole state, the same on every rank, and splits
    // it again: the same bits as one process's exchange.
    std::unique_ptr<SimulationState> whole = gatherWhole(s);
    whole->partition = &wholeRun();
    const ParticleExchange x = decide(whole->particles);
    if (x.remove.empty() && x.insert.size() == 0) return;
    exchangeWhole(*whole, x);
    std::shared_ptr<const DomainMap> domains = s.split.domains;
    std::shared_ptr<const Communicator> ranks = s.ranks;
    const DomainSplit previous = s.split;
    splitState(*whole, std::move(domains), std::move(ranks));
    whole->split.rebalanceDue = previous.rebalanceDue;
    whole->split.rebalanceAbove = previous.rebalanceAbove;
    whole->partition = &splitRun();
    state_ = std::move(whole);
  }
  if (state_->config.step.automatic) checkStep(*state_);
}

bool Simulation::anyParticleWhere(const std::function<bool(const Vec3& position)>& test) const {
  const Particles& p = state_->particles;
  bool found = false;
  for (std::size_t i = 0; i < p.size() && !found; ++i) {
    found = owns(i) && test(p.position[i]);
  }
  if (const Communicator* r = ranks()) found = r->anyOverRanks(found);
  return found;
}

ParticleTally Simulation::particleTally() const {
  const SimulationState& s = *state_;
  const Particles& p = s.particles;
  ExactSum held, lessHeld;  // Σ m and Σ (−m)
  std::uint64_t count = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!owns(i)) continue;
    held.add(p.mass[i]);
    lessHeld.add(-p.mass[i]);
    ++count;
  }
  if (const Communicator* r = ranks()) {
    std::vector<ExactSum> sums{held, lessHeld};
    r->mergeOverRanks(sums);
    held = sums[0];
    lessHeld = sums[1];
    std::vector<std::uint64_t> counts{count};
    r->sumOverRanks(counts);
    count = counts[0];
  }
  const ExchangeTally& x = s.exchange;
  ParticleTally t;
  t.held = count;
  t.inserted = x.inserted;
  t.removed = x.removed;
  t.heldMass = held.value();
  t.startMass = x.startMass.value();
  t.insertedMass = x.insertedMass.value();
  t.removedMass = x.removedMass.value();
  ExactSum balance = x.net;
  balance.merge(lessHeld);
  t.massBalance = balance.value();
  return t;
}

std::uint64_t Simulation::insertedBy(std::size_t source) const {
  const std::vector<std::uint64_t>& by = state_->exchange.insertedBy;
  return source < by.size() ? by[source] : 0;
}

void Simulation::removeWall(std::size_t wall) {
  SimulationState& s = *state_;
  requireConfig(wall < s.walls.size(), "remove wall: no wall " + std::to_string(wall) + " of " +
                                           std::to_string(s.walls.size()));
  Wall& w = s.walls[wall];
  if (w.removed) return;
  w.removed = true;
  w.velocity = Vec3::Zero();
  w.angularVelocity = Vec3::Zero();
  s.neighbours.valid = false;  // the rebuild drops its candidates and their springs
  rebuildList(s);
  evaluateForcesKeepingSprings(s);  // the reactions and the books without it
  startAccelerations(s);
}

}  // namespace granular
