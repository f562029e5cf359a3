#include "integrators.hpp"

#include <omp.h>

namespace granular {
namespace {

int threadCount(int threads) {
  return threads > 0 ? threads : omp_get_max_threads();
}

/// A Vec3 array as its 3n doubles: the loops below act on each component alike, and over a flat
/// array the compiler vectorises them without shuffling x, y, z. Eigen stores a Vector3d as
/// three contiguous doubles with no padding.
static_assert(sizeof(Vec3) == 3 * sizeof(double));
inline double* flat(std::vector<Vec3>& v) {
  return v.empty() ? nullptr : v.front().data();
}
inline const double* flat(const std::vector<Vec3>& v) {
  return v.empty() ? nullptr : v.front().data();
}
inline double* flat(std::vector<Vec3>* v) {
  return v ? flat(*v) : nullptr;
}

// A NaN or infinite value is caught in the loops that write the state: x·0 is NaN exactly for
// NaN and ±∞, so `x * 0.0 != 0.0` (a quiet comparison) flags them, OR-ed over the loop. It
// checks every value at no extra memory traffic, and OR vectorises where a sum would not.

}  // namespace

namespace {

/// Gear's predictor over n values; with kPositions also x (translation), without only the
/// velocity and its derivatives (rotation).
template <bool kPositions>
void gearPredict(double* __restrict x, double* __restrict v, Derivatives& d, std::size_t n,
                 double dt, int threads) {
  double* __restrict d2 = flat(d.d2);
  double* __restrict d3 = flat(d.d3);
  double* __restrict d4 = flat(d.d4);
  const double* __restrict d5 = flat(d.d5);
  const double h2 = dt / 2.0, h3 = dt / 3.0, h4 = dt / 4.0, h5 = dt / 5.0;
#pragma omp parallel for simd schedule(static) num_threads(threadCount(threads))
  for (std::size_t k = 0; k < n; ++k) {
    const double a = d2[k], b = d3[k], c = d4[k], e = d5[k];
    // Horner forms of the Taylor series x(t+Δt) = Σ x^(k) Δt^k / k!.
    if constexpr (kPositions) x[k] += dt * (v[k] + h2 * (a + h3 * (b + h4 * (c + h5 * e))));
    v[k] += dt * (a + h2 * (b + h3 * (c + h4 * e)));
    d2[k] = a + dt * (b + h2 * (c + h3 * e));
    d3[k] = b + dt * (c + h2 * e);
    d4[k] = c + dt * e;
  }
}

/// Gear's corrector over n values; returns nonzero if a value it wrote is not finite.
template <bool kPositions>
int gearCorrect(double* __restrict x, double* __restrict v, Derivatives& d,
                const double* __restrict accel, std::size_t n, double dt, int threads) {
  double* __restrict d2 = flat(d.d2);
  double* __restrict d3 = flat(d.d3);
  double* __restrict d4 = flat(d.d4);
  double* __restrict d5 = flat(d.d5);
  // r_k += c_k Δ with Δ = δ Δt²/2, unscaled: x^(k) += c_k Δ k!/Δt^k.
  const double sx = Gear5::kC0 * dt * dt / 2.0, sv = Gear5::kC1 * dt / 2.0,
               s3 = Gear5::kC3 * 3.0 / dt, s4 = Gear5::kC4 * 12.0 / (dt * dt),
               s5 = Gear5::kC5 * 60.0 / (dt * dt * dt);
  int broken = 0;
#pragma omp parallel for simd schedule(static) num_threads(threadCount(threads)) \
    reduction(|                                                                  \
              : broken)
  for (std::size_t k = 0; k < n; ++k) {
    const double delta = accel[k] - d2[k];
    if constexpr (kPositions) {
      x[k] += sx * delta;
      broken |= x[k] * 0.0 != 0.0;
    }
    v[k] += sv * delta;
    d2[k] += Gear5::kC2 * delta;
    d3[k] += s3 * delta;
    d4[k] += s4 * delta;
    d5[k] += s5 * delta;
    broken |= v[k] * 0.0 != 0.0;
  }
  return broken;
}

}  // namespace

void Gear5::predict(std::vector<Vec3>* x, std::vector<Vec3>& v, Derivatives& d, double dt,
                    int threads) {
  if (x) {
    gearPredict<true>(flat(x), flat(v), d, 3 * v.size(), dt, threads);
  } else {
    gearPredict<false>(nullptr, flat(v), d, 3 * v.size(), dt, threads);
  }
}

bool Gear5::correct(std::vector<Vec3>* x, std::vector<Vec3>& v, Derivatives& d,
                    const std::vector<Vec3>& accel, double dt, int threads) {
  const int broken =
      x ? gearCorrect<true>(flat(x), flat(v), d, flat(accel), 3 * v.size(), dt, threads)
        : gearCorrect<false>(nullptr, flat(v), d, flat(accel), 3 * v.size(), dt, threads);
  return broken == 0;
}

bool VelocityVerlet::drift(std::vector<Vec3>* positions, std::vector<Vec3>& velocities,
                           const Derivatives& d, double dt, int threads) {
  const std::size_t n = 3 * velocities.size();
  double* __restrict x = flat(positions);
  double* __restrict v = flat(velocities);
  const double* __restrict a = flat(d.d2);
  const double half = 0.5 * dt;
  int broken = 0;
#pragma omp parallel for simd schedule(static) num_threads(threadCount(threads)) \
    reduction(|                                                                  \
              : broken)
  for (std::size_t k = 0; k < n; ++k) {
    double vk = v[k] + half * a[k];
    if (x) {
      x[k] += dt * vk;
      broken |= x[k] * 0.0 != 0.0;
    }
    vk += half * a[k];
    v[k] = vk;
  }
  return broken == 0;
}

bool VelocityVerlet::kick(std::vector<Vec3>& velocities, Derivatives& d,
                          const std::vector<Vec3>& accelerations, double dt, int threads) {
  const std::size_t n = 3 * velocities.size();
  double* __restrict v = flat(velocities);
  double* __restrict a = flat(d.d2);
  const double* __restrict accel = flat(accelerations);
  const double half = 0.5 * dt;
  int broken = 0;
#pragma omp parallel for simd schedule(static) num_threads(threadCount(threads)) \
    reduction(|                                                                  \
              : broken)
  for (std::size_t k = 0; k < n; ++k) {
    v[k] += half * (accel[k] - a[k]);
    a[k] = accel[k];
    broken |= v[k] * 0.0 != 0.0;
  }
  return broken == 0;
}

}  // namespace granular
