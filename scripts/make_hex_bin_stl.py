#!/usr/bin/env python3
"""Writes assets/meshes/hex-bin.stl: a hexagonal bin with a flat floor and an open top, the
mesh of assets/scenes/mesh-bin.toml. ASCII STL, metres, triangles counter-clockwise seen from
inside the bin.

    python3 scripts/make_hex_bin_stl.py
"""
import math
import pathlib

APOTHEM = 0.08  # m, floor centre to the middle of a side
HEIGHT = 0.40   # m
SIDES = 6

corner = APOTHEM / math.cos(math.pi / SIDES)
ring = [(corner * math.cos(2 * math.pi * k / SIDES), corner * math.sin(2 * math.pi * k / SIDES))
        for k in range(SIDES)]
triangles = []
for k in range(SIDES):
    (x0, y0), (x1, y1) = ring[k], ring[(k + 1) % SIDES]
    # the floor, a fan about its centre; its normal up, into the bin
    triangles.append(((0.0, 0.0, 0.0), (x0, y0, 0.0), (x1, y1, 0.0)))
    # the side, two triangles; their normals towards the axis
    triangles.append(((x0, y0, 0.0), (x0, y0, HEIGHT), (x1, y1, HEIGHT)))
    triangles.append(((x0, y0, 0.0), (x1, y1, HEIGHT), (x1, y1, 0.0)))

lines = ["solid hex_bin"]
for a, b, c in triangles:
    lines += ["  facet normal 0 0 0", "    outer loop"]
    lines += ["      vertex %.9g %.9g %.9g" % v for v in (a, b, c)]
    lines += ["    endloop", "  endfacet"]
lines.append("endsolid hex_bin")
out = pathlib.Path(__file__).resolve().parent.parent / "assets" / "meshes" / "hex-bin.stl"
out.write_text("\n".join(lines) + "\n")
print("wrote", out, len(triangles), "triangles")
