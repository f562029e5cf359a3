#include "integrators.hpp"

#include <omp.h>

#include <algorithm>
#include <utility>

#include "force_pass.hpp"

namespace granular {
namespace {

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
// NaN and ±∞ (and ±0 otherwise), so the sum of x·0 over the loop is NaN if and only if one value
// is not finite, in any order of summation: the result does not depend on the vector width. It
// checks every value at no extra memory traffic. (An OR of `x * 0.0 != 0.0` kept GCC 12 from
// vectorising the loops: they ran one double at a time.)

/// Gear's predictor over [b, e); with x also the positions (translation), without only the
/// velocity and its derivatives (rotation).
template <bool kPositions>
[[gnu::always_inline]] inline int gearPredict(double* __restrict x, double* __restrict v,
                                              double* __restrict d2, double* __restrict d3,
                                              double* __restrict d4, const double* __restrict d5,
                                              double dt, std::size_t b, std::size_t e) {
  const double h2 = dt / 2.0, h3 = dt / 3.0, h4 = dt / 4.0, h5 = dt / 5.0;
  for (std::size_t k = b; k < e; ++k) {
    const double a = d2[k], p3 = d3[k], p4 = d4[k], p5 = d5[k];
    // Horner forms of the Taylor series x(t+Δt) = Σ x^(k) Δt^k / k!.
    if constexpr (kPositions) x[k] += dt * (v[k] + h2 * (a + h3 * (p3 + h4 * (p4 + h5 * p5))));
    v[k] += dt * (a + h2 * (p3 + h3 * (p4 + h4 * p5)));
    d2[k] = a + dt * (p3 + h2 * (p4 + h3 * p5));
    d3[k] = p3 + dt * (p4 + h2 * p5);
    d4[k] = p4 + dt * p5;
  }
  return 0;
}

/// Gear's corrector over [b, e); nonzero if a value it wrote is not finite.
template <bool kPositions>
[[gnu::always_inline]] inline int gearCorrect(double* __restrict x, double* __restrict v,
                                              double* __restrict d2, double* __restrict d3,
                                              double* __restrict d4, double* __restrict d5,
                                              const double* __restrict accel, double dt,
                                              std::size_t b, std::size_t e) {
  // r_k += c_k Δ with Δ = δ Δt²/2, unscaled: x^(k) += c_k Δ k!/Δt^k.
  const double sx = Gear5::kC0 * dt * dt / 2.0, sv = Gear5::kC1 * dt / 2.0,
               s3 = Gear5::kC3 * 3.0 / dt, s4 = Gear5::kC4 * 12.0 / (dt * dt),
               s5 = Gear5::kC5 * 60.0 / (dt * dt * dt);
  double probe = 0.0;
#pragma omp simd reduction(+ : probe)
  for (std::size_t k = b; k < e; ++k) {
    const double delta = accel[k] - d2[k];
    if constexpr (kPositions) {
      x[k] += sx * delta;
      probe += x[k] * 0.0;
    }
    v[k] += sv * delta;
    d2[k] += Gear5::kC2 * delta;
    d3[k] += s3 * delta;
    d4[k] += s4 * delta;
    d5[k] += s5 * delta;
    probe += v[k] * 0.0;
  }
  return probe != 0.0 ? 1 : 0;
}

/// Gear's corrector of one step and predictor of the next over [b, e) in one loop: the
/// corrected values go straight into the prediction, so the eleven arrays are read and written
/// once a step instead of twice. Each value sees the operations of gearCorrect then gearPredict
/// in their order (the same bits). Bit 0: a corrected value is not finite.
template <bool kPositions>
[[gnu::always_inline]] inline int gearCorrectPredict(double* __restrict x, double* __restrict v,
                                                     double* __restrict d2, double* __restrict d3,
                                                     double* __restrict d4, double* __restrict d5,
                                                     const double* __restrict accel, double dt,
                                                     std::size_t b, std::size_t e) {
  const double sx = Gear5::kC0 * dt * dt / 2.0, sv = Gear5::kC1 * dt / 2.0,
               s3 = Gear5::kC3 * 3.0 / dt, s4 = Gear5::kC4 * 12.0 / (dt * dt),
               s5 = Gear5::kC5 * 60.0 / (dt * dt * dt);
  const double h2 = dt / 2.0, h3 = dt / 3.0, h4 = dt / 4.0, h5 = dt / 5.0;
  double probe = 0.0;
#pragma omp simd reduction(+ : probe)
  for (std::size_t k = b; k < e; ++k) {
    const double delta = accel[k] - d2[k];
    const double vk = v[k] + sv * delta;
    const double a = d2[k] + Gear5::kC2 * delta, p3 = d3[k] + s3 * delta, p4 = d4[k] + s4 * delta,
                 p5 = d5[k] + s5 * delta;
    probe += vk * 0.0;
    if constexpr (kPositions) {
      const double xk = x[k] + sx * delta;
      probe += xk * 0.0;
      x[k] = xk + dt * (vk + h2 * (a + h3 * (p3 + h4 * (p4 + h5 * p5))));
    }
    v[k] = vk + dt * (a + h2 * (p3 + h3 * (p4 + h4 * p5)));
    d2[k] = a + dt * (p3 + h2 * (p4 + h3 * p5));
    d3[k] = p3 + dt * (p4 + h2 * p5);
    d4[k] = p4 + dt * p5;
    d5[k] = p5;
  }
  return probe != 0.0 ? 1 : 0;
}

/// Verlet's drift over [b, e): x += v Δt + a Δt²/2 (as two half kicks around the move), v += a Δt.
template <bool kPositions>
[[gnu::always_inline]] inline int verletDrift(double* __restrict x, double* __restrict v,
                                              const double* __restrict a, double dt, std::size_t b,
                                              std::size_t e) {
  const double half = 0.5 * dt;
  double probe = 0.0;
#pragma omp simd reduction(+ : probe)
  for (std::size_t k = b; k < e; ++k) {
    double vk = v[k] + half * a[k];
    if constexpr (kPositions) {
      x[k] += dt * vk;
      probe += x[k] * 0.0;
    }
    vk += half * a[k];
    v[k] = vk;
  }
  return probe != 0.0 ? 1 : 0;
}

/// Verlet's kick over [b, e): v += (accel - a) Δt/2, a = accel.
[[gnu::always_inline]] inline int verletKick(double* __restrict v, double* __restrict a,
                                             const double* __restrict accel, double dt,
                                             std::size_t b, std::size_t e) {
  const double half = 0.5 * dt;
  double probe = 0.0;
#pragma omp simd reduction(+ : probe)
  for (std::size_t k = b; k < e; ++k) {
    v[k] += half * (accel[k] - a[k]);
    a[k] = accel[k];
    probe += v[k] * 0.0;
  }
  return probe != 0.0 ? 1 : 0;
}

/// Verlet's kick of one step and drift of the next over [b, e) in one loop, with the
/// operations of verletKick then verletDrift (the same bits). Bit 0: a kicked velocity is not
/// finite; bit 1: a drifted position.
template <bool kPositions>
[[gnu::always_inline]] inline int verletKickDrift(double* __restrict x, double* __restrict v,
                                                  double* __restrict a,
                                                  const double* __restrict accel, double dt,
                                                  std::size_t b, std::size_t e) {
  const double half = 0.5 * dt;
  double kicked = 0.0, drifted = 0.0;
#pragma omp simd reduction(+ : kicked, drifted)
  for (std::size_t k = b; k < e; ++k) {
    const double ak = accel[k];
    double vk = v[k] + half * (ak - a[k]);
    kicked += vk * 0.0;
    a[k] = ak;
    vk += half * ak;
    if constexpr (kPositions) {
      const double xk = x[k] + dt * vk;
      drifted += xk * 0.0;
      x[k] = xk;
    }
    vk += half * ak;
    v[k] = vk;
  }
  return (kicked != 0.0 ? 1 : 0) | (drifted != 0.0 ? 2 : 0);
}

}  // namespace

int overRanges(std::size_t n, int threads,
               const std::function<int(std::size_t, std::size_t)>& loop) {
  const int count = threads > 0 ? threads : omp_get_max_threads();
  if (count == 1) return loop(std::size_t{0}, n);
  int broken = 0;
#pragma omp parallel num_threads(count) reduction(| : broken)
  {
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
    const std::size_t parts = static_cast<std::size_t>(omp_get_num_threads());
    broken |= loop(n * t / parts, n * (t + 1) / parts);
  }
  return broken;
}

FlatMotion FlatMotion::of(std::vector<Vec3>* x, std::vector<Vec3>& v, Derivatives& d) {
  return {flat(x), flat(v), flat(d.d2), flat(d.d3), flat(d.d4), flat(d.d5)};
}

namespace {

// The range loops in two builds, as the force kernels (force_pass.hpp): the baseline x86-64
// one and AVX2, chosen by forceKernelBuild(). Both give the same bits (every value is computed
// alone, no fused multiply-add; the probe is a sum of zeros or NaN).

[[gnu::always_inline]] inline int gearPredictBody(const FlatMotion& m, double dt, std::size_t b,
                                                  std::size_t e) {
  return m.x ? gearPredict<true>(m.x, m.v, m.d2, m.d3, m.d4, m.d5, dt, b, e)
             : gearPredict<false>(nullptr, m.v, m.d2, m.d3, m.d4, m.d5, dt, b, e);
}
[[gnu::always_inline]] inline int gearCorrectBody(const FlatMotion& m, const double* accel,
                                                  double dt, std::size_t b, std::size_t e) {
  return m.x ? gearCorrect<true>(m.x, m.v, m.d2, m.d3, m.d4, m.d5, accel, dt, b, e)
             : gearCorrect<false>(nullptr, m.v, m.d2, m.d3, m.d4, m.d5, accel, dt, b, e);
}
[[gnu::always_inline]] inline int verletDriftBody(const FlatMotion& m, double dt, std::size_t b,
                                                  std::size_t e) {
  return m.x ? verletDrift<true>(m.x, m.v, m.d2, dt, b, e)
             : verletDrift<false>(nullptr, m.v, m.d2, dt, b, e);
}
[[gnu::always_inline]] inline int verletKickBody(const FlatMotion& m, const double* accel,
                                                 double dt, std::size_t b, std::size_t e) {
  return verletKick(m.v, m.d2, accel, dt, b, e);
}

[[gnu::always_inline]] inline int gearCorrectPredictBody(const FlatMotion& m, const double* accel,
                                                         double dt, std::size_t b, std::size_t e) {
  return m.x ? gearCorrectPredict<true>(m.x, m.v, m.d2, m.d3, m.d4, m.d5, accel, dt, b, e)
             : gearCorrectPredict<false>(nullptr, m.v, m.d2, m.d3, m.d4, m.d5, accel, dt, b, e);
}
[[gnu::always_inline]] inline int verletKickDriftBody(const FlatMotion& m, const double* accel,
                                                      double dt, std::size_t b, std::size_t e) {
  return m.x ? verletKickDrift<true>(m.x, m.v, m.d2, accel, dt, b, e)
             : verletKickDrift<false>(nullptr, m.v, m.d2, accel, dt, b, e);
}

/// a = F/m + g and dω/dt = T/I over particles [b, e), in place; the divisions in blocks that
/// vectorise. I = 0.4 m r² as Particles::inertia computes it (the same bits).
[[gnu::always_inline]] inline void accelerationsBody(double* __restrict force,
                                                     double* __restrict torque,
                                                     const double* __restrict mass,
                                                     const double* __restrict radius, const Vec3& g,
                                                     std::size_t b, std::size_t e) {
  constexpr std::size_t kBlock = 128;
  double inverseMass[kBlock], inverseInertia[kBlock];
  for (std::size_t begin = b; begin < e; begin += kBlock) {
    const std::size_t count = std::min(kBlock, e - begin);
#pragma omp simd
    for (std::size_t k = 0; k < count; ++k) inverseMass[k] = 1.0 / mass[begin + k];
    for (std::size_t k = 0; k < count; ++k) {
      double* f = force + 3 * (begin + k);
      f[0] = f[0] * inverseMass[k] + g.x();
      f[1] = f[1] * inverseMass[k] + g.y();
      f[2] = f[2] * inverseMass[k] + g.z();
    }
    if (!torque) continue;  // frictionless: no rotations
#pragma omp simd
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t i = begin + k;
      inverseInertia[k] = 1.0 / (0.4 * mass[i] * radius[i] * radius[i]);
    }
    for (std::size_t k = 0; k < count; ++k) {
      double* t = torque + 3 * (begin + k);
      t[0] *= inverseInertia[k];
      t[1] *= inverseInertia[k];
      t[2] *= inverseInertia[k];
    }
  }
}

/// Runs `kBody` compiled for the baseline or, with `inAvx2`, for AVX2 (the body is inlined into
/// each, so the whole loop is built for that target).
template <auto kBody, class... Args>
auto inBaseline(Args&&... args) {
  return kBody(std::forward<Args>(args)...);
}
#if defined(__x86_64__)
template <auto kBody, class... Args>
[[gnu::target("avx2")]] auto inAvx2(Args&&... args) {
  return kBody(std::forward<Args>(args)...);
}
#endif

/// The build forceKernelBuild() selects.
template <auto kBody, class... Args>
auto dispatch(Args&&... args) {
#if defined(__x86_64__)
  if (forceKernelBuild() == ForceKernelBuild::Avx2) return inAvx2<kBody>(args...);
#endif
  return inBaseline<kBody>(args...);
}

}  // namespace

int gearPredictRange(const FlatMotion& m, double dt, std::size_t b, std::size_t e) {
  return dispatch<gearPredictBody>(m, dt, b, e);
}

int gearCorrectRange(const FlatMotion& m, const double* accel, double dt, std::size_t b,
                     std::size_t e) {
  return dispatch<gearCorrectBody>(m, accel, dt, b, e);
}

int verletDriftRange(const FlatMotion& m, double dt, std::size_t b, std::size_t e) {
  return dispatch<verletDriftBody>(m, dt, b, e);
}

int verletKickRange(const FlatMotion& m, const double* accel, double dt, std::size_t b,
                    std::size_t e) {
  return dispatch<verletKickBody>(m, accel, dt, b, e);
}

int gearCorrectPredictRange(const FlatMotion& m, const double* accel, double dt, std::size_t b,
                            std::size_t e) {
  return dispatch<gearCorrectPredictBody>(m, accel, dt, b, e);
}

int verletKickDriftRange(const FlatMotion& m, const double* accel, double dt, std::size_t b,
                         std::size_t e) {
  return dispatch<verletKickDriftBody>(m, accel, dt, b, e);
}

void accelerationsRange(std::vector<Vec3>& force, std::vector<Vec3>* torque, const Particles& p,
                        const Vec3& g, std::size_t b, std::size_t e) {
  dispatch<accelerationsBody>(flat(force), torque ? flat(*torque) : nullptr, p.mass.data(),
                              p.radius.data(), g, b, e);
}

void Gear5::predict(std::vector<Vec3>* x, std::vector<Vec3>& v, Derivatives& d, double dt,
                    int threads) {
  const FlatMotion m = FlatMotion::of(x, v, d);
  overRanges(3 * v.size(), threads,
             [&](std::size_t b, std::size_t e) { return gearPredictRange(m, dt, b, e); });
}

bool Gear5::correct(std::vector<Vec3>* x, std::vector<Vec3>& v, Derivatives& d,
                    const std::vector<Vec3>& accel, double dt, int threads) {
  const FlatMotion m = FlatMotion::of(x, v, d);
  return overRanges(3 * v.size(), threads, [&](std::size_t b, std::size_t e) {
           return gearCorrectRange(m, flat(accel), dt, b, e);
         }) == 0;
}

bool VelocityVerlet::drift(std::vector<Vec3>* x, std::vector<Vec3>& v, const Derivatives& d,
                           double dt, int threads) {
  const FlatMotion m = FlatMotion::of(x, v, const_cast<Derivatives&>(d));  // d is only read
  return overRanges(3 * v.size(), threads, [&](std::size_t b, std::size_t e) {
           return verletDriftRange(m, dt, b, e);
         }) == 0;
}

bool VelocityVerlet::kick(std::vector<Vec3>& v, Derivatives& d, const std::vector<Vec3>& accel,
                          double dt, int threads) {
  const FlatMotion m = FlatMotion::of(nullptr, v, d);
  return overRanges(3 * v.size(), threads, [&](std::size_t b, std::size_t e) {
           return verletKickRange(m, flat(accel), dt, b, e);
         }) == 0;
}

}  // namespace granular
