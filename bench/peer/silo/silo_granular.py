#!/usr/bin/python3
"""Writes one silo run's granular scene (TOML) from silo.params and a seed (standard library only).

    silo_granular.py --out RUNDIR --mesh-dir MESHDIR [--seed S] [--d0 RATIO] [--quick]
                     [--threads N] [--params silo.params] [--set key=value ...]

RUNDIR/silo.toml   the scene for `granular run` (keys: docs/scenes.md)
RUNDIR/run.json    every number of the run, for silo_granular_post.py

The walls are the STL files of silo_mesh.py (cylinder, floor and gate of the orifice) as
`shape = "mesh"` walls named cylinder, floor and gate. Stages:

  fill       inserts N particles into the cylinder r <= insert_radius, insert_z_min <= z <=
             insert_z_max, at insert_rate, one exchange every insert_every (so the batches are
             LIGGGHTS's: insert_rate x insert_every particles at a time), velocity
             (0, 0, insert_velocity_z), radii uniform in [radius_min, radius_max]; ends once the
             kinetic energy has stayed below settle_ke N/720 for settle_sustain after the last
             insertion, or at the cap (settle_cap after the last insertion)
  rest       rest_time with the gate closed; every rest_time/rest_samples a snapshot writes every
             contact (contacts_rest_<step>.csv: wall name, point, forces) and every particle
  discharge  the gate removed (remove_walls); an outlet removes the particles whose centre is
             below delete_below_z every sample_interval, for the LIGGGHTS run's discharge time
             (whole deletion intervals of delete_every)

The rest stage lists its own snapshot times (docs/scenes.md), so the fill and the discharge
write none, as LIGGGHTS dumps the rest alone. The fixed step is `dt`, the integrator velocity Verlet, the skin `skin`.
"""
import argparse
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import silo_params  # noqa: E402
import silo_setup  # noqa: E402


def num(x):
    """A TOML float that reads back to the same double."""
    return repr(float(x))


def vec(values):
    return "[" + ", ".join(num(v) for v in values) + "]"


def derive(p, seed, ratio, quick, threads, mesh_dir):
    """The LIGGGHTS run's numbers (silo_setup.derive) and granular's own."""
    r = silo_setup.derive(p, seed, ratio, quick, 1, mesh_dir)
    del r["ranks"], r["seed_insert"], r["seed_distribution"], r["wall_type"], r["ntypes"]
    del r["radius_classes"], r["gate_drop"], r["gate_vz"]
    dt = p["dt"]
    n = r["n_particles"]
    per_exchange = p["insert_rate"] * p["insert_every"]
    exchanges = int(math.ceil(n / per_exchange - 1e-9))
    t_insert_end = exchanges * p["insert_every"]  # the exchange that inserts the last ones
    r.update({
        "code": "granular", "threads": threads, "seed": seed,
        "insert_exchange_s": p["insert_every"], "t_insert_end": t_insert_end,
        "t_settle_cap": t_insert_end + p["settle_cap"],
        "fill_max_time": t_insert_end + p["settle_cap"],
        "rest_time": p["rest_time"],
        "rest_snapshots": [p["rest_time"] * k / int(p["rest_samples"])
                           for k in range(1, int(p["rest_samples"]) + 1)],
        # LIGGGHTS runs whole deletion intervals: the same discharge time here
        "discharge_time": r["discharge_steps"] * dt,
        "outlet_exchange_s": p["sample_interval"],
        "box": [-(p["silo_radius"] + 0.02), -(p["silo_radius"] + 0.02),
                p["delete_below_z"] - 0.1,
                p["silo_radius"] + 0.02, p["silo_radius"] + 0.02, p["silo_height"] + 0.05],
    })
    return r


def scene(p, r):
    if p["normal_law"] not in ("hooke", "hertz"):
        raise ValueError("normal_law must be hooke or hertz")
    if p["tangential_law"] not in ("mindlin", "constant"):
        raise ValueError("tangential_law must be mindlin or constant")
    box = r["box"]
    lines = [
        f"# The silo discharge benchmark (bench/peer/silo/README.md), granular's side: seed "
        f"{r['seed']}, D0 = {r['d0_ratio']:g} d = {r['d0_m']:.6g} m, N = {r['n_particles']}.",
        "# Written by silo_granular.py from silo.params; keys: docs/scenes.md.",
        "",
        "[material]",
        f"youngs_modulus = {num(p['youngs_modulus'])}",
        f"poisson_ratio = {num(p['poisson_ratio'])}",
        f"shear_modulus = {num(p['shear_modulus'])}",
        f"density = {num(p['density'])}",
        f"friction = {num(p['friction'])}",
        f"normal_damping = {num(p['normal_damping'])}",
        f"tangential_damping = {num(p['tangential_damping'])}",
        f"normal_law = \"{p['normal_law']}\"",
        f"tangential_law = \"{p['tangential_law']}\"",
    ]
    if p["tangential_law"] == "constant":
        lines.append(f"tangential_stiffness = {num(p['tangential_stiffness'])}")
    lines += [
        "",
        "[simulation]",
        "integrator = \"verlet\"",
        f"time_step = {num(p['dt'])}",
        f"skin = {num(p['skin'])}",
        f"gravity = {vec([0.0, 0.0, -p['gravity']])}",
        "",
        "[box]                      # no face is a wall: the meshes hold the bed",
        f"min = {vec(box[:3])}",
        f"max = {vec(box[3:])}",
        "walls = []",
    ]
    for name, path in (("cylinder", r["cylinder_stl"]), ("floor", r["floor_stl"]),
                       ("gate", r["gate_stl"])):
        lines += ["", "[[walls]]", f"name = \"{name}\"", "shape = \"mesh\"",
                  f"file = \"{path}\""]
    zlo, zhi = p["insert_z_min"], p["insert_z_max"]
    lines += [
        "",
        "[[stages]]",
        "name = \"fill\"",
        f"max_time = {num(r['fill_max_time'])}",
        f"kinetic_energy_below = {num(r['ke_stop'])}",
        f"sustain_time = {num(p['settle_sustain'])}",
        f"exchange_interval = {num(r['insert_exchange_s'])}",
        "",
        "[[stages.inserts]]",
        "name = \"pour\"",
        "shape = \"cylinder\"",
        f"base = {vec([0.0, 0.0, zlo])}",
        "axis = [0, 0, 1]",
        f"length = {num(zhi - zlo)}",
        f"radius = {num(p['insert_radius'])}",
        f"count = {r['n_particles']}",
        f"rate = {num(p['insert_rate'])}",
        f"radius_min = {num(p['radius_min'])}",
        f"radius_max = {num(p['radius_max'])}",
        f"velocity = {vec([0.0, 0.0, p['insert_velocity_z']])}",
        f"seed = {r['seed']}",
        "",
        "[[stages]]",
        "name = \"rest\"",
        f"max_time = {num(r['rest_time'])}",
        f"snapshots = {vec(r['rest_snapshots'])}",
        "",
        "[[stages]]",
        "name = \"discharge\"",
        f"max_time = {num(r['discharge_time'])}",
        "remove_walls = [\"gate\"]",
        f"exchange_interval = {num(r['outlet_exchange_s'])}",
        "",
        "[[stages.outlets]]",
        "name = \"below\"",
        f"min = {vec(box[:3])}",
        f"max = {vec([box[3], box[4], p['delete_below_z']])}",
        "",
        "[output]",
        f"interval = {num(p['sample_interval'])}",
        "",
    ]
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, help="the run's folder")
    ap.add_argument("--mesh-dir", required=True, help="silo_mesh.py's folder")
    ap.add_argument("--seed", type=int, default=None)
    ap.add_argument("--d0", type=float, default=None, help="D0/d (default: the first of "
                    "orifice_diameters)")
    ap.add_argument("--quick", action="store_true", help="quick_n_particles")
    ap.add_argument("--threads", type=int, default=1, help="recorded in run.json (the driver "
                    "sets OMP_NUM_THREADS)")
    ap.add_argument("--params", default=silo_params.DEFAULT)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = ap.parse_args()
    p = silo_params.read(args.params, args.set)
    seed = int(p["seed"]) if args.seed is None else args.seed
    ratio = args.d0 if args.d0 is not None else silo_params.as_list(p["orifice_diameters"])[0]
    r = derive(p, seed, ratio, args.quick, args.threads, args.mesh_dir)
    for key in ("cylinder_stl", "floor_stl", "gate_stl"):
        if not os.path.isfile(r[key]):
            raise SystemExit(f"silo_granular.py: {r[key]} missing (run silo_mesh.py --out "
                             f"{args.mesh_dir} first)")
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "silo.toml"), "w", encoding="utf-8") as f:
        f.write(scene(p, r))
    r["params"] = p
    with open(os.path.join(args.out, "run.json"), "w", encoding="utf-8") as f:
        json.dump(r, f, indent=1)


if __name__ == "__main__":
    main()
