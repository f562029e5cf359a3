#include "integrators.hpp"

#include <omp.h>

namespace granular {
namespace {

int threadCount(int threads) {
  return threads > 0 ? threads : omp_get_max_threads();
}

/// 0 for a finite vector, NaN otherwise (x·0 is NaN exactly for NaN and ±∞, and a sum of
/// such marks cannot overflow the way a sum of the values could). Summed in the loops that
/// write the state, it checks every particle at no extra memory traffic.
inline double nonFiniteMark(const Vec3& v) {
  return v.x() * 0.0 + v.y() * 0.0 + v.z() * 0.0;
}

}  // namespace

void Gear5::predict(std::vector<Vec3>* positions, std::vector<Vec3>& v, Derivatives& d, double dt,
                    int threads) {
  const std::size_t n = v.size();
  Vec3* x = positions ? positions->data() : nullptr;
#pragma omp parallel for schedule(static) num_threads(threadCount(threads))
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 a = d.d2[i], b = d.d3[i], c = d.d4[i], e = d.d5[i];
    // Horner forms of the Taylor series x(t+Δt) = Σ x^(k) Δt^k / k!.
    if (x) x[i] += dt * (v[i] + dt / 2.0 * (a + dt / 3.0 * (b + dt / 4.0 * (c + dt / 5.0 * e))));
    v[i] += dt * (a + dt / 2.0 * (b + dt / 3.0 * (c + dt / 4.0 * e)));
    d.d2[i] = a + dt * (b + dt / 2.0 * (c + dt / 3.0 * e));
    d.d3[i] = b + dt * (c + dt / 2.0 * e);
    d.d4[i] = c + dt * e;
  }
}

bool Gear5::correct(std::vector<Vec3>* positions, std::vector<Vec3>& v, Derivatives& d,
                    const std::vector<Vec3>& accel, double dt, int threads) {
  const std::size_t n = v.size();
  Vec3* x = positions ? positions->data() : nullptr;
  // r_k += c_k Δ with Δ = δ Δt²/2, unscaled: x^(k) += c_k Δ k!/Δt^k.
  const double sx = kC0 * dt * dt / 2.0, sv = kC1 * dt / 2.0, s3 = kC3 * 3.0 / dt,
               s4 = kC4 * 12.0 / (dt * dt), s5 = kC5 * 60.0 / (dt * dt * dt);
  double broken = 0.0;
#pragma omp parallel for schedule(static) num_threads(threadCount(threads)) reduction(+ : broken)
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 delta = accel[i] - d.d2[i];
    if (x) x[i] += sx * delta;
    v[i] += sv * delta;
    d.d2[i] += kC2 * delta;
    d.d3[i] += s3 * delta;
    d.d4[i] += s4 * delta;
    d.d5[i] += s5 * delta;
    broken += nonFiniteMark(v[i]) + (x ? nonFiniteMark(x[i]) : 0.0);
  }
  return broken == 0.0;  // false for NaN
}

bool VelocityVerlet::drift(std::vector<Vec3>* positions, std::vector<Vec3>& v, const Derivatives& d,
                           double dt, int threads) {
  Vec3* x = positions ? positions->data() : nullptr;
  double broken = 0.0;
#pragma omp parallel for schedule(static) num_threads(threadCount(threads)) reduction(+ : broken)
  for (std::size_t i = 0; i < v.size(); ++i) {
    v[i] += 0.5 * dt * d.d2[i];
    if (x) x[i] += dt * v[i];
    v[i] += 0.5 * dt * d.d2[i];
    if (x) broken += nonFiniteMark(x[i]);
  }
  return broken == 0.0;  // false for NaN
}

bool VelocityVerlet::kick(std::vector<Vec3>& v, Derivatives& d, const std::vector<Vec3>& accel,
                          double dt, int threads) {
  double broken = 0.0;
#pragma omp parallel for schedule(static) num_threads(threadCount(threads)) reduction(+ : broken)
  for (std::size_t i = 0; i < v.size(); ++i) {
    v[i] += 0.5 * dt * (accel[i] - d.d2[i]);
    d.d2[i] = accel[i];
    broken += nonFiniteMark(v[i]);
  }
  return broken == 0.0;  // false for NaN
}

}  // namespace granular
