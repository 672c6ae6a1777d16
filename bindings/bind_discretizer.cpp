// Bindings of the discretizer (discretizer.hpp): VariableKind, Variable, Context and
// Discretizer (context -> bins).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <string>
#include <vector>

#include "a2l/discretizer.hpp"
#include "common.hpp"

namespace py = pybind11;

namespace a2l::bindings {

void bind_discretizer(py::module_& m) {
  py::enum_<VariableKind>(m, "VariableKind", "What an evidence variable measures.")
      .value("effect", VariableKind::effect)
      .value("distance", VariableKind::distance)
      .value("orientation", VariableKind::orientation)
      .value("inclination", VariableKind::inclination)
      .value("high_level", VariableKind::high_level)
      .value("offset_x", VariableKind::offset_x)
      .value("offset_y", VariableKind::offset_y);

  py::class_<Variable>(m, "Variable", "One evidence variable (one axis of the policy table).")
      .def_readonly("name", &Variable::name)
      .def_readonly("kind", &Variable::kind)
      .def_readonly("n_bins", &Variable::n_bins)
      .def_readonly("low", &Variable::low)
      .def_readonly("high", &Variable::high)
      .def_readonly("values", &Variable::values)
      .def_readonly(
          "edges", &Variable::edges,
          "distance only: the interior bin edges (m); empty: equal bins over [low, high].")
      .def("__repr__", [](const Variable& v) {
        return "<a2l.Variable '" + v.name + "' " + variable_kind_name(v.kind) + ", " +
               std::to_string(v.n_bins) + " bins>";
      });

  py::class_<Context>(m, "Context", R"doc(
The situation at one instant, as step() sees it.

Parameters
----------
eef, object : array_like, shape (3,)
    End-effector position and object centre (m).
effect : int
    Index of the wanted effect among the skill's effect values.
high_level : list of int, optional
    Value index of each high-level variable, by axis (at most 16 entries; other axes
    ignored). ``Skill.context`` builds it from names.
effect_produced : bool
    The caller observed that the object moved: the next step ends the run.
)doc")
      .def(py::init([](const Eigen::Vector3d& eef, const Eigen::Vector3d& object, int effect,
                       const std::vector<int>& high_level, bool effect_produced) {
             if (high_level.size() > static_cast<size_t>(kMaxVariables)) {
               raise(Status::size_mismatch, "high_level: at most 16 entries");
             }
             Context c;
             c.eef = eef;
             c.object = object;
             c.effect = effect;
             for (size_t i = 0; i < high_level.size(); ++i) c.high_level[i] = high_level[i];
             c.effect_produced = effect_produced;
             return c;
           }),
           py::arg("eef") = Eigen::Vector3d::Zero(), py::arg("object") = Eigen::Vector3d::Zero(),
           py::arg("effect") = 0, py::arg("high_level") = std::vector<int>(),
           py::arg("effect_produced") = false)
      .def_readwrite("eef", &Context::eef)
      .def_readwrite("object", &Context::object)
      .def_readwrite("effect", &Context::effect)
      .def_readwrite("effect_produced", &Context::effect_produced)
      .def_property(
          "high_level",
          [](const Context& c) {
            return std::vector<int>(c.high_level.begin(), c.high_level.end());
          },
          [](Context& c, const std::vector<int>& v) {
            if (v.size() > static_cast<size_t>(kMaxVariables)) {
              raise(Status::size_mismatch, "high_level: at most 16 entries");
            }
            c.high_level.fill(0);
            for (size_t i = 0; i < v.size(); ++i) c.high_level[i] = v[i];
          });

  py::class_<Discretizer>(m, "Discretizer", "Context -> bins (docs/bundle_format.md).")
      .def_property_readonly("n_variables", &Discretizer::n_variables)
      .def_property_readonly("variables", &Discretizer::variables)
      .def_property_readonly("effect_axis", &Discretizer::effect_axis,
                             "Axis of the effect variable, or -1.")
      .def("find", &Discretizer::find, py::arg("name"), "Axis of a variable, or -1.")
      .def_static("distance_bin", &Discretizer::distance_bin, py::arg("d"), py::arg("low"),
                  py::arg("high"), py::arg("n"), "Saturating distance bin; -1 if not finite.")
      .def_static("orientation_bin", &Discretizer::orientation_bin, py::arg("theta"), py::arg("n"),
                  "Orientation bin (half-section offset); -1 if not finite.")
      .def_static("inclination_bin", &Discretizer::inclination_bin, py::arg("phi"), py::arg("n"),
                  "Inclination bin of phi in [0, pi]; -1 if not finite.")
      .def(
          "discretize",
          [](const Discretizer& d, const Context& c) {
            std::array<int, kMaxVariables> bins{};
            const Status s = d.discretize(c, bins.data());
            return py::make_tuple(s,
                                  std::vector<int>(bins.begin(), bins.begin() + d.n_variables()));
          },
          py::arg("context"),
          "(status, bins): bins of every variable (-1 = unknown), status ok or unknown_context.");
}

}  // namespace a2l::bindings
