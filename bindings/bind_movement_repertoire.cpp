// Bindings of the movement repertoire (movement_repertoire.hpp): MovementAction and
// MovementRepertoire (directions, then actions), the default directions and their labels.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "a2l/movement_repertoire.hpp"
#include "common.hpp"

namespace py = pybind11;

namespace a2l::bindings {

void bind_movement_repertoire(py::module_& m) {
  py::enum_<MovementAction>(m, "MovementAction",
                            "What a movement does besides a displacement (none for one).")
      .value("none", MovementAction::none)
      .value("open", MovementAction::open)
      .value("close", MovementAction::close)
      .value("stay", MovementAction::stay);
  m.def("movement_action_name", &movement_action_name, py::arg("action"),
        "The bundle name of an action ('open', 'close', 'stay'; 'none').");

  m.def(
      "default_directions",
      [](bool planar) {
        const std::vector<Eigen::Vector3i> dirs = default_directions(planar);
        Eigen::MatrixXi d(static_cast<Eigen::Index>(dirs.size()), 3);
        for (std::size_t i = 0; i < dirs.size(); ++i) {
          d.row(static_cast<Eigen::Index>(i)) = dirs[i].transpose();
        }
        return d;
      },
      py::arg("planar") = false,
      "The default directions in table order, shape (26, 3) (8 in the plane if `planar`): axis "
      "moves first (+x, -x, +y, -y, +z, -z), then the diagonals.");
  m.def("direction_label", &direction_label, py::arg("d"),
        "The label of sign vector `d` (3,): '+x', '-x+y', ...");

  py::class_<MovementRepertoire>(m, "MovementRepertoire",
                                 "The movements of a skill: directions, then actions.")
      .def_property_readonly("size", &MovementRepertoire::size)
      .def_property_readonly("n_directions", &MovementRepertoire::n_directions)
      .def_property_readonly("n_actions", &MovementRepertoire::n_actions)
      .def_property_readonly(
          "actions",
          [](const MovementRepertoire& r) {
            std::vector<std::string> names;
            for (MovementAction a : r.actions()) names.emplace_back(movement_action_name(a));
            return names;
          },
          "Names of the actions, in movement order (after the directions).")
      .def("action", &MovementRepertoire::action, py::arg("i"),
           "The action of movement i (MovementAction.none for a direction).")
      .def("is_action", &MovementRepertoire::is_action, py::arg("i"))
      .def_property_readonly("step", &MovementRepertoire::step, "Movement length (m).")
      .def_property_readonly("labels", &MovementRepertoire::labels)
      .def_property_readonly(
          "directions",
          [](const MovementRepertoire& r) {
            Eigen::MatrixXi d(r.n_directions(), 3);
            for (int i = 0; i < r.n_directions(); ++i) d.row(i) = r.direction(i).transpose();
            return d;
          },
          "Sign vectors of the directions, shape (n_directions, 3).")
      .def("displacement", &MovementRepertoire::displacement, py::arg("i"),
           "Displacement of movement i, shape (3,): step * d / |d| (zero for an action).")
      .def("label", &MovementRepertoire::label, py::arg("i"))
      .def("__len__", &MovementRepertoire::size);
}

}  // namespace a2l::bindings
