/// Scenes from a TOML file (bindings.hpp).
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.hpp"
#include "granular/scene.hpp"

namespace py = pybind11;

namespace granular::python {

void bindScene(py::module_& m) {
  py::class_<Scene>(m, "Scene", R"doc(
A scene as read from its TOML file (docs/scenes.md): the material, the box and walls, the
particles' generators, the stages and the output. Built by load_scene; Simulation(scene) builds
its particles and walls.)doc")
      .def_property_readonly(
          "path", [](const Scene& s) { return s.sourceFile; }, "The file it was read from.")
      .def_property_readonly(
          "stage_names",
          [](const Scene& s) {
            std::vector<std::string> names;
            for (const StageSpec& stage : s.stages) names.push_back(stage.name);
            return names;
          },
          "The stages' names, in order.")
      .def_property_readonly(
          "warnings", [](const Scene& s) { return s.warnings; },
          "What the loader found legal but likely wrong, each naming the file, line and key.")
      .def("__repr__", [](const Scene& s) {
        return "<granular.Scene '" + s.sourceFile.string() + "', " +
               std::to_string(s.stages.size()) + " stages>";
      });

  m.def(
      "load_scene", [](const std::filesystem::path& file) { return loadScene(file); },
      py::arg("path"), R"doc(
Reads and validates a scene file. Raises SceneError (a ValueError) naming the file, the line,
the key, the value and the allowed range, as `granular run` does.)doc");
}

}  // namespace granular::python
