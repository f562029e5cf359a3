#pragma once
/// A simulation's per-particle state as NumPy arrays (bind_simulation.cpp): copies, made
/// read-only, so that no array outlives or aliases the engine's storage, which the neighbour
/// list's rebuilds reorder and exchanges resize.
#include <pybind11/numpy.h>

#include <vector>

#include "granular/vec3.hpp"

namespace granular::python {

/// An (n, 3) float64 array of the vectors, read-only.
pybind11::array_t<double> vectorArray(const std::vector<Vec3>& values);
/// An (n,) float64 array of the values, read-only.
pybind11::array_t<double> scalarArray(const std::vector<double>& values);

}  // namespace granular::python
