#!/usr/bin/env bash
# `granular run` under mpirun (ctest Ranks.Run*): the bed of tests/ranks/bed.toml on 1-3 ranks.
#   files       every file but the checkpoint is the same bytes on 1, 2 and 3 ranks (summary.txt
#               but its wall-clock times), and one line of output comes from rank 0 alone
#   checkpoint  a NaN injected on 2 ranks (GRANULAR_INJECT_NAN) ends every rank with exit 3 and
#               one message naming the particle and the rank; the run then resumed on 3 ranks
#               ends with the files of the uninterrupted run; likewise 1 rank -> 2
#   kill        a rank killed with SIGKILL ends the job (no hang); --resume on 2 ranks then ends
#               with the files of the uninterrupted run
#   faults      an invalid scene and a missing file on 3 ranks: exit 2 and one message; with
#               mpirun -q that message is all of stderr (OpenMPI's banner left out)
#   alone       the run alone with simulation.exact_sums = true is the same bytes as on 2 ranks,
#               and so is that run stopped by a NaN and resumed alone; without exact sums, only
#               the energy and wall-reaction columns of timeseries.csv and the walls' ParaView
#               files differ, and the reactions do
#   exchange    (a scene that pours particles in and discharges them: tests/scenes/discharge.toml)
#               every file but the checkpoint is the same bytes on 1, 2 and 3 ranks; a rank
#               killed mid-discharge, --resume on 3 ranks ends with the files of the
#               uninterrupted run
#   sigterm     SIGTERM to mpirun: mpirun exits 1 (OpenMPI's own status for a signal it
#               received), the ranks write the checkpoint and say so in one line; resumed alone
#               with exact_sums it ends with the files of the uninterrupted run alone
# Usage: run_under_mpirun_test.sh CASE GRANULAR MPIEXEC SCENE WORKDIR
set -euo pipefail
case_name="$1" granular="$2" mpiexec="$3" scene="$4" work="$5"
rm -rf "$work"
mkdir -p "$work"
cd "$work"

fail() {
  echo "FAIL: $*" >&2
  exit 1
}
# mpirun with N ranks, bounded: a hang fails the test instead of stalling it.
ranks() {
  local n="$1"
  shift
  timeout 120 "$mpiexec" -np "$n" --oversubscribe --allow-run-as-root "$granular" "$@"
}
# The files two runs must share: everything but the checkpoint, with the summary's and the
# progress's wall-clock times left out.
same_files() {
  local a="$1" b="$2" f
  for f in $(cd "$a" && find . -type f ! -name checkpoint.bin ! -name 'failed_state*' | sort); do
    if [[ "$f" == ./summary.txt ]]; then
      cmp -s <(grep -v 'wall-clock' "$a/$f") <(grep -v 'wall-clock' "$b/$f") ||
        fail "$a/$f and $b/$f differ"
    else
      cmp -s "$a/$f" "$b/$f" || fail "$a/$f and $b/$f differ"
    fi
  done
  [[ -f "$a/final_state.csv" && -f "$a/timeseries.csv" ]] || fail "$a has no final state"
}
# `scene` with simulation.exact_sums = true, as FILE.
with_exact_sums() {
  sed 's/^\[simulation\]$/[simulation]\nexact_sums = true/' "$scene" >"$1"
  grep -q '^exact_sums = true' "$1" || fail "no [simulation] table in $scene"
}
# The columns of two time series with the same header whose values differ in some row, one a line.
differing_columns() {
  paste -d '\n' "$1" "$2" | awk -F, '
    NR == 1 { for (i = 1; i <= NF; ++i) name[i] = $i }
    NR > 2 && NR % 2 == 1 { split($0, first, ",") }
    NR > 2 && NR % 2 == 0 {
      for (i = 1; i <= NF; ++i) if (($i "") != (first[i] "")) differ[name[i]] = 1
    }
    END { for (c in differ) print c }' | sort
}
# The one error line a failed run must print (mpirun adds its own banner, which is not ours).
one_error() {
  local log="$1" pattern="$2"
  [[ "$(grep -c '^error' "$log")" == 1 ]] || { cat "$log" >&2; fail "not one error line in $log"; }
  grep -q "$pattern" "$log" || { cat "$log" >&2; fail "$log does not say '$pattern'"; }
}

case "$case_name" in
  files)
    for n in 1 2 3; do
      ranks "$n" run "$scene" --out "np$n" --quiet >"np$n.log" 2>"np$n.err" || fail "np$n failed"
    done
    same_files np1 np2
    same_files np1 np3
    [[ "$(grep -c '^stage press' np3.log)" == 1 ]] || fail "not one stage line from 3 ranks"
    [[ ! -s np3.err ]] || fail "3 ranks wrote to stderr: $(cat np3.err)"
    ;;
  checkpoint)
    ranks 1 run "$scene" --out whole --quiet >/dev/null
    for pair in "2 3" "1 2"; do
      read -r n m <<<"$pair"
      dir="from$n"
      set +e
      GRANULAR_INJECT_NAN=3000:17 ranks "$n" run "$scene" --out "$dir" --quiet \
        --checkpoint-every 1e-9 >"$dir.log" 2>"$dir.err"
      status=$?
      set -e
      [[ $status == 3 ]] || fail "a NaN on $n ranks: exit $status, expected 3"
      one_error "$dir.err" "particle 17"
      if ((n > 1)); then grep -q "on rank [0-9] of $n" "$dir.err" || fail "no rank named"; fi
      ranks "$m" run "$scene" --out "$dir" --quiet --resume >"$dir.resume.log" 2>&1 ||
        fail "resuming on $m ranks failed: $(cat "$dir.resume.log")"
      grep -q "resuming .* at t = .* s, step 3000" "$dir.resume.log" || fail "not resumed at 3000"
      same_files whole "$dir"
    done
    ;;
  kill)
    # A longer settling, so that the kill lands mid-run.
    sed 's/^max_time = 0.8 /max_time = 3.0 /' "$scene" >long.toml
    ranks 1 run long.toml --out whole --quiet >/dev/null
    ranks 2 run long.toml --out killed --quiet --checkpoint-every 1e-9 >killed.log 2>&1 &
    job=$!
    for _ in $(seq 100); do
      [[ -f killed/checkpoint.bin ]] && break
      sleep 0.1
    done
    sleep 0.3
    victim=$(pgrep -f "^$granular run long.toml --out killed" | tail -1)
    [[ -n "$victim" ]] || fail "no rank to kill (the run ended first?)"
    kill -9 "$victim"
    set +e
    wait "$job"
    status=$?
    set -e
    ((status != 0 && status != 124)) || fail "the job with a killed rank: exit $status"
    ranks 2 run long.toml --out killed --quiet --resume >resume.log 2>&1 ||
      fail "resuming failed: $(cat resume.log)"
    grep -q "^resuming" resume.log || fail "it did not resume: $(cat resume.log)"
    same_files whole killed
    ;;
  exchange)
    for n in 1 2 3; do
      ranks "$n" run "$scene" --out "np$n" --quiet >"np$n.log" 2>"np$n.err" || fail "np$n failed"
    done
    same_files np1 np2
    same_files np1 np3
    grep -q 'mass_discharged_kg' np1/timeseries.csv || fail "no discharged mass in the series"
    # Killed once the outlet has taken particles (the checkpoint's tally says so).
    ranks 2 run "$scene" --out killed --quiet --checkpoint-every 1e-9 >killed.log 2>&1 &
    job=$!
    for _ in $(seq 300); do
      if [[ -f killed/timeseries.csv ]] &&
        awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "particles") c = i }
                 NR > 1 && $1 == "discharge" && $c < 300 { found = 1 } END { exit !found }' \
          killed/timeseries.csv; then
        break
      fi
      sleep 0.05
    done
    victim=$(pgrep -f "^$granular run $scene --out killed" | tail -1)
    [[ -n "$victim" ]] || fail "no rank to kill (the run ended first?)"
    kill -9 "$victim"
    set +e
    wait "$job"
    status=$?
    set -e
    ((status != 0 && status != 124)) || fail "the job with a killed rank: exit $status"
    [[ ! -f killed/summary.txt ]] || fail "killed after it had finished"
    ranks 3 run "$scene" --out killed --quiet --resume >resume.log 2>&1 ||
      fail "resuming failed: $(cat resume.log)"
    grep -q "^resuming" resume.log || fail "it did not resume: $(cat resume.log)"
    same_files np1 killed
    ;;
  faults)
    sed 's/^friction = 0.3/friction = -1/' "$scene" >bad.toml
    exit_2_once() {
      local name="$1" file="$2" said="$3" status
      set +e
      ranks 3 run "$file" --out "$name" >"$name.log" 2>"$name.err"
      status=$?
      set -e
      [[ $status == 2 ]] || fail "$name on 3 ranks: exit $status, expected 2"
      one_error "$name.err" "$said"
    }
    exit_2_once bad bad.toml "friction = -1"
    exit_2_once missing missing.toml "missing.toml"
    # OpenMPI's mpirun adds its banner after any rank's non-zero exit; -q leaves it out and
    # keeps the status (docs/guide.md §9).
    set +e
    timeout 120 "$mpiexec" -q -np 3 --oversubscribe --allow-run-as-root "$granular" run bad.toml \
      --out quiet >quiet.log 2>quiet.err
    status=$?
    set -e
    [[ $status == 2 ]] || fail "bad.toml on 3 ranks under mpirun -q: exit $status, expected 2"
    one_error quiet.err "friction = -1"
    [[ "$(wc -l <quiet.err)" == 1 ]] || fail "mpirun -q printed more: $(cat quiet.err)"
    ;;
  alone)
    with_exact_sums exact.toml
    "$granular" run exact.toml --out exact --quiet >exact.log || fail "exact sums alone failed"
    ranks 2 run exact.toml --out np2 --quiet >np2.log || fail "np2 failed"
    same_files exact np2
    grep -q '^sums  *exact' exact.log || fail "the header does not say the sums are exact"
    # Stopped alone (a NaN at step 3000) and resumed alone, still with the exact sums.
    set +e
    GRANULAR_INJECT_NAN=3000:17 "$granular" run exact.toml --out resumed --quiet \
      --checkpoint-every 1e-9 >/dev/null 2>resumed.err
    status=$?
    set -e
    [[ $status == 3 ]] || fail "a NaN alone: exit $status, expected 3"
    "$granular" run exact.toml --out resumed --quiet --resume >resume.log 2>&1 ||
      fail "resuming alone failed: $(cat resume.log)"
    grep -q "resuming .* step 3000" resume.log || fail "not resumed at 3000: $(cat resume.log)"
    same_files np2 resumed
    # Without exact sums the run alone moves the same bits, and its energy and reaction sums
    # differ from the mpirun run's in the last bits only where the guide says.
    "$granular" run "$scene" --out plain --quiet >/dev/null || fail "the plain run alone failed"
    cmp -s plain/final_state.csv np2/final_state.csv || fail "the motion differs without exact sums"
    [[ "$(wc -l <plain/timeseries.csv)" == "$(wc -l <np2/timeseries.csv)" ]] ||
      fail "the time series have different lengths"
    columns=$(differing_columns plain/timeseries.csv np2/timeseries.csv)
    grep -q '^reaction_' <<<"$columns" || fail "no reaction differs without exact sums: $columns"
    while read -r column; do
      [[ "$column" =~ ^(reaction_.*|elastic_.*|dissipated_.*|.*_work_J|energy_total_J)$ ]] ||
        fail "$column differs without exact sums"
    done <<<"$columns"
    for f in $(cd np2 && find . -type f ! -name checkpoint.bin ! -name summary.txt | sort); do
      [[ "$f" == ./timeseries.csv || "$f" == *_walls.vtp ]] && continue
      cmp -s "plain/$f" "np2/$f" || fail "$f differs without exact sums"
    done
    ;;
  sigterm)
    # A longer settling, so that the signal lands mid-run.
    with_exact_sums exact.toml
    sed -i 's/^max_time = 0.8 /max_time = 20.0 /' exact.toml
    "$granular" run exact.toml --out whole --quiet >/dev/null || fail "the run alone failed"
    ranks 2 run exact.toml --out stopped --quiet >stopped.log 2>stopped.err &
    job=$!
    for _ in $(seq 600); do
      [[ -f stopped/timeseries.csv ]] && (($(wc -l <stopped/timeseries.csv) > 5)) && break
      sleep 0.1
    done
    launcher=$(pgrep -f "^$mpiexec -np 2 .*--out stopped")
    [[ -n "$launcher" ]] || fail "no mpirun to stop (the run ended first?)"
    kill -TERM "$launcher"
    set +e
    wait "$job"
    status=$?
    set -e
    [[ $status == 1 ]] || fail "mpirun stopped by SIGTERM: exit $status, expected OpenMPI's 1"
    # OpenMPI's event library may warn as mpirun tears the job down ("[warn] Epoll MOD(1) on fd
    # 26 failed ... Bad file descriptor", now and then): its line, not the run's.
    ours=$(grep -v '^\[warn\] Epoll ' stopped.err || true)
    [[ "$(wc -l <<<"$ours")" == 1 ]] || fail "not one line on stderr: $(cat stopped.err)"
    grep -q "^stopped by SIGTERM at t = .*; checkpoint stopped/checkpoint.bin written" \
      stopped.err || fail "the ranks did not say they wrote the checkpoint: $(cat stopped.err)"
    "$granular" run exact.toml --out stopped --quiet --resume >resume.log 2>&1 ||
      fail "resuming alone failed: $(cat resume.log)"
    grep -q "^resuming" resume.log || fail "it did not resume: $(cat resume.log)"
    same_files whole stopped
    ;;
  *)
    fail "unknown case $case_name"
    ;;
esac
echo "ok: $case_name"
