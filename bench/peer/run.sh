#!/usr/bin/env bash
# Side-by-side benchmark of the paper's stage 2: granular against Debian's LAMMPS and LIGGGHTS
# (bench/peer/README.md). Builds granular_peer_stage2, exports the settled packing, times every
# code with 1 and 2 threads (granular: OpenMP threads; LAMMPS/LIGGGHTS: MPI ranks, as Debian's
# LAMMPS has no OPENMP package), runs the time-step sweep and prints the tables of compare.py.
#
#   bench/peer/run.sh [--quick] [--build-dir DIR] [--no-build] [--checkpoint FILE]
#                     [--scene FILE] [--out DIR] [--reps N] [--no-wait]
#
#   --quick       0.2 s of stage 2, sweep 1, 2, 4 x dt against 0.5 x dt, one repetition (< 1 min)
# The sweep also runs granular's fixed steps with their check off (granular-*-unchecked, from 2
# to 24 x dt), to show where each really breaks beside the step it accepts.
#   --build-dir   CMake build folder (default build/release); --no-build uses it as it is
#   --checkpoint  settled mu = 0.3 bed (default runs/paper/mu03/settled.ckpt)
#   --scene       the scene the checkpoint was settled from (default assets/scenes/paper-mu03.toml)
#   --out         results (default runs/peer); report.md there holds the tables
#   --reps        repetitions of each timing, the best kept (default 2)
#   --no-wait     time at once, without waiting for a quiet machine (a smoke run, not a result)
# Nothing is downloaded. Timings wait (up to 3 min) for the 1-minute load average to drop under
# 1.5 and record it, since the machine may be shared.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="$ROOT/build/release"
CHECKPOINT="$ROOT/runs/paper/mu03/settled.ckpt"
SCENE="$ROOT/assets/scenes/paper-mu03.toml"
OUT="$ROOT/runs/peer"
QUICK=0
BUILD_IT=1
REPS=2
WAIT=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --quick) QUICK=1 ;;
    --build-dir) BUILD="$(realpath -m "$2")"; shift ;;
    --no-build) BUILD_IT=0 ;;
    --checkpoint) CHECKPOINT="$(realpath -m "$2")"; shift ;;
    --scene) SCENE="$(realpath -m "$2")"; shift ;;
    --out) OUT="$(realpath -m "$2")"; shift ;;
    --reps) REPS="$2"; shift ;;
    --no-wait) WAIT=0 ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    *) echo "run.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
  shift
done

DT=1.7e-4        # the paper scene's step [s]
SKIN=0.003       # neighbour skin of every code [m]; LAMMPS timings barely change over 0.001-0.009 m
if [[ $QUICK == 1 ]]; then
  TEND=0.2; REF=0.5; FACTORS="1 2 4"; REPS=1; UNCHECKED="4"
else
  TEND=1.0; REF=0.25; FACTORS="1 2 3 4 5 6 8 10 12 16 20 24"; UNCHECKED="2 4 6 8 10 12 16 20 24"
fi

if [[ ! -f "$CHECKPOINT" ]]; then
  echo "run.sh: settled checkpoint $CHECKPOINT not found. Make it with:" >&2
  echo "  ./build/release/app/granular paper --out runs/paper" >&2
  exit 1
fi
if [[ $BUILD_IT == 1 ]]; then
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release > /dev/null
  cmake --build "$BUILD" --target granular_peer_stage2 -j2 > /dev/null
fi
BIN="$BUILD/bench/granular_peer_stage2"
[[ -x "$BIN" ]] || { echo "run.sh: $BIN missing (build it, or drop --no-build)" >&2; exit 1; }
HAVE_LMP=0; command -v lmp > /dev/null && HAVE_LMP=1
HAVE_LIG=0; command -v liggghts > /dev/null && HAVE_LIG=1

if [[ $HAVE_LMP == 0 || $HAVE_LIG == 0 ]]; then
  echo "run.sh: a peer is missing and is skipped; install both with:" >&2
  echo "  apt-get install -y --no-install-recommends lammps liggghts openmpi-bin" >&2
fi

rm -rf "$OUT/timing" "$OUT/sweep" "$OUT/export"
mkdir -p "$OUT/timing" "$OUT/sweep" "$OUT/export" "$OUT/at-largest"
cd "$OUT"  # LIGGGHTS writes log.liggghts into the working folder whatever -log says
G=(--checkpoint "$CHECKPOINT" --scene "$SCENE")
"$BIN" "${G[@]}" --export-lammps "$OUT/export/lammps" --export-liggghts "$OUT/export/liggghts"
"$BIN" "${G[@]}" --export-lammps "$OUT/export/lammps-meanwall" --mean-wall-stiffness > /dev/null
{
  echo "date = $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "cpu = $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores"
  echo "dt = $DT"
  echo "tend = $TEND"
  echo "checkpoint = $CHECKPOINT"
  echo "lammps = $([[ $HAVE_LMP == 1 ]] && lmp -h | sed -n 's/^Large-scale[^-]*- //p' | head -1)"
  echo "liggghts = $([[ $HAVE_LIG == 1 ]] && echo 3.8.0)"
} > "$OUT/settings.txt"

# One run of CODE with THREADS threads/ranks at step DT_RUN; RECORD 1 writes the series (and the
# final dump of a peer) next to the stdout file OUTFILE (without its .out).
run_code() {
  local code=$1 threads=$2 dt=$3 record=$4 stem=$5
  local mpi=()
  [[ $threads -gt 1 ]] && mpi=(mpirun --allow-run-as-root -np "$threads")
  local series=()
  [[ $record == 1 ]] && series=(--series "$stem.csv")
  case "$code" in
    granular-gear5|granular-verlet)
      "$BIN" "${G[@]}" --fresh --integrator "${code#granular-}" --threads "$threads" --dt "$dt" \
        --skin "$SKIN" \
        --duration "$TEND" "${series[@]}" ;;
    granular-gear5-unchecked|granular-verlet-unchecked)  # the fixed step, its check off
      local integrator=${code#granular-}
      "$BIN" "${G[@]}" --fresh --integrator "${integrator%-unchecked}" --unchecked \
        --threads "$threads" --dt "$dt" --skin "$SKIN" --duration "$TEND" "${series[@]}" ;;
    granular-gear5-ranks)  # as granular-gear5, split by space among THREADS ranks of 1 thread
      OMP_NUM_THREADS=1 "${mpi[@]}" "$BIN" "${G[@]}" --fresh --integrator gear5 --threads 1 \
        --dt "$dt" --skin "$SKIN" --duration "$TEND" ;;
    granular-auto)     # time_step = "auto", Verlet, the default accuracy floor t_c/10
      "$BIN" "${G[@]}" --fresh --integrator verlet --auto --threads "$threads" --skin "$SKIN" \
        --duration "$TEND" "${series[@]}" ;;
    granular-auto-n1)  # time_step = "auto", Verlet, no accuracy floor: the network's step
      "$BIN" "${G[@]}" --fresh --integrator verlet --auto --contact-resolution 1 \
        --threads "$threads" --skin "$SKIN" --duration "$TEND" "${series[@]}" ;;
    granular-history)  # the real paper run: contact history and Gear derivatives kept
      "$BIN" "${G[@]}" --threads "$threads" --dt "$dt" --skin "$SKIN" --duration "$TEND" \
        "${series[@]}" ;;
    lammps|lammps-meanwall)
      OMP_NUM_THREADS=1 "${mpi[@]}" lmp -in "$ROOT/bench/peer/stage2.lmp" -log none \
        -var dir "$OUT/export/$code" -var dt "$dt" -var tend "$TEND" -var skin "$SKIN" \
        -var record "$record" -var out "$stem" ;;
    liggghts)
      OMP_NUM_THREADS=1 "${mpi[@]}" liggghts -in "$ROOT/bench/peer/stage2.liggghts" -log none \
        -var dir "$OUT/export/liggghts" -var dt "$dt" -var tend "$TEND" -var skin "$SKIN" \
        -var record "$record" -var out "$stem" ;;
  esac > "$stem.out" 2>&1 || true  # a failed run (unstable step) is reported by compare.py
}

# Waits for a quiet machine (1-minute load average < 1.5, at most 3 min; not with --no-wait) and
# logs the load.
wait_quiet() {
  local waited=0
  while [[ $WAIT == 1 ]] && awk '{exit !($1 >= 1.5)}' /proc/loadavg && [[ $waited -lt 180 ]]; do
    sleep 10; waited=$((waited + 10))
  done
  echo "$1: $(uptime)" >> "$OUT/timing/load.txt"
}

CODES=(granular-gear5 granular-verlet granular-auto granular-auto-n1)
[[ $HAVE_LMP == 1 ]] && CODES+=(lammps lammps-meanwall)
[[ $HAVE_LIG == 1 ]] && CODES+=(liggghts)

echo "timing: ${CODES[*]}, 1 and 2 threads, $REPS repetition(s), $TEND s of stage 2" >&2
for rep in $(seq 1 "$REPS"); do
  for threads in 1 2; do
    for code in "${CODES[@]}" $([[ $threads -gt 1 ]] && echo granular-gear5-ranks); do
      wait_quiet "${code}_t${threads}_r${rep} before"
      run_code "$code" "$threads" "$DT" 0 "$OUT/timing/${code}_t${threads}_r${rep}"
      echo "${code}_t${threads}_r${rep} after: $(uptime)" >> "$OUT/timing/load.txt"
    done
  done
done

echo "sweep: reference $REF x dt, factors $FACTORS (1 thread)" >&2
SWEEP=(granular-gear5 granular-verlet)
[[ $HAVE_LMP == 1 ]] && SWEEP+=(lammps)
[[ $HAVE_LIG == 1 ]] && SWEEP+=(liggghts)
for code in "${SWEEP[@]}"; do
  for factor in $REF $FACTORS; do
    dt=$(awk -v a="$DT" -v f="$factor" 'BEGIN { printf "%.9g", a * f }')
    run_code "$code" 1 "$dt" 1 "$OUT/sweep/${code}_x${factor}"
  done
done
# Where granular's fixed steps really break: their check against the network off, each against
# the checked run's reference.
for code in granular-gear5-unchecked granular-verlet-unchecked; do
  for factor in $UNCHECKED; do
    dt=$(awk -v a="$DT" -v f="$factor" 'BEGIN { printf "%.9g", a * f }')
    run_code "$code" 1 "$dt" 1 "$OUT/sweep/${code}_x${factor}"
  done
done
# The automatic steps: one run each (they choose their steps), compared in their own table.
run_code granular-auto 1 "$DT" 1 "$OUT/sweep/granular-auto_x1"
run_code granular-auto-n1 1 "$DT" 1 "$OUT/sweep/granular-auto-n1_x1"
# At the paper's step only: the run with the checkpoint's history, LAMMPS with one wall set.
run_code granular-history 1 "$DT" 1 "$OUT/sweep/granular-history_x1"
[[ $HAVE_LMP == 1 ]] && run_code lammps-meanwall 1 "$DT" 1 "$OUT/sweep/lammps-meanwall_x1"

# Each fixed-step code timed again at its largest step within the tolerance: a longer step
# rebuilds the neighbour list (and checks the step) more often per step, which a timing at the
# paper's step scaled by the factor leaves out.
python3 "$ROOT/bench/peer/compare.py" "$OUT" --from-time 0.1 --largest > "$OUT/largest.txt"
echo "timing at each code's largest step: $(tr '\n' ' ' < "$OUT/largest.txt")" >&2
mapfile -t LARGEST < "$OUT/largest.txt"  # read first: mpirun would swallow a loop's stdin
for rep in $(seq 1 "$REPS"); do
  for threads in 1 2; do
    for entry in "${LARGEST[@]}"; do
      read -r code factor <<< "$entry"
      dt=$(awk -v a="$DT" -v f="$factor" 'BEGIN { printf "%.9g", a * f }')
      wait_quiet "${code}_x${factor}_t${threads}_r${rep} before"
      run_code "$code" "$threads" "$dt" 0 "$OUT/at-largest/${code}_t${threads}_r${rep}" < /dev/null
    done
  done
done

python3 "$ROOT/bench/peer/compare.py" "$OUT" --from-time 0.1 | tee "$OUT/report.md"
