#!/usr/bin/env bash
# `granular paper --fresh` on a quiet machine and beside one busy process (a shell loop that
# keeps one core busy, as another user's job does), in alternating pairs of two builds, so that
# the host's drift between minutes falls on both alike: bench/RESULTS.md, "A busy machine".
#
#   busy_machine.sh NEW_GRANULAR OLD_GRANULAR [PAIRS] [WORK_DIR] [BUSY_BUILDS]
#
# NEW_GRANULAR and OLD_GRANULAR are two builds of `granular` (the one to judge and the one
# before its change). Each pair runs both, in alternating order; the busy rows run each beside
# its own busy process. BUSY_BUILDS: "new old" (the default), or "new" alone where the old
# build's busy runs (minutes each) are already known. Prints one row a run: condition, build, wall seconds. OMP_WAIT_POLICY and
# OMP_NUM_THREADS are left unset, as a user leaves them.
set -euo pipefail

new=$(realpath "$1")
old=$(realpath "$2")
pairs=${3:-3}
work=$(realpath -m "${4:-runs/busy-machine}")
busyBuilds=${5:-new old}
mkdir -p "$work"
unset OMP_WAIT_POLICY OMP_NUM_THREADS GOMP_SPINCOUNT

# One run of `granular paper --fresh`: its wall time [s].
timed() {
  local binary=$1 out=$2
  rm -rf "$out"
  local start end
  start=$(date +%s.%N)
  "$binary" paper --fresh --quiet --out "$out" > "$out.log" 2>&1
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f\n", b - a }'
}

# The same, beside a process that keeps one core busy for as long as it runs.
busy() {
  (while :; do :; done) &
  local burner=$!
  local seconds
  seconds=$(timed "$1" "$2")
  kill "$burner"
  wait "$burner" 2> /dev/null || true
  echo "$seconds"
}

# `pairs` pairs of rows of `condition`, each run by `runner` (timed or busy), the builds'
# order alternating from pair to pair.
rows() {
  local condition=$1 runner=$2 builds=$3 order which binary
  for ((k = 0; k < pairs; ++k)); do
    if ((k % 2 == 0)); then order="new old"; else order="old new"; fi
    for which in $order; do
      [[ " $builds " == *" $which "* ]] || continue
      binary=$new
      [[ $which == old ]] && binary=$old
      echo "$condition,$which,$("$runner" "$binary" "$work/$condition-$which")"
    done
  done
}

echo "condition,build,wall_s"
rows quiet timed "new old"
rows busy busy "$busyBuilds"
