#pragma once
/// The parts of the Python module `granular` (module.cpp), each binding one side of the core.
#include <pybind11/pybind11.h>

namespace granular::python {

/// The core's exceptions as Python's: SceneError and ConfigError are ValueErrors, IoError an
/// OSError, NumericalError a RuntimeError; each message as the core words it (the file, the
/// line, the key, the value, the allowed range).
void bindErrors(pybind11::module_& m);
/// Scenes read from a TOML file (load_scene) and what a scene holds.
void bindScene(pybind11::module_& m);
/// Simulation: built from a scene, stepped with the GIL released, its state as NumPy arrays.
void bindSimulation(pybind11::module_& m);

}  // namespace granular::python
