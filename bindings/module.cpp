// The pybind11 module a2l._core: one bind_<area>() per header area.
#include <pybind11/pybind11.h>

namespace py = pybind11;

namespace a2l::bindings {
void bind_status(py::module_& m);
void bind_kinematics(py::module_& m);
void bind_discretizer(py::module_& m);
void bind_policy_table(py::module_& m);
void bind_movement_repertoire(py::module_& m);
void bind_skill(py::module_& m);
void bind_effects(py::module_& m);
void bind_scene(py::module_& m);
void bind_transit(py::module_& m);
void bind_diffeo(py::module_& m);
void bind_skill_ds(py::module_& m);
void bind_bins(py::module_& m);
// New areas: declare bind_<area> here and call it below (one line each).
}  // namespace a2l::bindings

PYBIND11_MODULE(_core, m) {
  m.doc() = "a2l C++ core: kinematics, skills, runtime (see the a2l package for docs)";
  m.attr("__version__") = A2L_VERSION;
  a2l::bindings::bind_status(m);
  a2l::bindings::bind_kinematics(m);
  a2l::bindings::bind_discretizer(m);
  a2l::bindings::bind_policy_table(m);
  a2l::bindings::bind_movement_repertoire(m);
  a2l::bindings::bind_skill(m);  // after its parts (discretizer, table, repertoire)
  a2l::bindings::bind_effects(m);
  a2l::bindings::bind_scene(m);
  a2l::bindings::bind_transit(m);
  a2l::bindings::bind_diffeo(m);
  a2l::bindings::bind_skill_ds(m);
  a2l::bindings::bind_bins(m);
}
