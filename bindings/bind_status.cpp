#include <pybind11/pybind11.h>

#include "a2l/status.hpp"

namespace py = pybind11;

namespace a2l::bindings {

void bind_status(py::module_& m) {
  py::enum_<Status> s(m, "Status", "Outcome of a call into the C++ core.");
  for (int i = 0; i <= static_cast<int>(Status::converged); ++i) {
    const auto st = static_cast<Status>(i);
    s.value(status_name(st), st);
  }
  m.def("status_name", &status_name, py::arg("status"), "The snake_case name of a status.");
}

}  // namespace a2l::bindings
