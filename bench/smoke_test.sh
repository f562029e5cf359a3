#!/usr/bin/env bash
# The benchmark programs' documented commands (README.md, bench/RESULTS.md, bench/peer/README.md,
# docs/) run in a short mode: fewer particles, steps or cases, so that a program the engine has
# outgrown fails here rather than in a reader's hands. A case fails when a command exits non-zero;
# the figures are not looked at. Registered with ctest in bench/CMakeLists.txt, one test a case.
#
#   smoke_test.sh CASE BUILD_DIR SOURCE_DIR WORK_DIR [MPIEXEC]
#
# CASE: paper (the settled checkpoints that accuracy, peer_stage2 and peer_run restore: the
# paper's two cases on the tests' reduced scene, tests/scenes/reduced-compaction.toml, as
# `granular paper` makes them), step, render, scale, gear_stability, accuracy, heap, ranks,
# peer_stage2, peer_run. MPIEXEC: mpirun, for the ranks case's runs under it (none: skipped).
# Exit 77 (skipped): peer_run without python3, which compare.py needs.
set -euo pipefail

case=$1
build=$(realpath "$2")
source=$(realpath "$3")
work=$(realpath -m "$4")
mpiexec=${5:-}
bench=$build/bench
scenes=$work/scenes
paper=$work/paper
checkpoint=$paper/mu03/settled.ckpt
out=$work/$case
rm -rf "$out"
mkdir -p "$out"
cd "$out"

# Each command echoed first, so that a failure's log names it.
run() {
  echo "+ $*"
  "$@"
}

case $case in
  paper)
    # ./build/release/app/granular paper --out runs/paper (bench/peer/README.md)
    rm -rf "$scenes" "$paper"
    mkdir -p "$scenes"
    for friction in mu0:0.0 mu03:0.3; do
      { cat "$source/tests/scenes/reduced-compaction.toml"
        printf '\n[material]\nfriction = %s\n' "${friction#*:}"; } > "$scenes/paper-${friction%%:*}.toml"
    done
    run "$build/app/granular" paper --scenes "$scenes" --out "$paper" --quiet
    ;;
  step)
    # build/release/bench/granular_bench [--benchmark_filter=...] (bench/RESULTS.md)
    run "$bench/granular_bench" --quick
    ;;
  render)
    # build/release/bench/granular_bench_render [--benchmark_filter=figure] (bench/RESULTS.md);
    # its 10⁶-sphere frames take a minute
    run "$bench/granular_bench_render" --benchmark_filter='n:1980/|figure' \
      --benchmark_min_time=0.01
    ;;
  scale)
    # ./build/release/bench/granular_bench_scale --n 1000,10000,100000 (README.md) and
    # granular_bench_scale --n $n --settle 2000 [--shuffle | --cell-order] (bench/RESULTS.md)
    run "$bench/granular_bench_scale" --n 1000 --steps 50
    run "$bench/granular_bench_scale" --n 1000 --settle 2000 --steps 20 --cell-order
    run "$bench/granular_bench_scale" --n 1000 --steps 20 --shuffle --integrator verlet
    ;;
  gear_stability)
    # OMP_NUM_THREADS=1 build/release/bench/granular_bench_gear_stability (bench/RESULTS.md),
    # whole: a few seconds
    OMP_NUM_THREADS=1 run "$bench/granular_bench_gear_stability"
    ;;
  accuracy)
    # ./build/release/bench/granular_bench_accuracy --run runs/paper [--quick] (README.md)
    run "$bench/granular_bench_accuracy" --run "$paper" --scenes "$scenes" --quick --out "$out"
    test -s "$out/accuracy.png" -a -s "$out/accuracy.md"
    ;;
  heap)
    # build/release/bench/granular_bench_heap --rolling-friction 0,0.05,0.1 --seed 1,2
    # --out heap.csv (docs/validation.md §6a), --cohesion (§6c), and --method pour
    run "$bench/granular_bench_heap" --rolling-friction 0,0.1 --seed 1 --particles 200 \
      --max-time 0.5 --out "$out/heap.csv"
    run "$bench/granular_bench_heap" --method pour --rolling-friction 0.1 --cohesion 0,1e5 \
      --particles 200 --max-time 0.5
    test -s "$out/heap.csv"
    ;;
  ranks)
    # granular_bench_ranks --n 100000 --threads 2, and OMP_NUM_THREADS=1 mpirun -np 2
    # granular_bench_ranks --n 1000000 --settle 1500 --steps 100 --bed bed.bin --threads 1
    # --mode 2 (bench/RESULTS.md, docs/scaling.md)
    small=(--n 2000 --settle 300 --steps 10)
    run "$bench/granular_bench_ranks" "${small[@]}" --threads 2 --mode 1
    run "$bench/granular_bench_ranks" "${small[@]}" --threads 1 --mode 3
    if [[ -n $mpiexec ]]; then
      for pass in write read; do
        echo "(--bed: $pass)"
        OMP_NUM_THREADS=1 run "$mpiexec" -np 2 --oversubscribe --allow-run-as-root \
          "$bench/granular_bench_ranks" "${small[@]}" --threads 1 --mode 2 --bed "$out/bed.bin"
      done
    fi
    ;;
  peer_stage2)
    # granular_peer_stage2 --checkpoint runs/paper/mu03/settled.ckpt --fresh --duration 0.3
    # --threads 2 --integrator I --series FILE, --exact-sums, --dt 1.7e-4 --skin 0.003, --unchecked
    # (bench/RESULTS.md, bench/peer/README.md)
    restored=(--checkpoint "$checkpoint" --scene "$scenes/paper-mu03.toml")
    for integrator in gear5 verlet; do
      run "$bench/granular_peer_stage2" "${restored[@]}" --fresh --duration 0.05 --threads 2 \
        --integrator "$integrator" --series "$out/series_$integrator.csv"
    done
    run "$bench/granular_peer_stage2" "${restored[@]}" --duration 0.05 --exact-sums
    run "$bench/granular_peer_stage2" "${restored[@]}" --fresh --dt 1.7e-4 --skin 0.003 \
      --duration 0.05 --rebuild-every-step
    # a step above the network's limit, its check off (the sweep's granular-*-unchecked)
    run "$bench/granular_peer_stage2" "${restored[@]}" --fresh --integrator verlet --unchecked \
      --dt 6.8e-4 --skin 0.003 --duration 0.05
    ;;
  peer_run)
    # bench/peer/run.sh --quick (bench/peer/README.md); LAMMPS and LIGGGHTS, where absent, are
    # skipped by run.sh itself
    if ! command -v python3 > /dev/null; then
      echo "skipped: bench/peer/run.sh needs python3 for compare.py"
      exit 77
    fi
    run bash "$source/bench/peer/run.sh" --quick --no-build --build-dir "$build" \
      --checkpoint "$checkpoint" --scene "$scenes/paper-mu03.toml" --out "$out" --no-wait
    test -s "$out/report.md"
    ;;
  *)
    echo "smoke_test.sh: unknown case $case" >&2
    exit 2
    ;;
esac
