#!/usr/bin/python3
"""Post-processing of the LIGGGHTS silo runs (standard library only).

    silo_post.py run RUNDIR [--csv-dir DIR] [--wall-seconds S]
    silo_post.py table SUMMARY.json ... [--markdown FILE]
    silo_post.py profile WALL_PRESSURE.csv ...

`run` reads one run's folder (silo.liggghts's outputs and run.json) and writes, into --csv-dir
(default RUNDIR):
  discharge_<seed>.csv      time_s (from the gate opening), discharged_mass_kg
  wall_pressure_<seed>.csv  z_low_m, z_high_m, p_h_Pa (mean over the rest snapshots),
                            p_h_std_Pa (their standard deviation), samples
  summary_<seed>.json       the fitted rate W, the checks, the timings, the bed's mean sqrt(h)
and prints the checks. `table` prints one row per summary and the mean +- standard deviation
over them (the driver's table). `profile` prints the wall-pressure bands' mean +- standard
deviation over several runs' CSVs (seeds).

Definitions:
  discharged mass(t) = M(open) - sum of the masses whose centre is above z = 0 at t;
  W = least-squares slope of discharged mass against time over the samples whose discharged
      mass lies within [fit_low, fit_high] x its final value;
  p_h of a band [z_lo, z_hi) = sum over the cylinder's contacts (mesh 0) of particles whose
      centre lies in the band of the outward radial push -(F . r_hat) of the particle on the
      wall, divided by 2 pi R (z_hi - z_lo); F is the wall's force on the particle;
  particle-steps = sum over LIGGGHTS's runs (chunks of 0.01-0.05 s) of steps x atoms at the
      chunk's end; speeds divide them by the summed "Loop time" (set-up of the chunks excluded).
"""
import argparse
import json
import math
import os
import re
import statistics
import sys

LOOP = re.compile(r"^Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")
PHASE = re.compile(r"^PHASE (\w+) (.*)$")


def fields(text):
    """'step 12 time 0.5 atoms 3' -> {'step': 12.0, ...}"""
    words = text.split()
    out = {}
    for k, v in zip(words[0::2], words[1::2]):
        try:
            out[k] = float(v)
        except ValueError:
            out[k] = v
    return out


def read_log(path):
    """PHASE markers (name -> fields) and, per phase, the Loop lines as (seconds, steps, atoms)."""
    phases, loops = {}, {}
    current = None
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            m = PHASE.match(line)
            if m:
                current = m.group(1)
                phases[current] = fields(m.group(2))
                loops.setdefault(current, [])
                continue
            m = LOOP.match(line)
            if m and current is not None:
                loops[current].append((float(m.group(1)), int(m.group(3)), int(m.group(4)),
                                       int(m.group(2))))
    return phases, loops


def read_series(path):
    rows = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            rows.append([float(x) for x in line.split()])
    return rows


def read_dump(path):
    """LAMMPS dump (custom or local): list of (timestep, rows)."""
    snaps = []
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: TIMESTEP"):
            step = int(lines[i + 1])
            count = int(lines[i + 3])
            j = i + 4
            while not lines[j].startswith("ITEM: ATOMS") and not lines[j].startswith(
                    "ITEM: ENTRIES"):
                j += 1
            rows = [[float(x) for x in lines[j + 1 + k].split()] for k in range(count)]
            snaps.append((step, rows))
            i = j + 1 + count
        else:
            i += 1
    return snaps


def least_squares(xs, ys):
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    sxy = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
    slope = sxy / sxx
    intercept = my - slope * mx
    ss_res = sum((y - intercept - slope * x) ** 2 for x, y in zip(xs, ys))
    ss_tot = sum((y - my) ** 2 for y in ys)
    return slope, intercept, 1.0 - ss_res / ss_tot if ss_tot > 0 else 1.0


def mean_std(values):
    values = [v for v in values if v is not None and not (isinstance(v, float) and math.isnan(v))]
    if not values:
        return float("nan"), float("nan")
    return statistics.fmean(values), (statistics.stdev(values) if len(values) > 1 else 0.0)


def process_run(rundir, csv_dir, wall_seconds=None, cpu_seconds=None):
    with open(os.path.join(rundir, "run.json"), encoding="utf-8") as f:
        r = json.load(f)
    p = r["params"]
    seed = r["seed"]
    g = r["gravity"]
    checks = []  # (name, ok, text)
    phases, loops = read_log(os.path.join(rundir, "log.liggghts"))
    for name in ("fill", "settled", "rest", "open", "end"):
        if name not in phases:
            raise SystemExit(f"silo_post.py: {rundir}: log has no PHASE {name} (run failed?)")
    s = {"seed": seed, "ranks": r["ranks"], "n_requested": r["n_particles"],
         "d0_m": r["d0_m"], "d0_ratio": r["d0_ratio"], "quick": r["quick"]}

    # ---- Fill: the held mass against N x the mean particle mass.
    settled = phases["settled"]
    n_in = int(settled["inserted"])
    mass = settled["mass"]
    classes = r["radius_classes"]
    rho = p["density"]
    class_masses = [rho * 4.0 / 3.0 * math.pi * rk ** 3 for rk in classes]
    m_discrete = statistics.fmean(class_masses)
    sd_discrete = statistics.pstdev(class_masses)
    m_cont = r["mean_particle_mass"]
    expected = n_in * m_cont
    sigma = math.sqrt(n_in) * sd_discrete  # spread of a sum of n_in random picks
    z = (mass - n_in * m_discrete) / sigma if sigma > 0 else 0.0
    s.update({"inserted": n_in, "t_settled_s": settled["time"], "mass_kg": mass,
              "mass_expected_kg": expected, "mass_expected_discrete_kg": n_in * m_discrete,
              "mass_sigma_kg": sigma, "ke_settled_J": settled["ke"],
              "settle_capped": settled["time"] >= r["t_settle_cap"] - 1e-9})
    checks.append(("all particles inserted", n_in == r["n_particles"],
                   f"{n_in} of {r['n_particles']}"))
    checks.append(("held mass = N x mean mass", abs(z) < 4.0,
                   f"{mass:.6g} kg; N <m> = {expected:.6g} kg (continuous), "
                   f"{n_in * m_discrete:.6g} kg (the {len(classes)} classes), "
                   f"{(mass / expected - 1) * 100:+.3f} %, {z:+.2f} sigma of the random radii"))
    checks.append(("inserted mass = held mass", abs(settled["mass_inserted"] - mass) < 1e-9 * mass,
                   f"fix insert says {settled['mass_inserted']:.9g} kg"))
    checks.append(("settled below the KE threshold", not s["settle_capped"],
                   f"KE {settled['ke']:.3g} J, threshold {r['ke_stop']:.3g} J, at t = "
                   f"{settled['time']:.3f} s (cap {r['t_settle_cap']:.3f} s)"))

    # ---- Rest: reactions and the wall pressure.
    rest_step = int(phases["rest"]["step"])
    open_step = int(phases["open"]["step"])
    walls = [(st, rows) for st, rows in read_dump(os.path.join(rundir, "rest_walls.dump"))
             if rest_step < st <= open_step]
    weight = mass * g
    support = []  # vertical force of all walls on the particles, per snapshot
    per_mesh = []
    big_r = r["silo_radius"]
    band = p["pressure_band"]
    top = max(row[6] + row[2] for row in
              read_dump(os.path.join(rundir, "rest_atoms.dump"))[-1][1])
    nbands = int(math.ceil(min(top, r["silo_height"]) / band))
    band_samples = [[] for _ in range(nbands)]
    for st, rows in walls:
        fz = [0.0, 0.0, 0.0]
        push = [0.0] * nbands
        for row in rows:
            # c_wl: contact point (3), particle centre (3), mesh, triangle, atom, force (3), delta
            mesh = int(row[6])
            fz[mesh] += row[11]
            if mesh == 0:
                x, y, zc = row[3], row[4], row[5]
                rho_c = math.hypot(x, y)
                outward = -(row[9] * x + row[10] * y) / rho_c
                k = int(zc // band)
                if 0 <= k < nbands:
                    push[k] += outward
        support.append(sum(fz))
        per_mesh.append(fz)
        for k in range(nbands):
            band_samples[k].append(push[k] / (2.0 * math.pi * big_r * band))
    series = read_series(os.path.join(rundir, "series_fill.txt"))
    rest_rows = [row for row in series if rest_step < row[1] <= open_step]
    # mesh/surface/stress: force of the particles on each mesh (cylinder z, floor z, gate z)
    stress_support = [-(row[8] + row[9] + row[10]) for row in rest_rows]
    sup_mean, sup_std = mean_std(support)
    st_mean, _ = mean_std(stress_support)
    mesh_means = [statistics.fmean(m[i] for m in per_mesh) for i in range(3)]
    s.update({"weight_N": weight, "support_N": sup_mean, "support_std_N": sup_std,
              "support_stress_N": st_mean, "support_cylinder_N": mesh_means[0],
              "support_floor_N": mesh_means[1], "support_gate_N": mesh_means[2],
              "rest_samples": len(walls), "bed_top_m": top,
              # the height N particles fill at a solid fraction of 0.6 (the table's band picks)
              "bed_height_nominal_m": r["n_particles"] * m_cont / (rho * 0.6 * math.pi * big_r ** 2)})
    checks.append(("wall reactions carry the weight (2 %)",
                   abs(sup_mean / weight - 1) < 0.02,
                   f"sum of vertical wall forces {sup_mean:.5g} N (contacts), {st_mean:.5g} N "
                   f"(mesh/surface/stress), weight {weight:.5g} N: "
                   f"{(sup_mean / weight - 1) * 100:+.3f} %; cylinder {mesh_means[0]:.4g} N, floor "
                   f"{mesh_means[1]:.4g} N, gate {mesh_means[2]:.4g} N"))
    checks.append(("rest snapshots", len(walls) == r["rest_samples"],
                   f"{len(walls)} of {r['rest_samples']}"))
    pressure = []
    for k in range(nbands):
        m_, sd = mean_std(band_samples[k])
        pressure.append((k * band, min((k + 1) * band, r["silo_height"]), m_, sd,
                         len(band_samples[k])))
    s["p_h_Pa"] = [row[2] for row in pressure]
    s["p_h_band_m"] = band

    # ---- The bed's mean sqrt(h) (LIGGGHTS's constant k_t is taken at it).
    pairs = read_dump(os.path.join(rundir, "rest_pairs.dump"))[-1][1]
    roots_p = [math.sqrt(row[3]) for row in pairs if row[3] > 0]
    roots_w = [math.sqrt(row[12]) for row in walls[-1][1] if row[12] > 0]
    s["sqrt_overlap_pair"] = statistics.fmean(roots_p) if roots_p else float("nan")
    s["sqrt_overlap_wall"] = statistics.fmean(roots_w) if roots_w else float("nan")
    s["contacts_pair"] = len(roots_p)
    s["contacts_wall"] = len(roots_w)

    # ---- Discharge.
    dis = read_series(os.path.join(rundir, "series_discharge.txt"))
    t_open = phases["open"]["time"]
    m_open = phases["open"]["mass"]
    above_open = next((row[5] for row in reversed(series) if row[1] <= open_step), m_open)
    curve = [(0.0, 0.0)] + [(row[0] - t_open, above_open - row[5]) for row in dis]
    final = curve[-1][1]
    lo, hi = p["fit_low"] * final, p["fit_high"] * final
    window = [(t, m) for t, m in curve if lo <= m <= hi]
    if len(window) >= 3 and final > 0:
        w, b, r2 = least_squares([t for t, _ in window], [m for _, m in window])
        worst = max(abs(m - (b + w * t)) for t, m in window) / final
    else:
        w = b = r2 = worst = float("nan")
    drops = [curve[i][1] - curve[i + 1][1] for i in range(len(curve) - 1)]
    worst_drop = max([0.0] + drops)
    s.update({"t_open_s": t_open, "discharge_s": curve[-1][0], "discharged_kg": final,
              "W_kg_s": w, "fit_intercept_kg": b, "fit_r2": r2,
              "fit_window_s": [window[0][0], window[-1][0]] if window else None,
              "fit_worst_residual_frac": worst, "largest_decrease_kg": worst_drop,
              "mass_in_silo_at_open_kg": above_open})
    checks.append(("discharged mass monotone", worst_drop <= 1e-3 * max(final, 1e-12),
                   f"largest decrease between samples {worst_drop:.3g} kg "
                   f"(a particle's mass is about {m_cont:.3g} kg)"))
    checks.append(("roughly linear between 20 and 80 %", r2 > 0.99,
                   f"R^2 = {r2:.5f}, largest residual {worst * 100:.2f} % of the final mass"))

    # ---- Timings.
    def total(names):
        secs = sum(l[0] for n in names for l in loops.get(n, []))
        psteps = sum(l[1] * l[2] for n in names for l in loops.get(n, []))
        steps = sum(l[1] for n in names for l in loops.get(n, []))
        return secs, psteps, steps
    fill_s, fill_ps, fill_n = total(["fill"])
    rest_s, rest_ps, rest_n = total(["rest", "settled"])
    dis_s, dis_ps, dis_n = total(["open"])
    all_s, all_ps, all_n = total(["fill", "settled", "rest", "open"])
    # the fixed-count part: the fill phase's chunks after the last insertion, and the rest
    after = []
    step_at = 0
    for l in loops.get("fill", []):
        step_at += l[1]
        if step_at * r["dt"] > r["t_insert_end"] + 1e-9:
            after.append(l)
    after += loops.get("rest", [])
    fixed_s = sum(l[0] for l in after)
    fixed_ps = sum(l[1] * l[2] for l in after)
    procs = {l[3] for ls in loops.values() for l in ls}
    s["timing"] = {
        "procs": sorted(procs), "fill_settle_loop_s": fill_s, "fill_settle_steps": fill_n,
        "fill_settle_particle_steps": fill_ps,
        "fill_settle_particle_steps_per_s": fill_ps / fill_s if fill_s > 0 else float("nan"),
        "rest_loop_s": rest_s, "discharge_loop_s": dis_s, "discharge_steps": dis_n,
        "discharge_particle_steps": dis_ps, "total_loop_s": all_s, "total_steps": all_n,
        "total_particle_steps": all_ps,
        "particle_steps_per_s": all_ps / all_s if all_s > 0 else float("nan"),
        "settle_particle_steps_per_s": fixed_ps / fixed_s if fixed_s > 0 else float("nan"),
        "discharge_particle_steps_per_s": dis_ps / dis_s if dis_s > 0 else float("nan"),
        "wall_s": wall_seconds, "cpu_s": cpu_seconds}

    # ---- Files.
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


def print_run(s, out=sys.stdout):
    t = s["timing"]
    print(f"seed {s['seed']} ({s['ranks']} rank(s)), D0 = {s['d0_m']:.4g} m:", file=out)
    for c in s["checks"]:
        print(f"  [{'ok' if c['ok'] else 'FAIL'}] {c['check']}: {c['detail']}", file=out)
    print(f"  W = {s['W_kg_s']:.4g} kg/s over {s['fit_window_s']} s; discharged "
          f"{s['discharged_kg']:.4g} kg in {s['discharge_s']:.3f} s", file=out)
    print(f"  p_h by band of {s['p_h_band_m']} m from the floor [Pa]: "
          + " ".join(f"{v:.0f}" for v in s["p_h_Pa"]), file=out)
    print(f"  bed mean sqrt(h): pairs {s['sqrt_overlap_pair']:.5f} ({s['contacts_pair']} "
          f"contacts), walls {s['sqrt_overlap_wall']:.5f} ({s['contacts_wall']}) m^0.5", file=out)
    print(f"  loop s: fill+settle {t['fill_settle_loop_s']:.1f}, discharge "
          f"{t['discharge_loop_s']:.1f}, all {t['total_loop_s']:.1f}; wall "
          f"{t['wall_s'] if t['wall_s'] is not None else float('nan'):.1f} s; particle-steps/s "
          f"{t['particle_steps_per_s']:.3g} (settled bed {t['settle_particle_steps_per_s']:.3g})",
          file=out)


def band_picks(summaries):
    """Band indices to show: at 10 %, 35 %, 60 % and 85 % of the nominal bed height (N particles
    at a solid fraction of 0.6), the same for every run of the same N."""
    top = min(s.get("bed_height_nominal_m", s["bed_top_m"]) for s in summaries)
    band = summaries[0]["p_h_band_m"]
    n = min(len(s["p_h_Pa"]) for s in summaries)
    picks = []
    for f in (0.1, 0.35, 0.6, 0.85):
        k = min(n - 1, int(f * top / band))
        if k not in picks:
            picks.append(k)
    return picks, band


def table(summaries, out=sys.stdout):
    picks, band = band_picks(summaries)
    heads = (["seed", "ranks", "inserted", "fill+settle s (sim)", "W kg/s"]
             + [f"p_h {k * band:.3f}-{(k + 1) * band:.3f} m Pa" for k in picks]
             + ["support/weight", "wall s", "cpu s", "loop s", "discharge loop s", "particle-steps/s",
                "settled-bed particle-steps/s"])
    rows = []
    for s in summaries:
        t = s["timing"]
        rows.append([s["seed"], s["ranks"], s["inserted"], s["t_settled_s"], s["W_kg_s"]]
                    + [s["p_h_Pa"][k] for k in picks]
                    + [s["support_N"] / s["weight_N"],
                       t["wall_s"] if t["wall_s"] is not None else float("nan"),
                       t.get("cpu_s") if t.get("cpu_s") is not None else float("nan"),
                       t["total_loop_s"], t["discharge_loop_s"], t["particle_steps_per_s"],
                       t["settle_particle_steps_per_s"]])
    fmt = (["{:d}", "{:d}", "{:d}", "{:.3f}", "{:.4f}"] + ["{:.1f}"] * len(picks)
           + ["{:.4f}", "{:.1f}", "{:.1f}", "{:.1f}", "{:.1f}", "{:.3g}", "{:.3g}"])
    print("| " + " | ".join(heads) + " |", file=out)
    print("|" + "---|" * len(heads), file=out)
    for row in rows:
        print("| " + " | ".join(f.format(v) for f, v in zip(fmt, row)) + " |", file=out)
    if len(rows) > 1:
        cells = ["mean ± sd", "", ""]
        for col in range(3, len(heads)):
            m, sd = mean_std([row[col] for row in rows])
            f = fmt[col]
            cells.append(f"{f.format(m)} ± {f.format(sd)}")
        print("| " + " | ".join(cells) + " |", file=out)
    fails = [(s["seed"], c["check"]) for s in summaries for c in s["checks"] if not c["ok"]]
    print("", file=out)
    print("checks failed: " + (", ".join(f"seed {a}: {b}" for a, b in fails) if fails
                               else "none"), file=out)


def profile(paths, out=sys.stdout):
    runs = []
    for path in paths:
        with open(path, encoding="utf-8") as f:
            next(f)
            runs.append([[float(x) for x in line.split(",")] for line in f if line.strip()])
    n = min(len(r) for r in runs)
    print("| z_low_m | z_high_m | p_h_Pa mean ± sd over runs | runs |", file=out)
    print("|---|---|---|---|", file=out)
    for k in range(n):
        m, sd = mean_std([r[k][2] for r in runs])
        print(f"| {runs[0][k][0]:.3f} | {runs[0][k][1]:.3f} | {m:.1f} ± {sd:.1f} | {len(runs)} |",
              file=out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    a = sub.add_parser("run")
    a.add_argument("rundir")
    a.add_argument("--csv-dir")
    a.add_argument("--wall-seconds", type=float, help="the whole process's wall time")
    a.add_argument("--cpu-seconds", type=float, help="its user + system time (all ranks)")
    b = sub.add_parser("table")
    b.add_argument("summaries", nargs="+")
    b.add_argument("--markdown")
    c = sub.add_parser("profile")
    c.add_argument("csvs", nargs="+")
    args = ap.parse_args()
    if args.cmd == "profile":
        profile(args.csvs)
        return
    if args.cmd == "run":
        s = process_run(args.rundir, args.csv_dir or args.rundir, args.wall_seconds,
                        args.cpu_seconds)
        print_run(s)
    else:
        summaries = []
        for path in args.summaries:
            with open(path, encoding="utf-8") as f:
                summaries.append(json.load(f))
        summaries.sort(key=lambda s: (s["ranks"], s["seed"]))
        table(summaries)
        if args.markdown:
            with open(args.markdown, "w", encoding="utf-8") as f:
                table(summaries, f)


if __name__ == "__main__":
    main()
