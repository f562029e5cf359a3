#pragma once
/// The one choice of vector build for the whole process: the contact law's loops, the
/// integrators and the exact sums are each compiled twice, for the baseline x86-64 (SSE2, 2
/// doubles an instruction) and for AVX2 (4), and `simdDispatch` runs the build chosen here. The
/// builds give the same bits (no reductions, no fused multiply-add in the loops); tests switch
/// between them to compare. A build with GRANULAR_BASELINE_ONLY defined (the sanitizer builds,
/// whose instrumentation is the same for both) compiles the baseline alone.
#include <utility>

#if defined(__x86_64__) && !defined(GRANULAR_BASELINE_ONLY)
#define GRANULAR_AVX2_BUILD 1
#endif

namespace granular {

enum class SimdBuild { Baseline, Avx2 };

/// True where the CPU runs AVX2 and the program has the AVX2 build.
bool cpuHasAvx2();
/// The build in use: AVX2 where the CPU has it, else the baseline.
SimdBuild simdBuild();
/// Selects a build for the whole process; false (and nothing changed) if the CPU lacks it.
/// Not thread-safe: call it before stepping.
bool setSimdBuild(SimdBuild build);

/// Runs `kBody` compiled for the baseline, or for AVX2 (the body is inlined into each, so the
/// whole loop is built for that target; nothing shared, std:: or Eigen, is).
template <auto kBody, class... Args>
auto inBaseline(Args&&... args) {
  return kBody(std::forward<Args>(args)...);
}
#if GRANULAR_AVX2_BUILD
template <auto kBody, class... Args>
[[gnu::target("avx2")]] auto inAvx2(Args&&... args) {
  return kBody(std::forward<Args>(args)...);
}
#endif

/// Runs `kBody` in the build simdBuild() selects.
template <auto kBody, class... Args>
auto simdDispatch(Args&&... args) {
#if GRANULAR_AVX2_BUILD
  if (simdBuild() == SimdBuild::Avx2) return inAvx2<kBody>(std::forward<Args>(args)...);
#endif
  return inBaseline<kBody>(std::forward<Args>(args)...);
}

}  // namespace granular
