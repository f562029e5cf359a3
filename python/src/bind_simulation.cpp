/// Simulation (bindings.hpp): built from a scene, stepped in C++ with the GIL released, its
/// state read as NumPy arrays.
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "bindings.hpp"
#include "granular/scene.hpp"
#include "granular/simulation.hpp"
#include "state_arrays.hpp"

namespace py = pybind11;

namespace granular::python {
namespace {

/// A Simulation that Python holds: refused once closed, and while it steps on another thread
/// (a Python thread may read it while the GIL is released).
class SimulationHandle {
 public:
  explicit SimulationHandle(const Scene& scene)
      : sim_(std::make_unique<Simulation>(buildSimulation(scene))) {}

  /// The simulation to read: refused when closed or stepping.
  const Simulation& read() const { return checked(); }

  /// Runs `advance` on the simulation with the GIL released, marked as stepping meanwhile.
  template <class Advance>
  auto stepping(Advance&& advance) {
    Simulation& sim = checked();
    busy_ = true;
    struct Done {
      std::atomic<bool>& busy;
      ~Done() { busy = false; }
    } done{busy_};
    py::gil_scoped_release release;
    return advance(sim);
  }

  void close() {
    checkNotBusy();
    sim_.reset();
  }

 private:
  void checkNotBusy() const {
    if (busy_) throw std::runtime_error("the simulation is stepping on another thread");
  }
  Simulation& checked() const {
    if (!sim_) throw std::runtime_error("the simulation is closed");
    checkNotBusy();
    return *sim_;
  }

  std::unique_ptr<Simulation> sim_;
  std::atomic<bool> busy_{false};
};

/// Whether Python has a signal to deliver (Ctrl-C: KeyboardInterrupt), asked with the GIL held;
/// the exception then waits in Python's error indicator.
bool signalled() {
  py::gil_scoped_acquire acquire;
  return PyErr_CheckSignals() != 0;
}

/// The steps step(n) takes between two looks for a signal.
constexpr std::uint64_t kStepsBetweenSignalChecks = 256;

void step(SimulationHandle& h, long long n) {
  if (n < 1) throw py::value_error("step(n): n must be >= 1, got " + std::to_string(n));
  bool interrupted = false;
  h.stepping([&](Simulation& sim) {
    // run(k) in pieces gives the same bits as one run(n): each is steps.
    for (auto left = static_cast<std::uint64_t>(n); left > 0 && !interrupted;) {
      const std::uint64_t k = std::min(left, kStepsBetweenSignalChecks);
      sim.run(k);
      left -= k;
      if (left > 0 && signalled()) interrupted = true;
    }
  });
  if (interrupted) throw py::error_already_set();
}

void advanceTo(SimulationHandle& h, double t) {
  if (!std::isfinite(t)) {
    throw py::value_error("advance_to(t): t must be a finite time [s], got " +
                          py::repr(py::float_(t)).cast<std::string>());
  }
  bool interrupted = false;
  h.stepping([&](Simulation& sim) {
    sim.advanceTo(t, [&] {
      interrupted = signalled();
      return !interrupted;
    });
  });
  if (interrupted) throw py::error_already_set();
}

/// The energy ledger as the time series' columns name it [J].
py::dict energy(const SimulationHandle& h) {
  const EnergyBalance e = h.read().energy();
  py::dict out;
  out["kinetic_translational_J"] = e.kineticTranslational;
  out["kinetic_rotational_J"] = e.kineticRotational;
  for (const EnergyAccount& a : e.contact) out[py::str(std::string(a.column))] = a.value;
  out["gravity_work_J"] = e.gravityWork;
  out["wall_work_J"] = e.wallWork;
  out["energy_total_J"] = e.total();
  return out;
}

}  // namespace

void bindSimulation(py::module_& m) {
  py::class_<SimulationHandle>(m, "Simulation", R"doc(
A simulation built from a scene: its particles and walls, at time 0, before any stage. Stepping
runs in C++ with the GIL released; Ctrl-C stops it between two steps (KeyboardInterrupt), the
state whole. The state reads as NumPy arrays in SI units, copies that stay valid after the
simulation moves on (read-only: they are not the engine's storage).)doc")
      .def(py::init<const Scene&>(), py::arg("scene"))
      .def("step", &step, py::arg("n") = 1, R"doc(
Advances n >= 1 steps of the current time step.)doc")
      .def("advance_to", &advanceTo, py::arg("t"), R"doc(
Advances to simulated time t [s] (not before the clock): in steps no longer than the current
one, the last ones shortened alike to land on t; the clock reads t exactly afterwards.)doc")
      .def_property_readonly(
          "time", [](const SimulationHandle& h) { return h.read().time(); }, "Simulated time [s].")
      .def_property_readonly(
          "step_count", [](const SimulationHandle& h) { return h.read().stepCount(); },
          "Steps taken since the simulation was built.")
      .def_property_readonly(
          "time_step", [](const SimulationHandle& h) { return h.read().config().timeStep; },
          "The time step in use [s].")
      .def_property_readonly(
          "particle_count", [](const SimulationHandle& h) { return h.read().particles().size(); },
          "How many particles there are.")
      .def_property_readonly(
          "positions",
          [](const SimulationHandle& h) { return vectorArray(h.read().particles().position); },
          "Centres, (n, 3) [m].")
      .def_property_readonly(
          "velocities",
          [](const SimulationHandle& h) { return vectorArray(h.read().particles().velocity); },
          "Velocities, (n, 3) [m/s].")
      .def_property_readonly(
          "spins",
          [](const SimulationHandle& h) {
            return vectorArray(h.read().particles().angularVelocity);
          },
          "Angular velocities, (n, 3) [rad/s] (zero without friction).")
      .def_property_readonly(
          "radii",
          [](const SimulationHandle& h) { return scalarArray(h.read().particles().radius); },
          "Radii, (n,) [m].")
      .def_property_readonly(
          "masses",
          [](const SimulationHandle& h) { return scalarArray(h.read().particles().mass); },
          "Masses, (n,) [kg].")
      .def("energy", &energy, R"doc(
The energy ledger [J], by the time series' column names: kinetic, the contact terms' stored,
dissipated and supplied accounts, gravity's and the walls' work, and energy_total_J, constant
but for the integrator's error.)doc")
      .def_property_readonly(
          "state_hash", [](const SimulationHandle& h) { return h.read().stateHash(); },
          "A hash of the whole state: equal hashes, equal runs to the bit.")
      .def("close", &SimulationHandle::close, R"doc(
Frees the simulation; any later use but close() raises RuntimeError.)doc")
      .def("__enter__", [](SimulationHandle& h) -> SimulationHandle& { return h; })
      .def("__exit__", [](SimulationHandle& h, py::args) { h.close(); });
}

}  // namespace granular::python
