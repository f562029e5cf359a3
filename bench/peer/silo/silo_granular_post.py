#!/usr/bin/python3
"""Post-processing of granular's silo runs, and the comparison with LIGGGHTS (standard library).

    silo_granular_post.py run RUNDIR [--csv-dir DIR] [--wall-seconds S] [--cpu-seconds S]
    silo_granular_post.py compare --granular SUMMARY.json ... --liggghts SUMMARY.json ...
                                  [--title TEXT]

`run` reads one granular run (RUNDIR/run.json from silo_granular.py, RUNDIR/out/ from `granular
run`) and writes into --csv-dir (default RUNDIR) the files silo_post.py writes for LIGGGHTS, with
the same keys, so that `silo_post.py table` and `profile` read both codes' runs:
  discharge_<seed>.csv, wall_pressure_<seed>.csv, summary_<seed>.json.
`compare` prints the comparison as markdown: W of each code (mean +- seed-to-seed sd) and whether
|dW| <= sqrt(s_a^2 + s_b^2); p_h per band for both and the fraction of bands within their combined
scatter; particle-steps/s of both and their ratio.

Definitions, as silo_post.py's:
  discharged mass(t) = granular's mass_discharged_kg (the particles the outlet below
      z = delete_below_z removed, every sample_interval) at t from the gate's removal; it trails
      LIGGGHTS's M(open) - mass above z = 0 by the fall from the floor to the outlet, which
      shifts the curve in time and leaves its slope;
  W = least-squares slope over the samples within [fit_low, fit_high] x the final value;
  p_h of a band [z_lo, z_hi) = sum over the cylinder's contacts of particles whose centre lies in
      the band of -(F . r_hat), F the wall's force on the particle (normal + tangential, the
      contacts file's), r_hat from the axis to the centre, / (2 pi R (z_hi - z_lo)); mean and sd
      over the rest stage's snapshots;
  particle-steps = sum over the time series' samples of the steps since the previous sample x
      the particles held; speeds divide them by the stages' wall-clock (summary.txt: each
      stage's loop, snapshots included, set-up and the final output excluded).
"""
import argparse
import csv
import glob
import json
import math
import os
import re
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import silo_post  # noqa: E402

STAGE_LINE = re.compile(r"^\s+(\w+): ended by (.*); ([0-9.eE+-]+) s simulated, (\d+) steps, "
                        r"([0-9.eE+-]+) s wall-clock$")


def read_summary_txt(path):
    stages = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            m = STAGE_LINE.match(line.rstrip("\n"))
            if m:
                stages[m.group(1)] = {"reason": m.group(2), "simulated_s": float(m.group(3)),
                                      "steps": int(m.group(4)), "wall_s": float(m.group(5))}
    return stages


def read_csv(path):
    with open(path, encoding="utf-8") as f:
        return list(csv.DictReader(f))


def process_run(rundir, csv_dir, wall_seconds=None, cpu_seconds=None):
    with open(os.path.join(rundir, "run.json"), encoding="utf-8") as f:
        r = json.load(f)
    p = r["params"]
    out = os.path.join(rundir, "out")
    seed = r["seed"]
    g = r["gravity"]
    checks = []
    stages = read_summary_txt(os.path.join(out, "summary.txt"))
    for name in ("fill", "rest", "discharge"):
        if name not in stages:
            raise SystemExit(f"silo_granular_post.py: {out}/summary.txt has no stage {name} "
                             "(run failed?)")
    with open(os.path.join(out, "summary.txt"), encoding="utf-8") as f:
        warnings = [line.strip() for line in f if line.startswith("warning:")]
    rows = read_csv(os.path.join(out, "timeseries.csv"))
    for row in rows:
        for k in ("time_s", "step", "particles", "mass_held_kg", "mass_inserted_kg",
                  "mass_discharged_kg", "reaction_cylinder_z_N", "reaction_floor_z_N",
                  "reaction_gate_z_N"):
            row[k] = float(row[k]) if row[k] != "" else float("nan")
    s = {"code": "granular", "seed": seed, "ranks": r["threads"], "threads": r["threads"],
         "n_requested": r["n_particles"], "d0_m": r["d0_m"], "d0_ratio": r["d0_ratio"],
         "quick": r["quick"]}

    # ---- Fill: the first row of the rest stage is the state the fill ended with.
    rest_rows = [row for row in rows if row["stage"] == "rest"]
    settled = rest_rows[0]
    n_in = int(settled["particles"])
    mass = settled["mass_held_kg"]
    m_mean = r["mean_particle_mass"]
    rho = p["density"]
    a, b = p["radius_min"], p["radius_max"]
    # sd of a sphere's mass with R uniform in [a, b]: <m^2> - <m>^2, <R^6> = (b^7-a^7)/(7(b-a))
    r6 = (b ** 7 - a ** 7) / (7.0 * (b - a)) if b > a else a ** 6
    sd_m = math.sqrt(max(0.0, (rho * 4.0 / 3.0 * math.pi) ** 2 * r6 - m_mean ** 2))
    sigma = math.sqrt(n_in) * sd_m
    expected = n_in * m_mean
    z = (mass - expected) / sigma if sigma > 0 else 0.0
    fill = stages["fill"]
    capped = fill["reason"].startswith("max time")
    s.update({"inserted": n_in, "t_settled_s": fill["simulated_s"], "mass_kg": mass,
              "mass_expected_kg": expected, "mass_sigma_kg": sigma, "settle_capped": capped,
              "settle_reason": fill["reason"]})
    checks.append(("all particles inserted", n_in == r["n_particles"],
                   f"{n_in} of {r['n_particles']}"))
    checks.append(("held mass = N x mean mass", abs(z) < 4.0,
                   f"{mass:.6g} kg; N <m> = {expected:.6g} kg, {(mass / expected - 1) * 100:+.3f} "
                   f"%, {z:+.2f} sigma of the random radii"))
    checks.append(("inserted mass = held mass",
                   abs(settled["mass_inserted_kg"] - mass) < 1e-9 * mass,
                   f"inserted {settled['mass_inserted_kg']:.9g} kg"))
    checks.append(("settled below the KE threshold", not capped,
                   f"fill: {fill['reason']} after {fill['simulated_s']:.4f} s "
                   f"(cap {r['t_settle_cap']:.3f} s), threshold {r['ke_stop']:.3g} J"))

    # ---- Rest: the snapshots' contacts, each particle's centre from the snapshot beside it.
    contact_files = sorted(glob.glob(os.path.join(out, "contacts_rest_*.csv")),
                           key=lambda x: int(re.search(r"_(\d+)\.csv$", x).group(1)))
    big_r = r["silo_radius"]
    band = p["pressure_band"]
    last_snap = None
    per_sample = []  # (support by wall, band pushes)
    wall_roots, pair_roots = [], []
    for k, path in enumerate(contact_files):
        step = re.search(r"_(\d+)\.csv$", path).group(1)
        snap = read_csv(os.path.join(out, f"snapshot_rest_{step}.csv"))
        centre = {int(row["id"]): (float(row["x"]), float(row["y"]), float(row["z"]),
                                   float(row["radius"])) for row in snap}
        last_snap = centre
        fz = {"cylinder": 0.0, "floor": 0.0, "gate": 0.0}
        pushes = {}
        last = k == len(contact_files) - 1
        for row in read_csv(path):
            wall = row["wall"]
            if not wall:
                if last:
                    pair_roots.append(math.sqrt(float(row["overlap_m"])))
                continue
            fx = float(row["normal_force_x_N"]) + float(row["tangential_force_x_N"])
            fy = float(row["normal_force_y_N"]) + float(row["tangential_force_y_N"])
            fzc = float(row["normal_force_z_N"]) + float(row["tangential_force_z_N"])
            fz[wall] = fz.get(wall, 0.0) + fzc
            if last:
                wall_roots.append(math.sqrt(float(row["overlap_m"])))
            if wall != "cylinder":
                continue
            x, y, zc, _ = centre[int(row["particle"])]
            rho_c = math.hypot(x, y)
            outward = -(fx * x + fy * y) / rho_c
            kb = int(zc // band)
            pushes[kb] = pushes.get(kb, 0.0) + outward
        per_sample.append((fz, pushes))
    if last_snap is None:
        raise SystemExit(f"silo_granular_post.py: {out}: no contacts_rest_*.csv (snapshots?)")
    top = max(c[2] + c[3] for c in last_snap.values())
    nbands = int(math.ceil(min(top, r["silo_height"]) / band))
    band_samples = [[ps.get(k, 0.0) / (2.0 * math.pi * big_r * band) for _, ps in per_sample]
                    for k in range(nbands)]
    weight = mass * g
    support = [sum(fz.values()) for fz, _ in per_sample]
    sup_mean, sup_std = silo_post.mean_std(support)
    mesh_means = {w: statistics.fmean(fz[w] for fz, _ in per_sample)
                  for w in ("cylinder", "floor", "gate")}
    # the time series' reactions (the particles' push on each wall) over the rest stage
    series_support = [-(row["reaction_cylinder_z_N"] + row["reaction_floor_z_N"]
                        + row["reaction_gate_z_N"]) for row in rest_rows[1:]]
    ser_mean, _ = silo_post.mean_std(series_support)
    s.update({"weight_N": weight, "support_N": sup_mean, "support_std_N": sup_std,
              "support_series_N": ser_mean, "support_cylinder_N": mesh_means["cylinder"],
              "support_floor_N": mesh_means["floor"], "support_gate_N": mesh_means["gate"],
              "rest_samples": len(per_sample), "bed_top_m": top,
              "bed_height_nominal_m": r["n_particles"] * m_mean / (rho * 0.6 * math.pi
                                                                   * big_r ** 2)})
    checks.append(("wall reactions carry the weight (2 %)", abs(sup_mean / weight - 1) < 0.02,
                   f"sum of vertical wall forces {sup_mean:.5g} N (contacts), {ser_mean:.5g} N "
                   f"(time series), weight {weight:.5g} N: {(sup_mean / weight - 1) * 100:+.3f} %;"
                   f" cylinder {mesh_means['cylinder']:.4g} N, floor {mesh_means['floor']:.4g} N,"
                   f" gate {mesh_means['gate']:.4g} N"))
    checks.append(("rest snapshots", len(per_sample) == r["rest_samples"],
                   f"{len(per_sample)} of {r['rest_samples']}"))
    pressure = []
    for k in range(nbands):
        m_, sd = silo_post.mean_std(band_samples[k])
        pressure.append((k * band, min((k + 1) * band, r["silo_height"]), m_, sd,
                         len(band_samples[k])))
    s["p_h_Pa"] = [row[2] for row in pressure]
    s["p_h_band_m"] = band
    s["sqrt_overlap_pair"] = statistics.fmean(pair_roots) if pair_roots else float("nan")
    s["sqrt_overlap_wall"] = statistics.fmean(wall_roots) if wall_roots else float("nan")
    s["contacts_pair"] = len(pair_roots)
    s["contacts_wall"] = len(wall_roots)

    # ---- Discharge.
    dis = [row for row in rows if row["stage"] == "discharge"]
    t_open = dis[0]["time_s"]
    curve = [(row["time_s"] - t_open, row["mass_discharged_kg"]) for row in dis]
    final = curve[-1][1]
    lo, hi = p["fit_low"] * final, p["fit_high"] * final
    window = [(t, m) for t, m in curve if lo <= m <= hi]
    if len(window) >= 3 and final > 0:
        w, b0, r2 = silo_post.least_squares([t for t, _ in window], [m for _, m in window])
        worst = max(abs(m - (b0 + w * t)) for t, m in window) / final
    else:
        w = b0 = r2 = worst = float("nan")
    drops = [curve[i][1] - curve[i + 1][1] for i in range(len(curve) - 1)]
    worst_drop = max([0.0] + drops)
    balance = max(abs(float(row["mass_balance_kg"])) for row in rows
                  if row["mass_balance_kg"] != "")
    s.update({"t_open_s": t_open, "discharge_s": curve[-1][0], "discharged_kg": final,
              "W_kg_s": w, "fit_intercept_kg": b0, "fit_r2": r2,
              "fit_window_s": [window[0][0], window[-1][0]] if window else None,
              "fit_worst_residual_frac": worst, "largest_decrease_kg": worst_drop,
              "mass_in_silo_at_open_kg": dis[0]["mass_held_kg"]})
    checks.append(("discharged mass monotone", worst_drop <= 1e-3 * max(final, 1e-12),
                   f"largest decrease between samples {worst_drop:.3g} kg"))
    checks.append(("mass balance", balance == 0.0, f"largest |mass_balance_kg| {balance:.3g}"))
    checks.append(("roughly linear between 20 and 80 %", r2 > 0.99,
                   f"R^2 = {r2:.5f}, largest residual {worst * 100:.2f} % of the final mass"))
    checks.append(("no run-check warning", not warnings, "; ".join(warnings) or "none"))

    # ---- Timings: the interval before a sample belongs to the stage of the sample before it.
    psteps = {name: 0.0 for name in stages}
    counted = {name: 0 for name in stages}
    for prev, row in zip(rows, rows[1:]):
        d = int(row["step"] - prev["step"])
        psteps[prev["stage"]] += d * row["particles"]
        counted[prev["stage"]] += d
    last = rows[-1]
    psteps[last["stage"]] += (stages[last["stage"]]["steps"] - counted[last["stage"]]) \
        * last["particles"]
    after = [row for row in rows if row["stage"] == "fill" and row["time_s"] > r["t_insert_end"]]
    total_s = sum(st["wall_s"] for st in stages.values())
    total_ps = sum(psteps.values())
    fill_s = stages["fill"]["wall_s"]
    s["timing"] = {
        "threads": r["threads"], "fill_settle_loop_s": fill_s,
        "fill_settle_steps": stages["fill"]["steps"],
        "fill_settle_particle_steps": psteps["fill"],
        "fill_settle_particle_steps_per_s": psteps["fill"] / fill_s if fill_s > 0 else math.nan,
        "rest_loop_s": stages["rest"]["wall_s"], "discharge_loop_s": stages["discharge"]["wall_s"],
        "discharge_steps": stages["discharge"]["steps"],
        "discharge_particle_steps": psteps["discharge"], "total_loop_s": total_s,
        "total_steps": sum(st["steps"] for st in stages.values()),
        "total_particle_steps": total_ps,
        "particle_steps_per_s": total_ps / total_s if total_s > 0 else math.nan,
        # granular's stages give no wall time for the settling after the last insertion alone
        "settle_particle_steps_per_s": math.nan,
        "discharge_particle_steps_per_s": (psteps["discharge"] / stages["discharge"]["wall_s"]
                                           if stages["discharge"]["wall_s"] > 0 else math.nan),
        "wall_s": wall_seconds, "cpu_s": cpu_seconds,
        "settle_samples_after_insertion": len(after)}

    os.makedirs(csv_dir, exist_ok=True)
    with open(os.path.join(csv_dir, f"discharge_{seed}.csv"), "w", encoding="utf-8") as f:
        f.write("time_s,discharged_mass_kg\n")
        for t, m in curve:
            f.write(f"{t:.6f},{m:.9g}\n")
    with open(os.path.join(csv_dir, f"wall_pressure_{seed}.csv"), "w", encoding="utf-8") as f:
        f.write("z_low_m,z_high_m,p_h_Pa,p_h_std_Pa,samples\n")
        for row in pressure:
            f.write(f"{row[0]:.6g},{row[1]:.6g},{row[2]:.6g},{row[3]:.6g},{row[4]}\n")
    s["checks"] = [{"check": c, "ok": ok, "detail": d} for c, ok, d in checks]
    with open(os.path.join(csv_dir, f"summary_{seed}.json"), "w", encoding="utf-8") as f:
        json.dump(s, f, indent=1)
    return s


def load(paths):
    out = []
    for path in paths:
        with open(path, encoding="utf-8") as f:
            out.append(json.load(f))
    return out


def by_count(summaries):
    """{threads or ranks: [summaries]}"""
    groups = {}
    for s in summaries:
        groups.setdefault(int(s["ranks"]), []).append(s)
    return groups


def fmt_ms(values, f="{:.4f}"):
    m, sd = silo_post.mean_std(values)
    return f"{f.format(m)} ± {f.format(sd)}", m, sd


def compare(gran, ligg, title, out=sys.stdout):
    gg, lg = by_count(gran), by_count(ligg)
    pr = lambda *a: print(*a, file=out)  # noqa: E731
    pr(f"# {title}")
    pr()
    # ---- W
    pr("## Discharge rate W (kg/s), mean ± seed-to-seed sd")
    pr()
    pr("| granular threads | seeds | W granular | LIGGGHTS ranks | seeds | W LIGGGHTS | ΔW | "
       "√(s_a²+s_b²) | agree |")
    pr("|---|---|---|---|---|---|---|---|---|")
    for n in sorted(set(gg) | set(lg)):
        a, b = gg.get(n, []), lg.get(n, [])
        if not a or not b:
            continue
        ta, ma, sa = fmt_ms([s["W_kg_s"] for s in a])
        tb, mb, sb = fmt_ms([s["W_kg_s"] for s in b])
        comb = math.hypot(sa, sb)
        pr(f"| {n} | {len(a)} | {ta} | {n} | {len(b)} | {tb} | {ma - mb:+.4f} | {comb:.4f} | "
           f"{'yes' if abs(ma - mb) <= comb else 'no'} |")
    pr()
    # ---- p_h: each code's runs at its lowest count (granular's beds do not depend on threads)
    pr("## Wall pressure at rest p_h (Pa) per band, mean ± sd over the seeds")
    pr()
    na, nb = min(gg), min(lg)
    a, b = gg[na], lg[nb]
    band = a[0]["p_h_band_m"]
    nbands = max(max(len(s["p_h_Pa"]) for s in a), max(len(s["p_h_Pa"]) for s in b))

    def at(s, k):
        return s["p_h_Pa"][k] if k < len(s["p_h_Pa"]) else 0.0
    pr(f"granular: {len(a)} seeds at {na} thread(s); LIGGGHTS: {len(b)} seeds at {nb} rank(s).")
    pr()
    pr("| z_low m | z_high m | p_h granular | p_h LIGGGHTS | Δ | √(s_a²+s_b²) | agree |")
    pr("|---|---|---|---|---|---|---|")
    agree = 0
    for k in range(nbands):
        ta, ma, sa = fmt_ms([at(s, k) for s in a], "{:.1f}")
        tb, mb, sb = fmt_ms([at(s, k) for s in b], "{:.1f}")
        comb = math.hypot(sa, sb)
        ok = abs(ma - mb) <= comb
        agree += ok
        pr(f"| {k * band:.3f} | {(k + 1) * band:.3f} | {ta} | {tb} | {ma - mb:+.1f} | {comb:.1f} | "
           f"{'yes' if ok else 'no'} |")
    pr()
    pr(f"bands within the combined scatter: {agree} of {nbands} ({agree / nbands:.0%})")
    pr()
    for name, group in (("granular", a), ("LIGGGHTS", b)):
        sup, _, _ = fmt_ms([s["support_N"] / s["weight_N"] for s in group])
        cyl, _, _ = fmt_ms([s["support_cylinder_N"] / s["weight_N"] for s in group])
        top, _, _ = fmt_ms([s["bed_top_m"] for s in group], "{:.3f}")
        ts, _, _ = fmt_ms([s["t_settled_s"] for s in group], "{:.3f}")
        sp, _, _ = fmt_ms([s["sqrt_overlap_pair"] for s in group], "{:.5f}")
        sw, _, _ = fmt_ms([s["sqrt_overlap_wall"] for s in group], "{:.5f}")
        pr(f"- {name}: settled at t = {ts} s, bed top {top} m, wall support / weight {sup}, "
           f"the cylinder's share {cyl}; mean √h: pairs {sp}, walls {sw} m^½")
    pr()
    # ---- Speed
    pr("## Speed: particle-steps per second (mean ± sd over the seeds)")
    pr()
    pr("Whole run: Σ steps × particles over the summed loop time (granular: the stages' "
       "wall-clock, its rest snapshots included; LIGGGHTS: its Loop times, its rest dumps "
       "included). Fill + settle: the "
       "same over the fill-and-settle phase alone (no snapshots of the full bed in either).")
    pr()
    pr("| threads / ranks | granular whole run | LIGGGHTS whole run | ratio | granular fill+settle "
       "| LIGGGHTS fill+settle | ratio | granular wall s | LIGGGHTS wall s |")
    pr("|---|---|---|---|---|---|---|---|---|")
    for n in sorted(set(gg) & set(lg)):
        a, b = gg[n], lg[n]
        ta, ma, _ = fmt_ms([s["timing"]["particle_steps_per_s"] for s in a], "{:.3g}")
        tb, mb, _ = fmt_ms([s["timing"]["particle_steps_per_s"] for s in b], "{:.3g}")
        fa, fma, _ = fmt_ms([s["timing"]["fill_settle_particle_steps_per_s"] for s in a], "{:.3g}")
        fb, fmb, _ = fmt_ms([s["timing"]["fill_settle_particle_steps_per_s"] for s in b], "{:.3g}")
        wa, _, _ = fmt_ms([s["timing"]["wall_s"] for s in a], "{:.1f}")
        wb, _, _ = fmt_ms([s["timing"]["wall_s"] for s in b], "{:.1f}")
        pr(f"| {n} | {ta} | {tb} | {ma / mb:.2f} | {fa} | {fb} | {fma / fmb:.2f} | {wa} | {wb} |")
    pr()
    fails = [(s.get("code", "liggghts"), s["ranks"], s["seed"], c["check"])
             for s in gran + ligg for c in s["checks"] if not c["ok"]]
    pr("checks failed: " + (", ".join(f"{c} {n} seed {sd}: {ch}" for c, n, sd, ch in fails)
                            if fails else "none"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    a = sub.add_parser("run")
    a.add_argument("rundir")
    a.add_argument("--csv-dir")
    a.add_argument("--wall-seconds", type=float)
    a.add_argument("--cpu-seconds", type=float)
    c = sub.add_parser("compare")
    c.add_argument("--granular", nargs="+", required=True)
    c.add_argument("--liggghts", nargs="+", required=True)
    c.add_argument("--title", default="granular against LIGGGHTS: silo discharge")
    args = ap.parse_args()
    if args.cmd == "run":
        s = process_run(args.rundir, args.csv_dir or args.rundir, args.wall_seconds,
                        args.cpu_seconds)
        silo_post.print_run(s)
    else:
        compare(load(args.granular), load(args.liggghts), args.title)


if __name__ == "__main__":
    main()
