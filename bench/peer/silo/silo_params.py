"""The silo benchmark's parameter file (silo.params): `key = value` lines, `#` comments.

Standard library only. A value is read as a float where it parses as one, as a list of floats
where every space-separated word does, and as a word otherwise. Used by silo_mesh.py,
silo_setup.py and silo_post.py; the granular side can read the same file the same way.
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT = os.path.join(HERE, "silo.params")


def parse_value(text):
    words = text.split()
    if not words:
        raise ValueError("empty value")
    try:
        numbers = [float(w) for w in words]
    except ValueError:
        return text.strip()
    return numbers[0] if len(numbers) == 1 else numbers


def read(path=DEFAULT, overrides=()):
    """The parameters as a dict; `overrides` are 'key=value' strings applied on top (a key that
    the file does not hold is refused, so a typo cannot pass silently)."""
    params = {}
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            if "=" not in line:
                raise ValueError(f"{path}:{number}: expected 'key = value', got {line!r}")
            key, value = (s.strip() for s in line.split("=", 1))
            params[key] = parse_value(value)
    for item in overrides:
        if "=" not in item:
            raise ValueError(f"--set {item!r}: expected key=value")
        key, value = (s.strip() for s in item.split("=", 1))
        if key not in params:
            raise ValueError(f"--set {key}: no such parameter in {path}")
        params[key] = parse_value(value)
    return params


def as_list(value):
    return value if isinstance(value, list) else [value]


def mean_diameter(p):
    return p["radius_min"] + p["radius_max"]


def orifice_diameter(p, ratio):
    """D0 [m] for D0/d = ratio."""
    return ratio * mean_diameter(p)


def orifice_mm(d0):
    """The file-name tag of an orifice: D0 in whole millimetres (6 d = 0.102 m -> 102)."""
    return int(round(d0 * 1000.0))


def mean_particle_mass(p):
    """Mean mass of a sphere with radius uniform in [radius_min, radius_max] [kg]:
    rho 4/3 pi <R^3>, <R^3> = (b^4 - a^4) / (4 (b - a))."""
    a, b = p["radius_min"], p["radius_max"]
    r3 = (b**4 - a**4) / (4.0 * (b - a)) if b > a else a**3
    return p["density"] * 4.0 / 3.0 * math.pi * r3


def normal_coefficient(p):
    """(2/3) E / (1 - nu^2) [Pa]: k_n = this * R_ij for the Hooke law."""
    nu = p["poisson_ratio"]
    return 2.0 / 3.0 * p["youngs_modulus"] / (1.0 - nu * nu)


def tangential_coefficient(p):
    """(8/3) G / (2 - nu) [Pa]: Mindlin's k_t = this * sqrt(R_ij h)."""
    return 8.0 / 3.0 * p["shear_modulus"] / (2.0 - p["poisson_ratio"])


def radius_classes(p):
    """The LIGGGHTS radii: the centres of `radius_classes` equal bins of [radius_min,
    radius_max], equally likely (uniform in number)."""
    n = int(p["radius_classes"])
    a, b = p["radius_min"], p["radius_max"]
    return [a + (k + 0.5) * (b - a) / n for k in range(n)]


def steps(p, seconds):
    """Whole steps covering `seconds` at the fixed step, at least 1."""
    return max(1, int(round(seconds / p["dt"])))
