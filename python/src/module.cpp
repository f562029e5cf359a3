/// The Python module `granular` (python/granular/__init__.py re-exports this extension,
/// granular._core): docs/python.md.
#include "bindings.hpp"

PYBIND11_MODULE(_core, m) {
  m.doc() = "granular's core: scenes, simulations and their state as NumPy arrays";
  granular::python::bindErrors(m);
  granular::python::bindScene(m);
  granular::python::bindSimulation(m);
}
