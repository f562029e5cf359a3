"""granular: discrete-element simulations of granular material, from Python.

Scenes are read from TOML files (docs/scenes.md); a Simulation built from one steps in C++ and
gives its state as NumPy arrays in SI units. docs/python.md has a tutorial and the reference.
"""

from ._core import (
    ConfigError,
    IoError,
    NumericalError,
    Scene,
    SceneError,
    Simulation,
    TimeStepError,
    load_scene,
)

__all__ = [
    "ConfigError",
    "IoError",
    "NumericalError",
    "Scene",
    "SceneError",
    "Simulation",
    "TimeStepError",
    "load_scene",
]
