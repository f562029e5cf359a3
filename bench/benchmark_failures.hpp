#pragma once
/// The Google Benchmark programs' failed cases. The library reports a case skipped with an error
/// (SkipWithError) in its table and still exits 0; a case that fails records it here as well, so
/// that main() exits 1 and a script running the benchmark (bench/smoke_test.sh) sees it.
#include <benchmark/benchmark.h>

#include <exception>

namespace granular::bench {

/// Whether any case has failed in this process.
inline bool& anyCaseFailed() {
  static bool failed = false;
  return failed;
}

/// Ends the case with `error`'s message and marks the run failed.
inline void failCase(benchmark::State& state, const std::exception& error) {
  anyCaseFailed() = true;
  state.SkipWithError(error.what());
}

}  // namespace granular::bench
