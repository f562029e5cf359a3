/// The core's exceptions as Python's (bindings.hpp).
#include "bindings.hpp"
#include "granular/error.hpp"

namespace py = pybind11;

namespace granular::python {

void bindErrors(py::module_& m) {
  // A base before what derives from it: pybind11 tries the last registered translator first,
  // and each catches its type and every type derived from it.
  auto scene = py::register_exception<SceneError>(m, "SceneError", PyExc_ValueError);
  scene.doc() = "A scene file that cannot be read or does not validate (a ValueError).";
  auto config = py::register_exception<ConfigError>(m, "ConfigError", PyExc_ValueError);
  config.doc() =
      "A configuration the core refuses: a bad parameter, a particle outside the box (a "
      "ValueError).";
  auto step = py::register_exception<TimeStepError>(m, "TimeStepError", config.ptr());
  step.doc() = "A time step the engine refuses as unstable (a ConfigError).";
  auto io = py::register_exception<IoError>(m, "IoError", PyExc_OSError);
  io.doc() = "A file that cannot be opened, read or written in full (an OSError).";
  auto numerical = py::register_exception<NumericalError>(m, "NumericalError", PyExc_RuntimeError);
  numerical.doc() =
      "A state that stopped being a number during a step (a RuntimeError); the simulation is "
      "unusable afterwards.";
}

}  // namespace granular::python
