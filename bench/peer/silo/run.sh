#!/usr/bin/env bash
# granular against LIGGGHTS on the silo discharge (bench/peer/silo/README.md, "granular against
# LIGGGHTS"): the same STL walls and silo.params for both; for each thread/rank count and seed a
# granular run then a LIGGGHTS run, one after the other (this host's speed wanders, so the two
# codes' runs alternate rather than one code's block after the other's); each run
# post-processed; report.md with W, p_h per band and particle-steps/s of both.
#
#   bench/peer/silo/run.sh [--seeds "1 2 3 4"] [--threads "1 2"] [--quick] [--out DIR]
#                          [--granular BIN] [--params FILE] [--set key=value]...
#                          [--no-wait] [--max-wait S] [--post-only]
#
#   --seeds     seeds, default "1 2 3 4" (granular's insert seed; LIGGGHTS maps each to its primes)
#   --threads   counts, default "1 2": granular with OMP_NUM_THREADS=N, LIGGGHTS with N MPI ranks
#   --quick     quick_n_particles (1500) instead of n_particles (8000)
#   --out       results (default runs/silo-vs): mesh/, granular/t<N>/seed<s>/ (scene, out/),
#               liggghts/r<N>/seed<s>/, the per-run CSV and JSON beside them, report.md, load.txt
#   --granular  the granular binary (default build/release/app/granular of this checkout)
#   --params    parameter file (default bench/peer/silo/silo.params); --set overrides a line
#   --no-wait   start each run at once instead of waiting (at most --max-wait s, default 60) for
#               the 1-minute load average to fall under 1.5; load.txt records it around each run
#   --post-only post-process the runs already in --out and write report.md again
# The orifice is the first of orifice_diameters. Needs liggghts and mpirun (apt-get install -y
# --no-install-recommends liggghts openmpi-bin); Python: /usr/bin/python3, standard library.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../../.." && pwd)"
PY=/usr/bin/python3
SEEDS="1 2 3 4"
THREADS="1 2"
QUICK=0
OUT="$ROOT/runs/silo-vs"
GRANULAR="$ROOT/build/release/app/granular"
PARAMS="$HERE/silo.params"
SETS=()
WAIT=1
MAX_WAIT=60
POST_ONLY=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --seeds) SEEDS="$2"; shift ;;
    --threads) THREADS="$2"; shift ;;
    --quick) QUICK=1 ;;
    --out) OUT="$(realpath -m "$2")"; shift ;;
    --granular) GRANULAR="$(realpath -m "$2")"; shift ;;
    --params) PARAMS="$(realpath -m "$2")"; shift ;;
    --set) SETS+=(--set "$2"); shift ;;
    --no-wait) WAIT=0 ;;
    --max-wait) MAX_WAIT="$2"; shift ;;
    --post-only) POST_ONLY=1 ;;
    -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "run.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
  shift
done
for n in $THREADS; do
  [[ $n =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: --threads takes counts >= 1" >&2; exit 2; }
done
for s in $SEEDS; do
  [[ $s =~ ^[0-9]+$ ]] || { echo "run.sh: seed '$s' is not an integer >= 0" >&2; exit 2; }
done
if [[ $POST_ONLY == 0 ]]; then
  [[ -x $GRANULAR ]] || { echo "run.sh: no granular at $GRANULAR (--granular BIN)" >&2; exit 1; }
  command -v liggghts > /dev/null && command -v mpirun > /dev/null || {
    echo "run.sh: liggghts or mpirun missing; apt-get install -y --no-install-recommends liggghts openmpi-bin" >&2
    exit 1
  }
fi
D0="$($PY -c "import sys; sys.path.insert(0, '$HERE'); import silo_params as s; \
p = s.read('$PARAMS'); print('%g' % s.as_list(p['orifice_diameters'])[0])")"
QUICK_ARG=()
[[ $QUICK == 1 ]] && QUICK_ARG=(--quick)

mkdir -p "$OUT"
if [[ $POST_ONLY == 0 ]]; then
  $PY "$HERE/silo_mesh.py" --out "$OUT/mesh" --params "$PARAMS" "${SETS[@]}" --d0 "$D0" >&2
fi

wait_quiet() {
  local waited=0
  while [[ $WAIT == 1 ]] && awk '{exit !($1 >= 1.5)}' /proc/loadavg && [[ $waited -lt $MAX_WAIT ]]; do
    sleep 5; waited=$((waited + 5))
  done
  echo "$1 before: $(uptime)" >> "$OUT/load.txt"
}

# time.txt: wall, user and system seconds of the whole process.
run_granular() {  # threads seed
  local n=$1 seed=$2 dir="$OUT/granular/t$1" run="$OUT/granular/t$1/seed$2"
  if [[ $POST_ONLY == 0 ]]; then
    rm -rf "$run"
    mkdir -p "$run"
    $PY "$HERE/silo_granular.py" --out "$run" --mesh-dir "$OUT/mesh" --seed "$seed" --d0 "$D0" \
      --threads "$n" --params "$PARAMS" "${SETS[@]}" "${QUICK_ARG[@]}"
    wait_quiet "granular t$n seed$seed"
    echo "run: granular, $n thread(s), seed $seed -> $run" >&2
    if ! { TIMEFORMAT='%R %U %S'; time (cd "$run" && OMP_NUM_THREADS=$n "$GRANULAR" run \
           silo.toml --out out --checkpoint-every 0 > stdout.txt 2> stderr.txt); } \
           2> "$run/time.txt"; then
      echo "run.sh: granular failed in $run:" >&2
      tail -3 "$run/stderr.txt" >&2 || true
      return 1
    fi
    echo "granular t$n seed$seed after: $(uptime)" >> "$OUT/load.txt"
  fi
  [[ -f "$run/time.txt" ]] || { echo "run.sh: no finished run in $run" >&2; return 1; }
  local wall user sys
  read -r wall user sys < "$run/time.txt"
  $PY "$HERE/silo_granular_post.py" run "$run" --csv-dir "$dir" --wall-seconds "$wall" \
    --cpu-seconds "$(awk -v a="$user" -v b="$sys" 'BEGIN { printf "%.3f", a + b }')" >&2
}

run_liggghts() {  # ranks seed
  local n=$1 seed=$2 dir="$OUT/liggghts/r$1" run="$OUT/liggghts/r$1/seed$2"
  if [[ $POST_ONLY == 0 ]]; then
    rm -rf "$run"
    mkdir -p "$run"
    $PY "$HERE/silo_setup.py" --out "$run" --mesh-dir "$OUT/mesh" --seed "$seed" --d0 "$D0" \
      --ranks "$n" --params "$PARAMS" "${SETS[@]}" "${QUICK_ARG[@]}"
    wait_quiet "liggghts r$n seed$seed"
    echo "run: LIGGGHTS, $n rank(s), seed $seed -> $run" >&2
    # -screen none crashes LIGGGHTS 3.8 once it has read an STL; /dev/null does not.
    if ! { TIMEFORMAT='%R %U %S'; time (cd "$run" && OMP_NUM_THREADS=1 mpirun --allow-run-as-root \
           --oversubscribe -np "$n" liggghts -in "$HERE/silo.liggghts" -var dir "$run" \
           -log "$run/log.liggghts" -screen /dev/null > "$run/stdout.txt" 2>&1); } \
           2> "$run/time.txt"; then
      echo "run.sh: LIGGGHTS failed in $run (see $run/log.liggghts):" >&2
      grep -h ERROR "$run/log.liggghts" "$run/stdout.txt" 2>/dev/null | head -3 >&2 || true
      return 1
    fi
    echo "liggghts r$n seed$seed after: $(uptime)" >> "$OUT/load.txt"
  fi
  [[ -f "$run/time.txt" ]] || { echo "run.sh: no finished run in $run" >&2; return 1; }
  local wall user sys
  read -r wall user sys < "$run/time.txt"
  $PY "$HERE/silo_post.py" run "$run" --csv-dir "$dir" --wall-seconds "$wall" \
    --cpu-seconds "$(awk -v a="$user" -v b="$sys" 'BEGIN { printf "%.3f", a + b }')" >&2
}

FAILED=0
for n in $THREADS; do
  for seed in $SEEDS; do
    run_granular "$n" "$seed" || FAILED=1
    run_liggghts "$n" "$seed" || FAILED=1
  done
done

GS=() LS=()
for n in $THREADS; do
  for seed in $SEEDS; do
    [[ -f "$OUT/granular/t$n/summary_$seed.json" ]] && GS+=("$OUT/granular/t$n/summary_$seed.json")
    [[ -f "$OUT/liggghts/r$n/summary_$seed.json" ]] && LS+=("$OUT/liggghts/r$n/summary_$seed.json")
  done
done
if [[ ${#GS[@]} -eq 0 || ${#LS[@]} -eq 0 ]]; then
  echo "run.sh: no finished runs of one of the codes in $OUT" >&2
  exit 1
fi
{
  $PY "$HERE/silo_granular_post.py" compare --granular "${GS[@]}" --liggghts "${LS[@]}" \
    --title "granular against LIGGGHTS: silo discharge ($(date -u '+%Y-%m-%d %H:%M UTC'))"
  echo
  echo "cpu: $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1), $(nproc) cores;" \
       "granular: $GRANULAR; liggghts: $(command -v liggghts || echo none)"
  echo "seeds: $SEEDS; threads/ranks: $THREADS; quick: $QUICK; D0/d: $D0;" \
       "params: $PARAMS ${SETS[*]:-}; load: load.txt"
  echo
  echo "## Every run"
  echo
  echo "granular (the ranks column: threads):"
  echo
  $PY "$HERE/silo_post.py" table "${GS[@]}"
  echo
  echo "LIGGGHTS:"
  echo
  $PY "$HERE/silo_post.py" table "${LS[@]}"
} > "$OUT/report.md"
cat "$OUT/report.md"
exit $FAILED
