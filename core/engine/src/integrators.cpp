#include "integrators.hpp"

#include <omp.h>

#include <algorithm>
#include <utility>

#include "force_pass.hpp"
#include "granular/simd_build.hpp"

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

// Each scheme's update of one value is written once, as a step on locals; the loops below
// compose them, so a step's corrector followed by the next step's predictor in one loop does
// exactly what the two loops do one after the other (the same bits by construction).

/// Gear's predictor for one value: Horner forms of the Taylor series x(t+Δt) = Σ x^(k) Δt^k / k!,
/// each from the values before the step (x from the old v, v from the old a, ...).
struct GearPredictor {
  double dt, h2, h3, h4, h5;
  explicit GearPredictor(double step)
      : dt(step), h2(step / 2.0), h3(step / 3.0), h4(step / 4.0), h5(step / 5.0) {}
  template <bool kPositions>
  [[gnu::always_inline]] void operator()(double& x, double& v, double& a, double& p3, double& p4,
                                         double p5) const {
    if constexpr (kPositions) x += dt * (v + h2 * (a + h3 * (p3 + h4 * (p4 + h5 * p5))));
    v += dt * (a + h2 * (p3 + h3 * (p4 + h4 * p5)));
    a = a + dt * (p3 + h2 * (p4 + h3 * p5));
    p3 = p3 + dt * (p4 + h2 * p5);
    p4 = p4 + dt * p5;
  }
};

/// Gear's corrector for one value: r_k += c_k Δ with Δ = δ Δt²/2, unscaled: x^(k) += c_k Δ
/// k!/Δt^k, δ the acceleration at the predicted state minus the predicted one.
struct GearCorrector {
  double sx, sv, s3, s4, s5;
  explicit GearCorrector(double dt)
      : sx(Gear5::kC0 * dt * dt / 2.0),
        sv(Gear5::kC1 * dt / 2.0),
        s3(Gear5::kC3 * 3.0 / dt),
        s4(Gear5::kC4 * 12.0 / (dt * dt)),
        s5(Gear5::kC5 * 60.0 / (dt * dt * dt)) {}
  template <bool kPositions>
  [[gnu::always_inline]] void operator()(double accel, double& x, double& v, double& a, double& p3,
                                         double& p4, double& p5) const {
    const double delta = accel - a;
    if constexpr (kPositions) x += sx * delta;
    v += sv * delta;
    a += Gear5::kC2 * delta;
    p3 += s3 * delta;
    p4 += s4 * delta;
    p5 += s5 * delta;
  }
};

/// Gear over [b, e): the corrector (with accel), the predictor, or the one then the other; with
/// x also the positions (translation), without only the velocity and its derivatives
/// (rotation). NotFinite::kCorrected if a corrected position or velocity is not finite.
template <bool kPositions, bool kCorrect, bool kPredict>
[[gnu::always_inline]] inline int gearLoop(double* __restrict x, double* __restrict v,
                                           double* __restrict d2, double* __restrict d3,
                                           double* __restrict d4, double* __restrict d5,
                                           const double* __restrict accel, double dt, std::size_t b,
                                           std::size_t e) {
  const GearCorrector correct(dt);
  const GearPredictor predict(dt);
  double probe = 0.0;
#pragma omp simd reduction(+ : probe)
  for (std::size_t k = b; k < e; ++k) {
    double xk = 0.0, vk = v[k], a = d2[k], p3 = d3[k], p4 = d4[k], p5 = d5[k];
    if constexpr (kPositions) xk = x[k];
    if constexpr (kCorrect) {
      correct.template operator()<kPositions>(accel[k], xk, vk, a, p3, p4, p5);
      probe += (kPositions ? xk : 0.0) * 0.0 + vk * 0.0;
    }
    if constexpr (kPredict) predict.template operator()<kPositions>(xk, vk, a, p3, p4, p5);
    if constexpr (kPositions) x[k] = xk;
    v[k] = vk;
    d2[k] = a;
    d3[k] = p3;
    d4[k] = p4;
    if constexpr (kCorrect) d5[k] = p5;  // the predictor leaves it
  }
  return probe != 0.0 ? NotFinite::kCorrected : 0;
}

/// Velocity Verlet's two halves for one value, in the half-step form the peers use. Drift: the
/// half kick v_½ = v + a Δt/2, then x += v_½ Δt; the velocity held between them is v_½, at which
/// the force pass evaluates the dashpots and advances the springs (ξ then moves by exactly the
/// drift's displacement). Kick: v = v_½ + accel Δt/2, a = accel. (With v held at the predicted
/// v + a Δt instead, the dashpots act on a velocity a whole step ahead, and a damped network
/// breaks at 14× the paper's step where this form holds to 16×: bench/RESULTS.md.)
struct VerletSteps {
  double dt, half;
  explicit VerletSteps(double step) : dt(step), half(0.5 * step) {}
  template <bool kPositions>
  [[gnu::always_inline]] void drift(double& x, double& v, double a) const {
    const double vk = v + half * a;
    if constexpr (kPositions) x += dt * vk;
    v = vk;
  }
  [[gnu::always_inline]] void kick(double accel, double& v, double& a) const {
    v += half * accel;
    a = accel;
  }
};

/// Verlet over [b, e): the kick (with accel), the drift, or the one then the other.
/// NotFinite::kCorrected: a kicked velocity is not finite; NotFinite::kPredicted: a drifted
/// position.
template <bool kPositions, bool kKick, bool kDrift>
[[gnu::always_inline]] inline int verletLoop(double* __restrict x, double* __restrict v,
                                             double* __restrict a, const double* __restrict accel,
                                             double dt, std::size_t b, std::size_t e) {
  const VerletSteps steps(dt);
  double kicked = 0.0, drifted = 0.0;
#pragma omp simd reduction(+ : kicked, drifted)
  for (std::size_t k = b; k < e; ++k) {
    double xk = 0.0, vk = v[k], ak = a[k];
    if constexpr (kPositions && kDrift) xk = x[k];
    if constexpr (kKick) {
      steps.kick(accel[k], vk, ak);
      kicked += vk * 0.0;
    }
    if constexpr (kDrift) {
      steps.drift<kPositions>(xk, vk, ak);
      if constexpr (kPositions) drifted += xk * 0.0;
    }
    if constexpr (kPositions && kDrift) x[k] = xk;
    v[k] = vk;
    if constexpr (kKick) a[k] = ak;
  }
  return (kicked != 0.0 ? NotFinite::kCorrected : 0) | (drifted != 0.0 ? NotFinite::kPredicted : 0);
}

}  // namespace

int overRanges(std::size_t n, int threads,
               const std::function<int(std::size_t, std::size_t)>& loop) {
  const int count = threads > 0 ? threads : omp_get_max_threads();
  if (count == 1) return loop(std::size_t{0}, n);
  int notFinite = 0;
#pragma omp parallel num_threads(count) reduction(| : notFinite)
  {
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
    const std::size_t parts = static_cast<std::size_t>(omp_get_num_threads());
    notFinite |= loop(n * t / parts, n * (t + 1) / parts);
  }
  return notFinite;
}

FlatMotion FlatMotion::of(std::vector<Vec3>* x, std::vector<Vec3>& v, Derivatives& d) {
  return {flat(x), flat(v), flat(d.d2), flat(d.d3), flat(d.d4), flat(d.d5)};
}

namespace {

// The range loops in two builds, as the law's kernels (chunk_kernels.cpp): the baseline x86-64
// one and AVX2, chosen by simdBuild() (granular/simd_build.hpp). Both give the same bits (every
// value is computed alone, no fused multiply-add; the probe is a sum of zeros or NaN).

/// A Gear or Verlet loop over a FlatMotion, with or without positions.
template <bool kCorrect, bool kPredict>
[[gnu::always_inline]] inline int gearBody(const FlatMotion& m, const double* accel, double dt,
                                           std::size_t b, std::size_t e) {
  return m.x ? gearLoop<true, kCorrect, kPredict>(m.x, m.v, m.d2, m.d3, m.d4, m.d5, accel, dt, b, e)
             : gearLoop<false, kCorrect, kPredict>(nullptr, m.v, m.d2, m.d3, m.d4, m.d5, accel, dt,
                                                   b, e);
}
template <bool kKick, bool kDrift>
[[gnu::always_inline]] inline int verletBody(const FlatMotion& m, const double* accel, double dt,
                                             std::size_t b, std::size_t e) {
  return m.x ? verletLoop<true, kKick, kDrift>(m.x, m.v, m.d2, accel, dt, b, e)
             : verletLoop<false, kKick, kDrift>(nullptr, m.v, m.d2, accel, dt, b, e);
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

}  // namespace

int gearPredictRange(const FlatMotion& m, double dt, std::size_t b, std::size_t e) {
  return simdDispatch<gearBody<false, true>>(m, nullptr, dt, b, e);
}

int gearCorrectRange(const FlatMotion& m, const double* accel, double dt, std::size_t b,
                     std::size_t e) {
  return simdDispatch<gearBody<true, false>>(m, accel, dt, b, e);
}

int verletDriftRange(const FlatMotion& m, double dt, std::size_t b, std::size_t e) {
  return simdDispatch<verletBody<false, true>>(m, nullptr, dt, b, e);
}

int verletKickRange(const FlatMotion& m, const double* accel, double dt, std::size_t b,
                    std::size_t e) {
  return simdDispatch<verletBody<true, false>>(m, accel, dt, b, e);
}

int gearCorrectPredictRange(const FlatMotion& m, const double* accel, double dt, std::size_t b,
                            std::size_t e) {
  return simdDispatch<gearBody<true, true>>(m, accel, dt, b, e);
}

int verletKickDriftRange(const FlatMotion& m, const double* accel, double dt, std::size_t b,
                         std::size_t e) {
  return simdDispatch<verletBody<true, true>>(m, accel, dt, b, e);
}

void accelerationsRange(std::vector<Vec3>& force, std::vector<Vec3>* torque, const Particles& p,
                        const Vec3& g, std::size_t b, std::size_t e) {
  simdDispatch<accelerationsBody>(flat(force), torque ? flat(*torque) : nullptr, p.mass.data(),
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
