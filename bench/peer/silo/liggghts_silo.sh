#!/usr/bin/env bash
# The LIGGGHTS side of the silo discharge comparison (bench/peer/silo/README.md): writes the STL
# walls, runs bench/peer/silo/silo.liggghts for each orifice, rank count and seed, post-processes
# each run and prints the table (seed, particles inserted, fill+settle time, discharge rate W,
# wall pressure at a few heights, wall time, particle-steps/s; mean +- sd over the seeds).
#
#   bench/peer/silo/liggghts_silo.sh [--seeds "1 2 3 4"] [--ranks 1|2|"1 2"] [--quick]
#                                    [--out DIR] [--d0-diameters "6"] [--params FILE]
#                                    [--set key=value]... [--no-wait] [--max-wait S] [--post-only]
#
#   --seeds          seeds (integers >= 0; each maps to LIGGGHTS's prime seeds), default "1 2 3 4"
#   --ranks          MPI ranks, 1, 2 or "1 2" (both, one after the other), default 1
#   --quick          quick_n_particles (1500) instead of n_particles (8000)
#   --out            results (default runs/silo-peer): mesh/, D0_<mm>/r<ranks>/seed<s>/ (the
#                    run), D0_<mm>/r<ranks>/{discharge,wall_pressure}_<seed>.csv, summary_<seed>.json,
#                    report.md (the tables), load.txt (uptime around each run)
#   --d0-diameters   orifice diameters D0/d (d = 0.017 m), e.g. "5 6 7 8"; default: silo.params
#   --params         parameter file (default bench/peer/silo/silo.params); --set overrides a line
#   --post-only      run no LIGGGHTS: post-process the runs already in --out again (same options)
#   --no-wait        start each run at once instead of waiting (at most --max-wait s, default
#                    180) for the 1-minute load average to fall under 1.5 (timings on a busy
#                    machine are not results; load.txt records the load around each run)
# Needs liggghts (and mpirun for 2 ranks): apt-get install -y --no-install-recommends liggghts
# openmpi-bin. Python: /usr/bin/python3, standard library only. Nothing is downloaded.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../../.." && pwd)"
PY=/usr/bin/python3
SEEDS="1 2 3 4"
RANKS="1"
QUICK=0
OUT="$ROOT/runs/silo-peer"
D0S=""
PARAMS="$HERE/silo.params"
SETS=()
WAIT=1
MAX_WAIT=180
POST_ONLY=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --seeds) SEEDS="$2"; shift ;;
    --ranks) RANKS="$2"; shift ;;
    --quick) QUICK=1 ;;
    --out) OUT="$(realpath -m "$2")"; shift ;;
    --d0-diameters) D0S="$2"; shift ;;
    --params) PARAMS="$(realpath -m "$2")"; shift ;;
    --set) SETS+=(--set "$2"); shift ;;
    --no-wait) WAIT=0 ;;
    --post-only) POST_ONLY=1 ;;
    --max-wait) MAX_WAIT="$2"; shift ;;
    -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "liggghts_silo.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
  shift
done
for r in $RANKS; do
  [[ $r == 1 || $r == 2 ]] || { echo "liggghts_silo.sh: --ranks takes 1, 2 or \"1 2\"" >&2; exit 2; }
done
for s in $SEEDS; do
  [[ $s =~ ^[0-9]+$ ]] || { echo "liggghts_silo.sh: seed '$s' is not an integer >= 0" >&2; exit 2; }
done
command -v liggghts > /dev/null || {
  echo "liggghts_silo.sh: liggghts not found; apt-get install -y --no-install-recommends liggghts openmpi-bin" >&2
  exit 1
}
if [[ " $RANKS " == *" 2 "* ]] && ! command -v mpirun > /dev/null; then
  echo "liggghts_silo.sh: mpirun not found; apt-get install -y --no-install-recommends openmpi-bin" >&2
  exit 1
fi
if [[ -z $D0S ]]; then
  D0S="$($PY -c "import sys; sys.path.insert(0, '$HERE'); import silo_params as s; \
p = s.read('$PARAMS'); print(' '.join('%g' % x for x in s.as_list(p['orifice_diameters'])))")"
fi
QUICK_ARG=()
[[ $QUICK == 1 ]] && QUICK_ARG=(--quick)

mkdir -p "$OUT"
if [[ $POST_ONLY == 0 ]]; then
  echo "meshes: $OUT/mesh" >&2
  # shellcheck disable=SC2086
  $PY "$HERE/silo_mesh.py" --out "$OUT/mesh" --params "$PARAMS" "${SETS[@]}" --d0 $D0S >&2
fi

wait_quiet() {
  local waited=0
  while [[ $WAIT == 1 ]] && awk '{exit !($1 >= 1.5)}' /proc/loadavg && [[ $waited -lt $MAX_WAIT ]]; do
    sleep 10; waited=$((waited + 10))
  done
  echo "$1: $(uptime)" >> "$OUT/load.txt"
}

SUMMARIES=()
FAILED=0
for d0 in $D0S; do
  mm="$($PY -c "import sys; sys.path.insert(0, '$HERE'); import silo_params as s; \
p = s.read('$PARAMS'); print(s.orifice_mm(s.orifice_diameter(p, $d0)))")"
  for ranks in $RANKS; do
    dir="$OUT/D0_$mm/r$ranks"
    for seed in $SEEDS; do
      run="$dir/seed$seed"
      if [[ $POST_ONLY == 1 ]]; then
        if [[ -f "$run/time.txt" && -f "$run/log.liggghts" ]]; then
          read -r wall user sys < "$run/time.txt"
          cpu=$(awk -v a="$user" -v b="$sys" 'BEGIN { printf "%.3f", a + b }')
          $PY "$HERE/silo_post.py" run "$run" --csv-dir "$dir" --wall-seconds "$wall" \
            --cpu-seconds "$cpu" >&2 || FAILED=1
        else
          echo "liggghts_silo.sh: --post-only: no finished run in $run" >&2
          FAILED=1
        fi
        continue
      fi
      rm -rf "$run"
      mkdir -p "$run"
      $PY "$HERE/silo_setup.py" --out "$run" --mesh-dir "$OUT/mesh" --seed "$seed" --d0 "$d0" \
        --ranks "$ranks" --params "$PARAMS" "${SETS[@]}" "${QUICK_ARG[@]}"
      mpi=()
      [[ $ranks -gt 1 ]] && mpi=(mpirun --allow-run-as-root -np "$ranks")
      wait_quiet "D0_$mm r$ranks seed$seed before"
      echo "run: D0 = $d0 d, $ranks rank(s), seed $seed -> $run" >&2
      # LIGGGHTS writes log.liggghts into the working folder; -screen none crashes after an STL.
      # time.txt: wall, user and system seconds of the whole process (all ranks).
      if { TIMEFORMAT='%R %U %S'; time (cd "$run" && OMP_NUM_THREADS=1 "${mpi[@]}" liggghts \
             -in "$HERE/silo.liggghts" -var dir "$run" -log "$run/log.liggghts" \
             -screen /dev/null > "$run/stdout.txt" 2>&1); } 2> "$run/time.txt"; then
        echo "D0_$mm r$ranks seed$seed after: $(uptime)" >> "$OUT/load.txt"
        read -r wall user sys < "$run/time.txt"
        cpu=$(awk -v a="$user" -v b="$sys" 'BEGIN { printf "%.3f", a + b }')
        $PY "$HERE/silo_post.py" run "$run" --csv-dir "$dir" --wall-seconds "$wall" \
          --cpu-seconds "$cpu" >&2
        SUMMARIES+=("$dir/summary_$seed.json")
      else
        echo "liggghts_silo.sh: LIGGGHTS failed for $run (see $run/log.liggghts):" >&2
        grep -h ERROR "$run/log.liggghts" "$run/stdout.txt" 2>/dev/null | head -3 >&2 || true
        FAILED=1
      fi
    done
  done
done

{
  echo "# LIGGGHTS silo discharge ($(date -u '+%Y-%m-%d %H:%M UTC'))"
  echo
  echo "cpu: $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores; liggghts: $(cd "$OUT" && liggghts -log none -h 2>/dev/null | sed -n 's/^LIGGGHTS (Version \([^,]*\),.*/\1/p' | head -1)"
  echo "seeds: $SEEDS; ranks: $RANKS; quick: $QUICK; D0/d: $D0S; params: $PARAMS ${SETS[*]:-}"
  for d0 in $D0S; do
    mm="$($PY -c "import sys; sys.path.insert(0, '$HERE'); import silo_params as s; \
p = s.read('$PARAMS'); print(s.orifice_mm(s.orifice_diameter(p, $d0)))")"
    for ranks in $RANKS; do
      files=()
      for seed in $SEEDS; do
        [[ -f "$OUT/D0_$mm/r$ranks/summary_$seed.json" ]] && files+=("$OUT/D0_$mm/r$ranks/summary_$seed.json")
      done
      [[ ${#files[@]} -gt 0 ]] || continue
      echo
      echo "## D0 = $d0 d ($mm mm), $ranks rank(s)"
      echo
      $PY "$HERE/silo_post.py" table "${files[@]}"
    done
  done
} > "$OUT/report.md"
cat "$OUT/report.md"
exit $FAILED
