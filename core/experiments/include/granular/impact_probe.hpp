#pragma once
/// A head-on impact of two equal spheres, run through the full engine and measured from the
/// trajectory: the smallest problem on which an integrator's accuracy can be compared with the
/// closed forms of contact_theory.hpp (docs/validation.md §1) and with a run at a much smaller
/// step.
#include <cstdint>
#include <functional>
#include <optional>

#include "granular/contact_theory.hpp"
#include "granular/simulation.hpp"

namespace granular {

/// Two equal spheres on the x axis approaching each other, no gravity, no walls.
struct PairImpactSpec {
  Material material;  ///< contact law and damping of both spheres
  Integrator integrator = Integrator::Gear5;
  double timeStep = 1e-4;      ///< Δt [s]
  double radius = 0.03;        ///< radius of each sphere [m] (the paper's smallest)
  double approachSpeed = 0.5;  ///< relative normal speed before the contact [m/s]
  /// Gap between the surfaces at the start [m]: small, so the run is almost all contact, but
  /// not zero, so the first touch falls inside a step as it does in a real bed.
  double initialGap = 1e-4;
};

/// What an impact produced, measured from the trajectory.
struct ImpactMeasurement {
  /// Between the zero crossings of the overlap, each interpolated linearly inside its step
  /// (exact where the motion is free, i.e. just before the touch and after the separation) [s].
  double overlapDuration = 0;
  double restitution = 0;   ///< relative normal speed after / before [-]
  double peakOverlap = 0;   ///< largest overlap at a step end [m]
  std::uint64_t steps = 0;  ///< steps taken until the separation was seen
  bool separated = false;   ///< false when `maxTime` ran out during the contact
};

/// Steps `sim` until `overlap` (positive while in contact) has gone positive and back to
/// non-positive, or `maxTime` is reached; fills overlapDuration, peakOverlap, steps and
/// separated of the result (restitution is the caller's: it depends on the bodies).
ImpactMeasurement traceContact(Simulation& sim,
                               const std::function<double(const Simulation&)>& overlap,
                               double maxTime);

/// The pair's reduced radius R/2 [m] and mass m/2 [kg] (two equal spheres, docs/physics.md §2.3).
double pairReducedRadius(const PairImpactSpec& spec);
double pairReducedMass(const PairImpactSpec& spec);

/// The closed form for the spec's law: hookeDampedImpact for Hooke (any damping that leaves the
/// contact under-damped; hookeDampedImpactWithPull without the no-pull clamp), hertzUndampedImpact
/// for Hertz without damping; none for damped Hertz.
std::optional<ImpactPrediction> predictPairImpact(const PairImpactSpec& spec);

/// The initial gap [m] that puts the first touch at `phase` ∈ [0, 1) of the third step (two free
/// steps first). The error of a contact that starts inside a step depends on where inside it
/// starts (the force, or for Hertz its derivative, jumps there), so accuracy is judged over
/// several phases: at a single one a coarse step may look lucky.
double gapForTouchPhase(const PairImpactSpec& spec, double phase);

/// Builds the two-sphere simulation on one thread (threads would only add overhead for two
/// particles). Throws ConfigError like Simulation does, e.g. for a step above the stability
/// limit.
Simulation makePairImpact(const PairImpactSpec& spec);

/// Steps a simulation built by makePairImpact until the spheres have touched and separated
/// again, or until its clock reaches `maxTime` [s].
ImpactMeasurement measurePairImpact(Simulation& sim, double approachSpeed, double maxTime);

}  // namespace granular
