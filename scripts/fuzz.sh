#!/usr/bin/env bash
# Builds the libFuzzer targets (cmake preset "fuzz": clang, ASan + UBSan) and runs each one:
#   1. every file in fuzz/regressions/<target>/ once, as a plain regression input;
#   2. fuzzing for SECONDS (default 60) on fuzz/corpus/<target>/ plus fuzz/regressions/<target>/.
# The two targets fuzz side by side (one process each, 2 cores). Prints the executions per
# target and exits non-zero on any crash, sanitizer report, timeout (a unit over 1 s) or
# out-of-memory; the input that caused it is left in build/fuzz/artifacts/<target>/.
#
# New inputs the fuzzer finds go to build/fuzz/corpus/<target>/ (scratch, never into fuzz/).
# A crash worth keeping goes to fuzz/regressions/<target>/ with a name that says what it was.
#
# Usage: scripts/fuzz.sh [SECONDS]
set -euo pipefail

seconds="${1:-60}"
if [[ ! "$seconds" =~ ^[0-9]+$ || "$seconds" -lt 1 ]]; then
  echo "fuzz.sh: SECONDS must be a positive whole number, got '$seconds'" >&2
  exit 2
fi
cd "$(dirname "$0")/.."

if ! command -v clang++ >/dev/null 2>&1; then
  echo "fuzz.sh: clang++ not found; run scripts/install-deps.sh first" >&2
  exit 1
fi

cmake --preset fuzz >/dev/null
cmake --build --preset fuzz --target fuzz_scene fuzz_checkpoint

targets=(scene checkpoint)
# A unit slower than FUZZ_TIMEOUT seconds (default 1) is a hang: the slowest seed takes under
# 0.1 s on an idle core. On a machine busy with other work, raise it (FUZZ_TIMEOUT=3) rather
# than chase false hangs. UBSan reports are fatal (-fno-sanitize-recover), so libFuzzer catches
# them as crashes.
timeout="${FUZZ_TIMEOUT:-1}"
options=(-timeout="$timeout" -rss_limit_mb=2048 -print_final_stats=1)
export UBSAN_OPTIONS="print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
# The checkpoint target steps on one thread (see fuzz_checkpoint.cpp); OpenMP must not spin.
export OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive

status=0

# 1. Regression inputs, each run once.
for t in "${targets[@]}"; do
  files=()
  if [[ -d "fuzz/regressions/$t" ]]; then
    mapfile -t files < <(find "fuzz/regressions/$t" -type f | sort)
  fi
  if [[ ${#files[@]} -eq 0 ]]; then
    echo "fuzz.sh: $t: no regression inputs"
    continue
  fi
  if "build/fuzz/fuzz/fuzz_$t" "${options[@]}" "${files[@]}" >"build/fuzz/regressions-$t.log" 2>&1; then
    echo "fuzz.sh: $t: ${#files[@]} regression inputs pass"
  else
    echo "fuzz.sh: $t: a regression input fails; log:" >&2
    tail -n 60 "build/fuzz/regressions-$t.log" >&2
    status=1
  fi
done

# 2. Fuzzing, both targets at once.
pids=()
for t in "${targets[@]}"; do
  mkdir -p "build/fuzz/corpus/$t" "build/fuzz/artifacts/$t"
  # The first folder receives the new inputs; the others are only read.
  corpora=("build/fuzz/corpus/$t" "fuzz/corpus/$t")
  [[ -d "fuzz/regressions/$t" ]] && corpora+=("fuzz/regressions/$t")
  dict=()
  [[ -f "fuzz/$t.dict" ]] && dict=(-dict="fuzz/$t.dict")
  "build/fuzz/fuzz/fuzz_$t" "${options[@]}" "${dict[@]}" -max_total_time="$seconds" \
    -artifact_prefix="build/fuzz/artifacts/$t/" "${corpora[@]}" \
    >"build/fuzz/fuzz-$t.log" 2>&1 &
  pids+=($!)
done
for i in "${!targets[@]}"; do
  t="${targets[$i]}"
  if wait "${pids[$i]}"; then
    runs="$(sed -n 's/^stat::number_of_executed_units: *//p' "build/fuzz/fuzz-$t.log" | tail -n 1)"
    echo "fuzz.sh: $t: ${runs:-?} executions in ${seconds} s, no crash" \
      "(corpus $(find "build/fuzz/corpus/$t" -type f | wc -l) inputs; log build/fuzz/fuzz-$t.log)"
  else
    echo "fuzz.sh: $t: FAILED; input in build/fuzz/artifacts/$t/; end of the log:" >&2
    tail -n 60 "build/fuzz/fuzz-$t.log" >&2
    status=1
  fi
done
exit "$status"
