#!/usr/bin/env bash
# The sanitizer half of CI (.ci/run calls it after the release build and tests):
#   1. ASan + UBSan (preset "sanitize", clang): build, then the tests that the sanitize test
#      preset selects;
#   2. ThreadSanitizer (preset "tsan", clang + LLVM's libomp + Archer): build the test files
#      whose code runs on threads, then the tests that the tsan test preset selects, on 2 OpenMP
#      threads (CMakePresets.json and tests/CMakeLists.txt say which);
# The fuzzers (scripts/fuzz.sh) are not part of CI: their build no longer fits its 30 minutes;
# run them after touching a loader (docs/RELIABILITY.md).
# Runs every part even after a failure; prints the wall time of each part and the total, and
# exits non-zero if any part failed.
# Expects the packages of scripts/install-deps.sh. docs/RELIABILITY.md has measured times.
#
# Usage: scripts/ci-sanitizers.sh
set -euo pipefail
cd "$(dirname "$0")/.."

for tool in clang clang++ cmake ctest; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "ci-sanitizers: $tool not found; run scripts/install-deps.sh first" >&2
    exit 1
  fi
done
archer=/usr/lib/llvm-14/lib/libarcher.so  # also named in the tsan test preset
if [[ ! -f "$archer" ]]; then
  echo "ci-sanitizers: $archer not found (package libomp-14-dev); run scripts/install-deps.sh" >&2
  exit 1
fi

summary=()
failed=()
total_start=$SECONDS
# Runs "$@" as one timed part named $1. A failing part is recorded and the next parts still
# run, so that one run shows every failure.
part() {
  local name="$1"
  shift
  echo "=== ci-sanitizers: $name"
  local start=$SECONDS result=""
  if ! "$@"; then
    result="  FAILED"
    failed+=("$name")
  fi
  summary+=("$(printf '%-32s %5d s%s' "$name" $((SECONDS - start)) "$result")")
}

part "asan+ubsan: configure + build" \
  bash -c 'cmake --preset sanitize && cmake --build --preset sanitize'
part "asan+ubsan: tests" ctest --preset sanitize
part "tsan: configure + build" bash -c 'cmake --preset tsan && cmake --build --preset tsan'
part "tsan: tests" ctest --preset tsan

echo "=== ci-sanitizers: wall times"
printf '%s\n' "${summary[@]}"
printf '%-32s %5d s\n' "total" $((SECONDS - total_start))
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "=== ci-sanitizers: FAILED: ${failed[*]}" >&2
  exit 1
fi
echo "=== ci-sanitizers: all clean"
