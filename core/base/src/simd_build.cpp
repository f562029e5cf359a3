/// The process's vector build (granular/simd_build.hpp).
#include "granular/simd_build.hpp"

namespace granular {
namespace {

SimdBuild& selected() {
  static SimdBuild build = cpuHasAvx2() ? SimdBuild::Avx2 : SimdBuild::Baseline;
  return build;
}

}  // namespace

bool cpuHasAvx2() {
#if GRANULAR_AVX2_BUILD
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

SimdBuild simdBuild() {
  return selected();
}

bool setSimdBuild(SimdBuild build) {
  if (build == SimdBuild::Avx2 && !cpuHasAvx2()) return false;
  selected() = build;
  return true;
}

}  // namespace granular
