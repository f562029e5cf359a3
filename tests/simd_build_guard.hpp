#pragma once
/// Tests that switch the process's vector build (granular/simd_build.hpp) restore the CPU's own
/// choice when they end, whatever they asserted.
#include "granular/simd_build.hpp"

namespace granular::testing {

class SimdBuildGuard {
 public:
  SimdBuildGuard() : saved_(simdBuild()) {}
  ~SimdBuildGuard() { setSimdBuild(saved_); }
  SimdBuildGuard(const SimdBuildGuard&) = delete;
  SimdBuildGuard& operator=(const SimdBuildGuard&) = delete;

 private:
  SimdBuild saved_;
};

}  // namespace granular::testing
