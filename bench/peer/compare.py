#!/usr/bin/env python3
"""Tables of bench/peer/run.sh: wall times, stresses at the end of stage 2, the time-step sweep.

    compare.py RUN_DIR [--interval 0.01] [--from-time 0.1]

Reads what run.sh left in RUN_DIR (layout in run.sh) and prints Markdown tables. Standard
library only. Definitions (bench/peer/README.md):

- Eq. (2) series: sigma_ii from the instantaneous wall forces after every step, averaged over
  windows ((k-1) I, k I] of the stage clock (I = --interval); the same steps-to-window rule for
  every code, so codes and time steps are compared at the same times.
- sweep error of a run: max over windows ending in [--from-time, end] of
  |s33 - s33_ref| / |s33_ref|, the reference being the same code at its smallest step.
- Eq. (1) of a peer: from its final dump through the identity
  V sigma = sum_wall F (x) c - sum_p (f_p - m_p g) (x) x_p (design section 4), with the wall
  contact point c midway in the overlap as granular puts it; pair terms do not depend on c.
"""
import argparse
import contextlib
import glob
import io
import math
import os
import re
import sys


def read_keys(path):
    """`key = value` lines of a run's stdout."""
    keys = {}
    with open(path) as f:
        for line in f:
            m = re.match(r"^(\w+) = (.*)$", line.strip())
            if m:
                keys[m.group(1)] = m.group(2)
    return keys


def read_series(path):
    """Per-step rows {step: (top_z, s11, s22, s33)} from granular's CSV or a peer's ave/time."""
    rows = {}
    with open(path) as f:
        for line in f:
            if line.startswith("#") or line.startswith("step"):
                continue
            parts = line.replace(",", " ").split()
            step = int(parts[0])
            values = [float(v) for v in parts[-4:]]
            if step >= 1:  # step 0 is the state before stage 2's first step
                rows[step] = tuple(values)
    return rows


def windows(rows, dt, interval, end):
    """Mean of each column over the steps n with n dt in ((k-1) I, k I], for complete windows."""
    return timed_windows({step * dt: values for step, values in rows.items()}, interval, end)


def read_timed_series(path):
    """Per-step rows {time: (top_z, s11, s22, s33)} of granular's CSV (steps of any length)."""
    rows = {}
    with open(path) as f:
        for line in f:
            if line.startswith("step"):
                continue
            parts = line.split(",")
            rows[float(parts[1])] = tuple(float(v) for v in parts[-4:])
    return rows


def timed_windows(rows, interval, end):
    """windows() for steps of any length: the mean over the steps ending in ((k-1) I, k I]."""
    sums, counts = {}, {}
    for t, values in rows.items():
        k = math.ceil(t / interval - 1e-6)
        acc = sums.setdefault(k, [0.0] * len(values))
        for i, v in enumerate(values):
            acc[i] += v
        counts[k] = counts.get(k, 0) + 1
    last = math.floor(end / interval + 1e-6)
    return {k * interval: [v / counts[k] for v in sums[k]] for k in sorted(sums) if 1 <= k <= last}


def sweep_error(run, ref, from_time):
    """max |s33 - s33_ref| / |s33_ref| over the common windows ending at or after from_time."""
    worst = 0.0
    for t, values in run.items():
        if t + 1e-9 >= from_time and t in ref:
            worst = max(worst, abs(values[3] - ref[t][3]) / abs(ref[t][3]))
    return worst


def increment_error(run, ref, from_time):
    """The same on what the moving wall adds, s33(t) - s33(first window): max |d - d_ref| over
    max |d_ref|. sigma33 is mostly the bed's weight, which any stable step gets right; this
    isolates the compaction (informative only, not the criterion)."""
    first = min(ref)
    if first not in run:
        return float("nan")
    span = max(abs(v[3] - ref[first][3]) for v in ref.values()) or 1.0
    worst = 0.0
    for t, values in run.items():
        if t + 1e-9 >= from_time and t in ref:
            d, d_ref = values[3] - run[first][3], ref[t][3] - ref[first][3]
            worst = max(worst, abs(d - d_ref) / span)
    return worst


def read_model_vars(path):
    """`variable NAME equal VALUE` lines of an exported model file."""
    out = {}
    with open(path) as f:
        for line in f:
            m = re.match(r"^variable (\w+) equal ([-0-9.eE+]+)\s*$", line)
            if m:
                out[m.group(1)] = float(m.group(2))
    return out


# Per-atom wall-force columns of the peers' final dumps: (column prefix, axis, which wall).
WALL_COLUMNS = [
    ("v_wx_", 0, "auto"), ("v_wy_", 1, "auto"), ("v_wb_", 2, "lo"), ("v_wt_", 2, "hi"),  # LAMMPS
    ("f_force_xlo[", 0, "lo"), ("f_force_xhi[", 0, "hi"), ("f_force_ylo[", 1, "lo"),
    ("f_force_yhi[", 1, "hi"), ("f_force_zlo[", 2, "lo"), ("f_force_topwall[", 2, "hi"),  # LIGGGHTS
]


def peer_eq1(dump, model, top_z):
    """sigma of Eq. (1) [Pa], row = force component, column = branch component."""
    box = read_model_vars(model)
    g = (0.0, 0.0, -box["grav_g"])
    lo = (box["box_xlo"], box["box_ylo"], box["box_zlo"])
    hi = (box["box_xhi"], box["box_yhi"], top_z)
    with open(dump) as f:
        lines = f.read().splitlines()
    start = lines.index(next(l for l in lines if l.startswith("ITEM: ATOMS")))
    names = lines[start].split()[2:]
    s = [[0.0] * 3 for _ in range(3)]
    for line in lines[start + 1:]:
        a = dict(zip(names, (float(v) for v in line.split())))
        x = (a["x"], a["y"], a["z"])
        r, m = a["radius"], a["mass"]
        f = (a["fx"], a["fy"], a["fz"])
        for i in range(3):
            for j in range(3):
                s[i][j] -= (f[i] - m * g[i]) * x[j]
        for prefix, axis, side in WALL_COLUMNS:
            if prefix + "x" not in a and prefix + "1]" not in a:
                continue
            comps = ("x", "y", "z") if prefix + "x" in a else ("1]", "2]", "3]")
            fw = tuple(a[prefix + c] for c in comps)
            if fw == (0.0, 0.0, 0.0):
                continue
            # A pair of walls in one column set (LAMMPS xplane lo hi): the side the particle is on.
            upper = side == "hi" or (side == "auto" and x[axis] > 0.5 * (lo[axis] + hi[axis]))
            distance = hi[axis] - x[axis] if upper else x[axis] - lo[axis]
            overlap = r - distance
            c = list(x)
            c[axis] += (1 if upper else -1) * (r - 0.5 * overlap)
            for i in range(3):
                for j in range(3):
                    s[i][j] += fw[i] * c[j]
    volume = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2])
    return [[v / volume for v in row] for row in s]


def loop_time(log):
    """LAMMPS/LIGGGHTS 'Loop time of X on P procs for M steps with N atoms' -> (X, M, N)."""
    with open(log) as f:
        m = re.search(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms",
                      f.read())
    return (float(m.group(1)), int(m.group(2)), float(m.group(3))) if m else (None, None, None)


def fmt_tensor(rows):
    return "[" + "; ".join(" ".join(f"{v:.1f}" for v in row) for row in rows) + "]"


def best_timings(run_dir, folder):
    """{(code, threads): (wall s, particle-steps/s, steps)}: the best of the repetitions of the
    timing runs in run_dir/folder."""
    best = {}
    for path in sorted(glob.glob(os.path.join(run_dir, folder, "*.out"))):
        code, threads, _ = os.path.basename(path)[:-4].rsplit("_", 2)
        keys = read_keys(path)
        if "wall_s" in keys:
            wall, steps, n = float(keys["wall_s"]), int(keys["steps"]), float(keys["particles"])
        else:
            wall, steps, n = loop_time(path)
        if wall is None:
            continue
        key = (code, int(threads[1:]))
        if key not in best or wall < best[key][0]:
            best[key] = (wall, n * steps / wall, steps)
    return best


def timing_table(run_dir):
    """Best of the repetitions per code and thread count."""
    best = best_timings(run_dir, "timing")
    loads = []
    load_file = os.path.join(run_dir, "timing", "load.txt")
    if os.path.exists(load_file):
        with open(load_file) as f:
            loads = [float(m) for m in re.findall(r"load average: ([0-9.]+)", f.read())]
    print("### Wall time of stage 2 (best of the repetitions)\n")
    print("| code | threads/ranks | steps | wall s | particle-steps/s | granular-gear5 / this "
          "| granular-verlet / this |")
    print("|---|---|---|---|---|---|---|")
    for (code, threads), (wall, rate, steps) in sorted(best.items()):
        ratios = []
        for ours in ("granular-gear5", "granular-verlet"):
            o = best.get((ours, threads))
            ratios.append(f"{o[1] / rate:.2f}" if o else "-")
        print(f"| {code} | {threads} | {steps} | {wall:.3f} | {rate:.3g} | {ratios[0]} "
              f"| {ratios[1]} |")
    if loads:
        print(f"\n1-minute load average around the timings: min {min(loads):.2f}, "
              f"max {max(loads):.2f} (2 cores)")
    return best


def series_runs(run_dir):
    """{code: {factor: (stdout keys, series file)}} of the sweep runs."""
    runs = {}
    for path in glob.glob(os.path.join(run_dir, "sweep", "*.out")):
        code, factor = os.path.basename(path)[:-4].rsplit("_x", 1)
        stem = path[:-4]
        series = next((stem + e for e in (".csv", ".series") if os.path.exists(stem + e)), None)
        runs.setdefault(code, {})[float(factor)] = (path, series)
    return runs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run_dir")
    ap.add_argument("--interval", type=float, default=0.01)
    ap.add_argument("--from-time", type=float, default=0.1)
    ap.add_argument("--tolerance", type=float, default=0.01)
    ap.add_argument("--largest", action="store_true",
                    help="print 'code factor' for each fixed-step code's largest step within the "
                         "tolerance, and nothing else")
    args = ap.parse_args()
    with open(os.path.join(args.run_dir, "settings.txt")) as f:
        # "lammps = " with nothing after it when that peer is not installed
        settings = {k.strip(): v.strip() for k, v in (l.split(" = ", 1) for l in f if " = " in l)}
    dt0, tend = float(settings["dt"]), float(settings["tend"])

    runs = series_runs(args.run_dir)
    if args.largest:
        with contextlib.redirect_stdout(io.StringIO()):
            largest = sweep_table(args, runs, dt0, tend)
        for code in ("granular-gear5", "granular-verlet", "lammps", "liggghts"):
            if code in largest:
                print(f"{code} {largest[code]:g}")
        return 0
    best = timing_table(args.run_dir)

    # Stresses at the end, from each code's run at the paper's step.
    print(f"\n### Stresses at t = {tend:g} s (dt = {dt0:g} s), Pa, compression negative\n")
    print(f"Eq. (2): mean over the last window ({tend - args.interval:g}, {tend:g}] s of the "
          "per-step values; Eq. (1): the final state.\n")
    print("| code | sigma11 Eq.2 | sigma22 Eq.2 | sigma33 Eq.2 | Eq. (1) tensor [row = force] |")
    print("|---|---|---|---|---|")
    for code in sorted(runs):
        if 1.0 not in runs[code]:
            continue
        out, series = runs[code][1.0]
        keys = read_keys(out)
        if not series or "top_z_m" not in keys:
            print(f"| {code} | failed | | | see {out} |")
            continue
        w = windows(read_series(series), dt0, args.interval, tend)
        last = w[max(w)]
        if "sigma_eq1_Pa" in keys:
            v = [float(x) for x in keys["sigma_eq1_Pa"].split()]
            eq1 = [v[0:3], v[3:6], v[6:9]]
        else:
            model = glob.glob(os.path.join(args.run_dir, "export", code, "model.l*"))[0]
            eq1 = peer_eq1(out[:-4] + ".dump", model, float(keys["top_z_m"]))
        print(f"| {code} | {last[1]:.1f} | {last[2]:.1f} | {last[3]:.1f} | {fmt_tensor(eq1)} |")

    largest = sweep_table(args, runs, dt0, tend)
    trust_table(args, runs, best, largest, dt0, tend)
    return 0


def sweep_table(args, runs, dt0, tend):
    """The time-step sweep's table; returns {code: its largest factor within the tolerance}."""
    print(f"\n### Largest step keeping sigma33(t) within {args.tolerance:.0%} of the code's own "
          "small-step reference\n")
    print(f"Error = max over windows ending in [{args.from_time:g}, {tend:g}] s of "
          "|s33 - s33_ref| / |s33_ref| (Eq. 2, window means). Increment error: the same on "
          "s33(t) - s33(first window), over the reference's largest increment (not the "
          "criterion).\n")
    print("| code | dt / paper dt | dt s | steps | error | within | increment error |")
    print("|---|---|---|---|---|---|---|")
    largest = {}
    for code in sorted(runs):
        factors = sorted(runs[code])
        # granular's fixed steps with their check off are measured against the checked run's
        # reference (the same integrator and step: the check changes nothing below the limit).
        base = code[:-len("-unchecked")] if code.endswith("-unchecked") else code
        if base not in runs or code.startswith("granular-auto") or \
                (base == code and len(factors) < 2):
            continue  # run at the paper's step only, for the stress table
        ref_factor = sorted(runs[base])[0]
        ref = windows(read_series(runs[base][ref_factor][1]), dt0 * ref_factor, args.interval,
                      tend)
        for factor in factors:
            out, series = runs[code][factor]
            keys = read_keys(out)
            dt = dt0 * factor
            if not series or "top_z_m" not in keys:
                with open(out) as f:
                    text = f.read()
                # granular refuses a step above its integrator's limit before running
                refused = re.search(r"above the (stable )?limit|contact network allows", text)
                reason = "refused (step limit)" if refused else "failed (unstable)"
                print(f"| {code} | {factor:g} | {dt:.3g} | - | {reason} | no | - |")
                continue
            run = windows(read_series(series), dt, args.interval, tend)
            err = sweep_error(run, ref, args.from_time)
            inc = increment_error(run, ref, args.from_time)
            ok = err <= args.tolerance
            tag = "reference" if factor == ref_factor and base == code else \
                ("yes" if ok else "no")
            steps = math.ceil(tend / dt - 1e-6)
            print(f"| {code} | {factor:g} | {dt:.3g} | {steps} | {err:.2e} | {tag} | {inc:.2e} |")
            if ok and (factor != ref_factor or base != code) and \
                    (code not in largest or factor > largest[code]):
                largest[code] = factor
    return largest


def trust_table(args, runs, best, largest, dt0, tend):
    """Speed for a trustworthy answer: simulated seconds per wall second at each code's largest
    step, timed at that step (run_dir/at-largest); where no such timing exists, projected from
    the timing at the paper's step times the factor, which leaves out that a longer step
    rebuilds the neighbour list more often per step (the projection is marked)."""
    at_largest = best_timings(args.run_dir, "at-largest")
    print("\n| code | largest step / paper dt | threads | simulated s per wall s | timed | "
          "granular-gear5 / this | granular-verlet / this |")
    print("|---|---|---|---|---|---|---|")
    trust = {}
    for threads in sorted({t for (_, t) in best}):
        speed = trust.setdefault(threads, {})
        for code, factor in largest.items():
            if (code, threads) in at_largest:
                speed[code] = (factor, tend / at_largest[(code, threads)][0], "at that step")
            elif (code, threads) in best:
                wall, _, steps = best[(code, threads)]
                speed[code] = (factor, tend / wall * factor, "projected")
        for code, (factor, v, how) in sorted(speed.items()):
            ratios = []
            for ours in ("granular-gear5", "granular-verlet"):
                o = speed.get(ours)
                ratios.append(f"{o[1] / v:.2f}" if o else "-")
            print(f"| {code} | {factor:g} | {threads} | {v:.3f} | {how} | {ratios[0]} | "
                  f"{ratios[1]} |")
    auto_table(args, runs, best, trust, dt0, tend)


def auto_table(args, runs, best, trust, dt0, tend):
    """time_step = "auto" (one run per code, its own steps): sigma33 against granular-verlet's
    small-step reference, and its speed (simulated s per wall s, its own timing) against each
    peer's speed at the peer's largest step within the tolerance."""
    autos = sorted(c for c in runs if c.startswith("granular-auto"))
    if not autos or "granular-verlet" not in runs:
        return
    ref_factor = sorted(runs["granular-verlet"])[0]
    ref = windows(read_series(runs["granular-verlet"][ref_factor][1]), dt0 * ref_factor,
                  args.interval, tend)
    print(f"\n### time_step = \"auto\": sigma33 against granular-verlet at {ref_factor:g} x dt, "
          "and speed against each code's largest step within the tolerance\n")
    print("| code | threads | steps | dt range s | error | within | simulated s per wall s | "
          "LAMMPS / this | LIGGGHTS / this | this / LAMMPS | this / LIGGGHTS |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for code in autos:
        out, series = runs[code][1.0]
        keys = read_keys(out)
        if not series or "top_z_m" not in keys:
            print(f"| {code} | - | - | - | failed | no | - | - | - | - | - |")
            continue
        err = sweep_error(timed_windows(read_timed_series(series), args.interval, tend), ref,
                          args.from_time)
        ok = "yes" if err <= args.tolerance else "no"
        for threads in sorted(trust):
            if (code, threads) not in best:
                continue
            wall, _, steps = best[(code, threads)]
            v = tend / wall
            peers = [trust[threads].get(p) for p in ("lammps", "liggghts")]
            cells = [f"{p[1] / v:.2f}" if p else "-" for p in peers]
            cells += [f"**{v / p[1]:.2f}**" if p else "-" for p in peers]
            print(f"| {code} | {threads} | {steps} | {keys.get('dt_range_s', '-')} | {err:.2e} | "
                  f"{ok} | {v:.3f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    sys.exit(main())
