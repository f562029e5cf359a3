/// A simulation's per-particle state as NumPy arrays (state_arrays.hpp).
#include "state_arrays.hpp"

#include <algorithm>

namespace py = pybind11;

namespace granular::python {
namespace {

template <class Array>
Array readOnly(Array a) {
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

}  // namespace

py::array_t<double> vectorArray(const std::vector<Vec3>& values) {
  const auto n = static_cast<py::ssize_t>(values.size());
  py::array_t<double> out({n, py::ssize_t(3)});
  auto w = out.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    for (py::ssize_t k = 0; k < 3; ++k) w(i, k) = values[std::size_t(i)][k];
  }
  return readOnly(std::move(out));
}

py::array_t<double> scalarArray(const std::vector<double>& values) {
  py::array_t<double> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return readOnly(std::move(out));
}

}  // namespace granular::python
