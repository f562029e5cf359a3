#pragma once
/// The extreme eigenvalues of the live contact network, estimated rather than bounded
/// (docs/physics.md §2.14): Lanczos on the mass-weighted stiffness matrix A = M^(-1/2) K M^(-1/2)
/// and on the dashpots' D = M^(-1/2) C M^(-1/2) of the same linearisation as the bound
/// (granular/network_frequency.hpp), each a product over the touching contacts, never
/// assembled. Within a few tenths of a per cent of the exact ω_max and Γ after a few tens of
/// products on settled beds (tests/test_network_frequency.cpp), where the bound is 1.3–1.5 ×
/// above; capped by the bound, which stays the outer limit.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "granular/simulation.hpp"

namespace granular {

struct NetworkSpectrum {
  /// √θ for the largest Ritz value θ of A [rad/s], at most the bound's ω_max (0 without
  /// contacts).
  double omegaMax = 0;
  /// The largest Ritz value of D [1/s], at most the bound's Γ.
  double dampingRate = 0;
  /// Each Ritz pair's residual ‖A y − θ y‖ over θ [-]: an eigenvalue of A lies within this
  /// fraction of θ (of D for the second), the estimate's own measure of its convergence.
  double omegaResidual = 0, dampingResidual = 0;
  std::size_t contacts = 0;     ///< touching contacts counted
  std::size_t approaching = 0;  ///< contacts not yet touching counted (the lookahead)
  int products = 0;             ///< matrix–vector products, A's and D's together
};

/// What an estimate leaves for the next one on the same bodies: the Ritz vectors of A and D,
/// over the bodies with contacts by global id (`bodies`). Started from them, an estimate on a
/// network that has changed little needs a few products instead of tens. Not used (a cold
/// start) where another set of bodies has contacts, or the network is too large to keep the
/// Lanczos basis (64 MB).
struct NetworkSpectrumStart {
  std::vector<std::uint64_t> bodies;
  std::vector<double> stiffness, damping;
};

/// Estimates ω_max and Γ of `sim`'s touching contacts and, with `lookahead` > 0 [s], of the
/// contacts about to touch within it, linearised as the bound counts them
/// (granular/network_frequency.hpp), by at most `iterations` Lanczos steps on
/// each matrix (fewer where the Ritz pair's residual falls below `tolerance` of its value),
/// from `start` where it fits and a fixed vector otherwise, on the engine's threads. The
/// contacts are numbered by their bodies' global ids (a run split among processes gathers them
/// all on every process): the same bits on any thread count, any split among processes and
/// any order of the particles in memory. `start` (may be null) then holds this estimate's Ritz
/// vectors. Collective in a split run.
NetworkSpectrum networkSpectrumEstimate(const Simulation& sim, double lookahead = 0.0,
                                        NetworkSpectrumStart* start = nullptr, int iterations = 40,
                                        double tolerance = 1e-2);

}  // namespace granular
