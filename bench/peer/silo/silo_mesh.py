#!/usr/bin/python3
"""Writes the silo's walls as ASCII STL (standard library only), for LIGGGHTS and granular alike.

    silo_mesh.py --out DIR [--params silo.params] [--set key=value ...] [--d0 RATIO ...]

Files, in metres:
  cylinder.stl          side wall, radius R, z = 0 .. H; `mesh_segments` facets around, rings
                        about `mesh_edge` high; vertices on the circle, normals inward.
  floor_D0_<mm>.stl     the floor at z = 0: annulus from D0/2 to R, normals up (+z).
  gate_D0_<mm>.stl      the gate at z = 0: disc of radius D0/2, normals up (+z).
<mm> is D0 in whole millimetres (6 d = 0.102 m -> 102). The floor's outer rim shares its
vertices with the cylinder's bottom ring and its inner rim with the gate's rim, so the three
meshes meet without gaps. Prints one line per file: name, triangles, smallest angle.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import silo_params  # noqa: E402


def ring(radius, count, z, phase=0.0):
    return [(radius * math.cos(2.0 * math.pi * (j + phase) / count),
             radius * math.sin(2.0 * math.pi * (j + phase) / count), z) for j in range(count)]


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    return math.sqrt(dot(a, a))


def oriented(tri, want):
    """The triangle with its vertices ordered so that its normal points along `want`."""
    a, b, c = tri
    n = cross(sub(b, a), sub(c, a))
    return (a, b, c) if dot(n, want) > 0 else (a, c, b)


def smallest_angle(tri):
    worst = 180.0
    for i in range(3):
        a, b, c = tri[i], tri[(i + 1) % 3], tri[(i + 2) % 3]
        u, v = sub(b, a), sub(c, a)
        cosine = dot(u, v) / (norm(u) * norm(v))
        worst = min(worst, math.degrees(math.acos(max(-1.0, min(1.0, cosine)))))
    return worst


def stitch(inner, outer):
    """Triangles between two closed rings, len(outer) = len(inner) or 2 len(inner), vertex 0 of
    each at the same angle (the outer ring's vertices 2j and 2j+1 then lie over inner j and the
    middle of inner j, j+1)."""
    n, m = len(inner), len(outer)
    tris = []
    if m == n:
        for j in range(n):
            a, b = inner[j], inner[(j + 1) % n]
            c, d = outer[j], outer[(j + 1) % n]
            tris += [(a, c, d), (a, d, b)]
    elif m == 2 * n:
        for j in range(n):
            a, b = inner[j], inner[(j + 1) % n]
            c, e, f = outer[2 * j], outer[2 * j + 1], outer[(2 * j + 2) % m]
            tris += [(a, c, e), (a, e, b), (b, e, f)]
    else:
        raise ValueError("rings must have n and n or 2n vertices")
    return tris


def cylinder(radius, height, segments, edge):
    rings = max(1, int(round(height / edge)))
    tris = []
    for i in range(rings):
        lo = ring(radius, segments, height * i / rings)
        hi = ring(radius, segments, height * (i + 1) / rings)
        for j in range(segments):
            a, b = lo[j], lo[(j + 1) % segments]
            c, d = hi[j], hi[(j + 1) % segments]
            mid = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, 0.0)
            inward = (-mid[0], -mid[1], 0.0)
            tris += [oriented((a, b, d), inward), oriented((a, d, c), inward)]
    return tris


def annulus(r_in, r_out, segments, edge, z=0.0):
    """Flat ring r_in..r_out at height z, all rings with `segments` vertices."""
    intervals = max(1, int(round((r_out - r_in) / edge)))
    radii = [r_in + (r_out - r_in) * k / intervals for k in range(intervals + 1)]
    tris = []
    for k in range(intervals):
        tris += stitch(ring(radii[k], segments, z), ring(radii[k + 1], segments, z))
    return [oriented(t, (0.0, 0.0, 1.0)) for t in tris]


def disc(radius, segments, edge, z=0.0):
    """Flat disc at height z: rings about `edge` apart, the outer one with `segments` vertices,
    inner ones halving their count while their spacing stays under about `edge`; a fan at the
    centre."""
    intervals = max(1, int(round(radius / edge)))
    radii = [radius * k / intervals for k in range(1, intervals + 1)]
    counts = [segments] * intervals
    for k in range(intervals - 2, -1, -1):
        c = counts[k + 1]
        if c % 2 == 0 and c // 2 >= 6 and 2.0 * math.pi * radii[k] / (c // 2) <= edge:
            counts[k] = c // 2
        else:
            counts[k] = c
    rings = [ring(r, c, z) for r, c in zip(radii, counts)]
    centre = (0.0, 0.0, z)
    first = rings[0]
    tris = [(centre, first[j], first[(j + 1) % len(first)]) for j in range(len(first))]
    for k in range(intervals - 1):
        tris += stitch(rings[k], rings[k + 1])
    return [oriented(t, (0.0, 0.0, 1.0)) for t in tris]


def check(name, tris):
    """Refuses a mesh with an edge shared by more than two triangles or two neighbours whose
    orientations disagree (granular refuses both); returns the number of open edges."""
    key = lambda v: tuple(fmt(c) for c in v)
    directed = set()
    undirected = {}
    for t in tris:
        for i in range(3):
            a, b = key(t[i]), key(t[(i + 1) % 3])
            if (a, b) in directed:
                raise ValueError(f"{name}: neighbours with opposite orientations at {a}-{b}")
            directed.add((a, b))
            e = (min(a, b), max(a, b))
            undirected[e] = undirected.get(e, 0) + 1
            if undirected[e] > 2:
                raise ValueError(f"{name}: an edge shared by three triangles at {a}-{b}")
    return sum(1 for c in undirected.values() if c == 1)


def fmt(x):
    s = "%.9g" % x
    return "0" if s in ("-0", "0") else s


def write_stl(path, name, tris):
    with open(path, "w", encoding="ascii") as f:
        f.write(f"solid {name}\n")
        for t in tris:
            n = cross(sub(t[1], t[0]), sub(t[2], t[0]))
            length = norm(n)
            if length == 0.0:
                raise ValueError(f"{name}: zero-area triangle {t}")
            f.write("  facet normal %s %s %s\n    outer loop\n" %
                    tuple(fmt(c / length) for c in n))
            for v in t:
                f.write("      vertex %s %s %s\n" % tuple(fmt(c) for c in v))
            f.write("    endloop\n  endfacet\n")
        f.write(f"endsolid {name}\n")


def write_all(p, out, ratios):
    os.makedirs(out, exist_ok=True)
    n, edge, big_r = int(p["mesh_segments"]), p["mesh_edge"], p["silo_radius"]
    files = [("cylinder.stl", "cylinder", cylinder(big_r, p["silo_height"], n, edge))]
    for ratio in ratios:
        d0 = silo_params.orifice_diameter(p, ratio)
        if not 0.0 < d0 / 2.0 < big_r:
            raise ValueError(f"D0 = {d0} m does not fit in the silo (R = {big_r} m)")
        mm = silo_params.orifice_mm(d0)
        files.append((f"floor_D0_{mm}.stl", f"floor_D0_{mm}", annulus(d0 / 2.0, big_r, n, edge)))
        files.append((f"gate_D0_{mm}.stl", f"gate_D0_{mm}", disc(d0 / 2.0, n, edge)))
    for file, name, tris in files:
        open_edges = check(name, tris)
        write_stl(os.path.join(out, file), name, tris)
        print(f"{file}: {len(tris)} triangles, smallest angle "
              f"{min(smallest_angle(t) for t in tris):.2f} deg, {open_edges} rim edges")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, help="folder for the STL files")
    ap.add_argument("--params", default=silo_params.DEFAULT)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--d0", type=float, nargs="+",
                    help="D0/d ratios (default: orifice_diameters of the parameter file)")
    args = ap.parse_args()
    p = silo_params.read(args.params, args.set)
    ratios = args.d0 or silo_params.as_list(p["orifice_diameters"])
    write_all(p, args.out, ratios)


if __name__ == "__main__":
    main()
