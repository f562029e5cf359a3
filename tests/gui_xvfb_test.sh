#!/usr/bin/env bash
# Opens the real granular-gui window under Xvfb, runs a few hundred steps, changes μ from the
# script, takes a screenshot and checks it (issue 8), and that every label of the controls panel
# shows whole at the default window size: not cut off, no character missing from the font. Exits 77 (ctest: skipped) without Xvfb.
# Usage: gui_xvfb_test.sh GRANULAR_GUI SCREENSHOT_CHECK OUT_DIR
set -euo pipefail
gui=$1 check=$2 out=$3
if ! command -v xvfb-run > /dev/null; then
  echo "xvfb-run not found: skipped (apt-get install xvfb xauth)"
  exit 77
fi
mkdir -p "$out"
rm -f "$out/gui.png" "$out/view.png"
log="$out/gui.log"
script="speed 20; run; wait-steps 300; pause; mu 0.5; step 20; frames 10; colour force; frames 5"
script+="; save-view $out/view.png; frames 2"
if ! xvfb-run -a -s "-screen 0 1280x800x24" "$gui" --frames 100000 --screenshot "$out/gui.png" \
  --script "$script; quit" > "$log" 2>&1; then
  cat "$log"
  if grep -q "Xvfb failed to start" "$log"; then
    echo "Xvfb cannot start on this machine: skipped"
    exit 77
  fi
  echo "granular-gui failed under Xvfb"
  exit 1
fi
cat "$log"
if grep -q "labels cut off\|characters the font lacks" "$log"; then
  echo "FAILED: the controls panel does not show every label whole at the default window size"
  exit 1
fi
summary=$(grep '^granular-gui: [0-9]* frames' "$log" | tail -1)
[[ $summary == *"mu = 0.5,"* ]] || { echo "FAILED: the script's mu 0.5 did not reach the run"; exit 1; }
steps=$(sed -n 's/.* \([0-9]*\) steps,.*/\1/p' <<< "$summary")
(( steps >= 320 )) || { echo "FAILED: $steps steps, expected at least 300 + 20"; exit 1; }
"$check" "$out/gui.png"
"$check" --view "$out/view.png"
