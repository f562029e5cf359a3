#pragma once
/// A stage's particle exchange: the particles its inserts place and its outlets remove, every
/// StageSpec::exchangeInterval of stage time (runStage drives it).
#include <cstdint>
#include <vector>

#include "granular/scene.hpp"
#include "granular/simulation.hpp"

namespace granular {

/// The `wanted` particles an insert places at its exchange number `event` (1, 2, ...), the
/// insert's particles `first`, first + 1, ... (the number it placed before): particle n's radius
/// is drawn from the seed and n alone, uniform in [radiusMin, radiusMax], so that it is the same
/// whether the particle finds room at once or at a later exchange (a radius drawn at each try
/// would favour the small ones, which find room more easily); centres uniform where the sphere
/// lies in the region and touches none of `whole`'s particles, none placed before it and no wall
/// that is not removed; masses from `density` [kg/m³]; the insert's velocity; no spin. A
/// particle that finds no room in 100 tries ends the placement: it and those after it come at a
/// later exchange. The same particles for the same arguments on every platform (SplitMix64 and
/// std::mt19937_64 from the seed, the particle and the event, raw draws made doubles by hand).
Particles placeInserted(const InsertSpec& insert, std::uint64_t wanted, std::uint64_t first,
                        std::uint64_t event, const Particles& whole, const std::vector<Wall>& walls,
                        double density);

/// The particles of `whole` whose centres are in an outlet's region, ascending.
std::vector<std::size_t> particlesInOutlets(const std::vector<OutletSpec>& outlets,
                                            const Particles& whole);

/// A stage's exchanges, at stage times m · exchangeInterval, m = 1, 2, ...
class StageExchange {
 public:
  /// `tolerance` [s]: an exchange due at exactly m · interval happens at the step landing there.
  StageExchange(const StageSpec& stage, double tolerance);
  /// Whether the stage has inserts or outlets at all.
  bool active() const { return active_; }
  /// Continuing the stage at stage time t [s] whose exchanges up to t were all made.
  void resumeAt(double t);
  /// The stage time of the next exchange [s] (+∞ for a stage with none).
  double next() const;
  /// Whether an exchange is due at stage time t [s].
  bool due(double t) const;
  /// Makes the exchanges due at stage time t [s]: each insert adds the particles due by t
  /// (min(count, ⌊rate · t⌋) in all) that are not in yet, the outlets remove theirs.
  void apply(Simulation& sim, double t);
  /// Whether every insert of the stage has placed all its particles.
  bool insertsDone(const Simulation& sim) const;

 private:
  const StageSpec& stage_;
  double tolerance_;
  bool active_;
  std::uint64_t next_ = 1;
};

}  // namespace granular
