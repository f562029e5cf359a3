#!/usr/bin/python3
"""Writes the run-specific LIGGGHTS include files of one silo run (bench/peer/silo/silo.liggghts).

    silo_setup.py --out RUNDIR --mesh-dir MESHDIR [--seed S] [--d0 RATIO] [--quick]
                  [--ranks N] [--params silo.params] [--set key=value ...]

RUNDIR/vars.liggghts   every number of the run as a LIGGGHTS variable (geometry, fill, settle,
                       discharge, step counts, seeds, STL paths)
RUNDIR/model.liggghts  the contact law per type pair (fix property/global: kn, kt, gamman,
                       gammat, coefficientFriction), the particle templates (one atom type per
                       radius class) and their distribution
RUNDIR/run.json        the same numbers for silo_post.py

The law (docs/physics.md §1; bench/peer/README.md for the mapping this follows):
  k_n = (2/3) E/(1-nu^2) R_ij, R_ij = R_i R_j/(R_i + R_j), a wall: R_ij = R_i (type pair exact:
        every radius class is one atom type with one radius);
  k_t = (8/3) G/(2-nu) sqrt(R_ij) <sqrt(h)> (LIGGGHTS's k_t is constant per type pair; ours is
        (8/3) G/(2-nu) sqrt(R_ij h)), or tangential_stiffness with tangential_law = constant;
  dashpots gamma_n m_ij dh/dt and gamma_t m_ij v_t (absolute_damping off: LIGGGHTS multiplies
        gamman, gammat by m_eff = m_i m_j/(m_i + m_j), m_i at a wall), friction mu.
LIGGGHTS seeds must be primes above 10000: seed S maps to the first primes at or above
100000 + 1000 S (insertion), 200000 + 1000 S (distribution), 300000 + 1000 S (the
templates: the next ones).
"""
import argparse
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import silo_params  # noqa: E402


def is_prime(n):
    if n < 2:
        return False
    if n % 2 == 0:
        return n == 2
    k = 3
    while k * k <= n:
        if n % k == 0:
            return False
        k += 2
    return True


def prime_at_least(n):
    while not is_prime(n):
        n += 1
    return n


def per_type_pair(fix_id, name, n, value):
    lines = [f"fix {fix_id} all property/global {name} peratomtypepair {n} &"]
    rows = []
    for a in range(1, n + 1):
        rows.append("  " + " ".join("%.17g" % value(a, b) for b in range(1, n + 1)))
    lines.append(" &\n".join(rows))
    return "\n".join(lines) + "\n"


def derive(p, seed, ratio, quick, ranks, mesh_dir):
    """Every number of one run."""
    dt = p["dt"]
    n = int(p["quick_n_particles"] if quick else p["n_particles"])
    d0 = silo_params.orifice_diameter(p, ratio)
    mm = silo_params.orifice_mm(d0)
    insert_every = silo_params.steps(p, p["insert_every"])
    per_event = p["insert_rate"] * insert_every * dt
    events = int(math.ceil(n / per_event - 1e-9))
    t_ins_end = events * insert_every * dt  # the last event is at or before this
    check = silo_params.steps(p, p["check_interval"])
    sample = silo_params.steps(p, p["sample_interval"])
    rest_every = silo_params.steps(p, p["rest_time"] / p["rest_samples"])
    delete_steps = silo_params.steps(p, p["delete_every"])
    discharge_steps = silo_params.steps(p, p["discharge_time"])
    delete_chunks = int(math.ceil(discharge_steps / delete_steps))
    big_r, height = p["silo_radius"], p["silo_height"]
    classes = silo_params.radius_classes(p)
    return {
        "seed": seed, "ranks": ranks, "quick": quick, "d0_ratio": ratio, "d0_m": d0,
        "d0_mm": mm, "n_particles": n, "dt": dt, "skin": p["skin"], "gravity": p["gravity"],
        "silo_radius": big_r, "silo_height": height,
        "box": [-(big_r + 0.02), big_r + 0.02, -(big_r + 0.02), big_r + 0.02,
                p["delete_below_z"] - 0.5, height + 0.05],
        # the gate drops to delete_z - 0.3 during the first deletion interval
        "gate_drop": 0.3 - p["delete_below_z"],
        "gate_vz": -(0.3 - p["delete_below_z"]) / (delete_steps * dt),
        "insert_radius": p["insert_radius"], "insert_z_min": p["insert_z_min"],
        "insert_z_max": p["insert_z_max"], "insert_rate": p["insert_rate"],
        "insert_every_steps": insert_every, "insert_velocity_z": p["insert_velocity_z"],
        "insert_events": events, "t_insert_end": t_ins_end,
        "t_settle_cap": t_ins_end + p["settle_cap"],
        "ke_stop": p["settle_ke"] * n / 720.0,
        "calm_checks": max(1, int(math.ceil(p["settle_sustain"] / (check * dt) - 1e-9))),
        "check_steps": check, "sample_steps": sample, "rest_every_steps": rest_every,
        "rest_samples": int(p["rest_samples"]), "rest_steps": rest_every * int(p["rest_samples"]),
        "delete_z": p["delete_below_z"], "delete_steps": delete_steps,
        "delete_chunks": delete_chunks, "discharge_steps": delete_chunks * delete_steps,
        "radius_classes": classes, "wall_type": len(classes) + 1, "ntypes": len(classes) + 1,
        "mean_particle_mass": silo_params.mean_particle_mass(p),
        "seed_insert": prime_at_least(100000 + 1000 * seed),
        "seed_distribution": prime_at_least(200000 + 1000 * seed),
        "cylinder_stl": os.path.abspath(os.path.join(mesh_dir, "cylinder.stl")),
        "floor_stl": os.path.abspath(os.path.join(mesh_dir, f"floor_D0_{mm}.stl")),
        "gate_stl": os.path.abspath(os.path.join(mesh_dir, f"gate_D0_{mm}.stl")),
    }


def write_vars(r, path):
    keys = ["dt", "skin", "gravity", "silo_radius", "silo_height", "insert_radius",
            "insert_z_min", "insert_z_max", "insert_rate", "insert_every_steps",
            "insert_velocity_z", "n_particles", "t_insert_end", "t_settle_cap", "ke_stop",
            "calm_checks", "check_steps", "sample_steps", "rest_every_steps", "rest_steps",
            "delete_z", "delete_steps", "delete_chunks", "gate_vz", "wall_type", "ntypes",
            "seed_insert", "ranks"]
    with open(path, "w", encoding="utf-8") as f:
        f.write("# Generated by silo_setup.py: the numbers of one silo run "
                f"(seed {r['seed']}, D0 = {r['d0_ratio']:g} d = {r['d0_m']:.6g} m, "
                f"N = {r['n_particles']}).\n")
        for k in keys:
            f.write(f"variable {k} equal {r[k]!r}\n")
        for k, v in zip(["box_xlo", "box_xhi", "box_ylo", "box_yhi", "box_zlo", "box_zhi"],
                        r["box"]):
            f.write(f"variable {k} equal {v!r}\n")
        for k in ["cylinder_stl", "floor_stl", "gate_stl"]:
            f.write(f"variable {k} string {r[k]}\n")


def write_model(p, r, path):
    classes = r["radius_classes"]
    wall = r["wall_type"]
    n = r["ntypes"]
    cn = silo_params.normal_coefficient(p)
    ct = silo_params.tangential_coefficient(p)
    if p["normal_law"] != "hooke":
        raise ValueError("LIGGGHTS's hooke/stiffness expresses the Hooke law only")
    constant_kt = p["tangential_law"] == "constant"
    if not constant_kt and p["tangential_law"] != "mindlin":
        raise ValueError("tangential_law must be mindlin or constant")

    def radius(a, b):
        if a == wall and b == wall:
            return 0.0  # wall-wall: never in contact
        if a == wall:
            return classes[b - 1]
        if b == wall:
            return classes[a - 1]
        ra, rb = classes[a - 1], classes[b - 1]
        return ra * rb / (ra + rb)

    def kn(a, b):
        return cn * radius(a, b)

    def kt(a, b):
        if constant_kt:
            return p["tangential_stiffness"]
        root = p["kt_sqrt_overlap_wall"] if wall in (a, b) else p["kt_sqrt_overlap_pair"]
        return ct * math.sqrt(radius(a, b)) * root

    with open(path, "w", encoding="utf-8") as f:
        f.write("# Generated by silo_setup.py: the contact law per type pair (types 1-"
                f"{len(classes)}: radius classes, {wall}: the walls), the particle templates and\n"
                "# their distribution (uniform in number over the classes).\n")
        f.write("# k_n = (2/3)E/(1-nu^2) R_ij; k_t = " +
                ("tangential_stiffness (constant law)\n" if constant_kt else
                 f"(8/3)G/(2-nu) sqrt(R_ij) <sqrt(h)>, <sqrt(h)> = "
                 f"{p['kt_sqrt_overlap_pair']} (pairs), {p['kt_sqrt_overlap_wall']} (walls)\n"))
        f.write(per_type_pair("m_kn", "kn", n, kn))
        f.write(per_type_pair("m_kt", "kt", n, kt))
        f.write(per_type_pair("m_gn", "gamman", n, lambda a, b: p["normal_damping"]))
        f.write(per_type_pair("m_gt", "gammat", n, lambda a, b: p["tangential_damping"]))
        f.write(per_type_pair("m_mu", "coefficientFriction", n, lambda a, b: p["friction"]))
        seed = 300000 + 1000 * r["seed"]
        for k, rk in enumerate(classes, 1):
            seed = prime_at_least(seed + 1)
            f.write(f"fix pts{k} all particletemplate/sphere {seed} atom_type {k} "
                    f"density constant {p['density']!r} radius constant {rk!r}\n")
        weights = " ".join(f"pts{k} {1.0 / len(classes)!r}" for k in range(1, len(classes) + 1))
        f.write(f"fix pdd all particledistribution/discrete/numberbased "
                f"{r['seed_distribution']} {len(classes)} {weights}\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, help="the run's folder")
    ap.add_argument("--mesh-dir", required=True, help="where silo_mesh.py wrote the STL files")
    ap.add_argument("--seed", type=int, default=None)
    ap.add_argument("--d0", type=float, default=None, help="D0/d")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--params", default=silo_params.DEFAULT)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = ap.parse_args()
    p = silo_params.read(args.params, args.set)
    seed = args.seed if args.seed is not None else int(p["seed"])
    if seed < 0:
        raise SystemExit("silo_setup.py: --seed must be >= 0")
    ratio = args.d0 if args.d0 is not None else silo_params.as_list(p["orifice_diameters"])[0]
    os.makedirs(args.out, exist_ok=True)
    r = derive(p, seed, ratio, args.quick, args.ranks, args.mesh_dir)
    for k in ["cylinder_stl", "floor_stl", "gate_stl"]:
        if not os.path.isfile(r[k]):
            raise SystemExit(f"silo_setup.py: {r[k]} missing (run silo_mesh.py first)")
    write_vars(r, os.path.join(args.out, "vars.liggghts"))
    write_model(p, r, os.path.join(args.out, "model.liggghts"))
    r["params"] = p
    with open(os.path.join(args.out, "run.json"), "w", encoding="utf-8") as f:
        json.dump(r, f, indent=1)


if __name__ == "__main__":
    main()
