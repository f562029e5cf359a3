#pragma once
/// Time integrators acting on (position, velocity, Derivatives) triples; they know nothing of
/// contacts. Used for translation (x, v) and rotation (ω only: a null `x` skips the positions,
/// since a sphere's orientation feeds back into nothing).
#include <functional>
#include <vector>

#include "simulation_state.hpp"

namespace granular {

/// One kind of motion as flat arrays of 3n doubles: x (null for rotation, whose "position" is
/// not kept), v and the derivatives (d3..d5 null for Verlet). Eigen stores a Vector3d as three
/// contiguous doubles, so a std::vector<Vec3> is such an array; over it the loops below
/// vectorise without shuffling x, y, z.
struct FlatMotion {
  double* x = nullptr;
  double* v = nullptr;
  double *d2 = nullptr, *d3 = nullptr, *d4 = nullptr, *d5 = nullptr;
  static FlatMotion of(std::vector<Vec3>* x, std::vector<Vec3>& v, Derivatives& d);
};

/// Bits of the int the loops below return: which of the values they wrote came out not finite.
/// Plain int bits, not an enum class, because overRanges and the force pass OR them over ranges
/// and threads with OpenMP's `reduction(|)`.
struct NotFinite {
  /// A corrected (Gear) or kicked (Verlet) value: this step's state is broken.
  static constexpr int kCorrected = 1 << 0;
  /// A drifted position, Verlet's prediction for the next step (Gear's predictor checks none):
  /// the next step's state is broken.
  static constexpr int kPredicted = 1 << 1;
};

/// The integrators' loops over the values [b, e) of a motion (3 per particle). Each value is
/// computed alone, so any split into ranges gives the same bits; each returns its NotFinite bits
/// (x·0 != 0 flags NaN and ±∞ in the same pass).
int gearPredictRange(const FlatMotion& m, double dt, std::size_t b, std::size_t e);
int gearCorrectRange(const FlatMotion& m, const double* accel, double dt, std::size_t b,
                     std::size_t e);
int verletDriftRange(const FlatMotion& m, double dt, std::size_t b, std::size_t e);
int verletKickRange(const FlatMotion& m, const double* accel, double dt, std::size_t b,
                    std::size_t e);
/// A step's corrector (kick) and the next step's predictor (drift) in one loop over [b, e), the
/// same bits as the two loops one after the other. NotFinite::kCorrected: a corrected value is
/// not finite; NotFinite::kPredicted: a predicted position (Verlet only).
int gearCorrectPredictRange(const FlatMotion& m, const double* accel, double dt, std::size_t b,
                            std::size_t e);
int verletKickDriftRange(const FlatMotion& m, const double* accel, double dt, std::size_t b,
                         std::size_t e);
/// Over particles [b, e), in place: force → acceleration F/m + g and, with `torque`, torque →
/// angular acceleration T/I (I = 0.4 m r²).
void accelerationsRange(std::vector<Vec3>& force, std::vector<Vec3>* torque, const Particles& p,
                        const Vec3& g, std::size_t b, std::size_t e);

/// Runs `loop(begin, end)` over [0, n) split into one contiguous range per thread (0: OpenMP's
/// default count) and ORs the NotFinite bits the ranges return; one thread runs it in place,
/// with no parallel region. The loops are functions of a range rather than `omp parallel for`
/// bodies because GCC does not vectorise an outlined parallel loop whose pointers come through
/// OpenMP's shared data.
int overRanges(std::size_t n, int threads,
               const std::function<int(std::size_t, std::size_t)>& loop);

/// Gear's 6-value (5th-order) predictor-corrector for x'' = f(x, x').
///
/// Predictor: Taylor series of x and its derivatives to 5th order. Corrector, with
/// δ = a(predicted state) - a_predicted and Δ = δ·Δt²/2 in the scaled (Nordsieck) variables
/// r_k = x^(k) Δt^k / k!:  r_k += c_k Δ, with
///   c = {3/20, 251/360, 1, 11/18, 1/6, 1/60}.
/// Gear's c0 for position-only forces is 3/16; for forces that depend on the velocity (the
/// dashpots γn, γt here) Gear gives c0 = 3/20 (Allen & Tildesley, Computer Simulation of Liquids,
/// App. E), which keeps the scheme's order for x'' = f(x, x').
struct Gear5 {
  static constexpr double kC0 = 3.0 / 20.0, kC1 = 251.0 / 360.0, kC2 = 1.0, kC3 = 11.0 / 18.0,
                          kC4 = 1.0 / 6.0, kC5 = 1.0 / 60.0;
  /// Element-wise loops, run on `threads` threads (0: OpenMP's default); the result does not
  /// depend on the count.
  static void predict(std::vector<Vec3>* x, std::vector<Vec3>& v, Derivatives& d, double dt,
                      int threads = 1);
  /// `accel` is the acceleration evaluated at the predicted state. Returns false if a corrected
  /// position or velocity is not finite (checked in the same loop: no extra pass).
  static bool correct(std::vector<Vec3>* x, std::vector<Vec3>& v, Derivatives& d,
                      const std::vector<Vec3>& accel, double dt, int threads = 1);
};

/// Velocity Verlet. The dashpots need the velocity at the new time, which Verlet only knows
/// after the force: the force is evaluated with the predicted velocity v_n + a_n Δt, and the
/// kick then completes v_{n+1} = v_n + (a_n + a_{n+1}) Δt/2. Evaluating with the half-step
/// velocity instead would make the scheme first order for velocity-dependent forces.
struct VelocityVerlet {
  /// x += v Δt + a Δt²/2; v += a Δt (the predicted velocity). Returns false if a new position
  /// is not finite.
  static bool drift(std::vector<Vec3>* x, std::vector<Vec3>& v, const Derivatives& d, double dt,
                    int threads = 1);
  /// v += (accel - a) Δt/2; a = accel. Returns false if a new velocity is not finite.
  static bool kick(std::vector<Vec3>& v, Derivatives& d, const std::vector<Vec3>& accel, double dt,
                   int threads = 1);
};

}  // namespace granular
