// Bindings of a skill's DS phases (ds_phases.hpp) and step_ds() (skill.hpp).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "a2l/skill.hpp"
#include "common.hpp"

namespace py = pybind11;

namespace a2l::bindings {
namespace {

// Value index per DS state variable from {name: value name or index}; states the phases do
// not name are ignored, missing ones are -1 (they match no condition).
DSStateValues state_values(const DSPhaseSet& set, const py::object& states) {
  DSStateValues v;
  v.fill(-1);
  if (states.is_none()) return v;
  if (!py::isinstance<py::dict>(states)) {
    const auto list = states.cast<std::vector<int>>();
    if (list.size() > v.size()) raise(Status::size_mismatch, "states: at most 16 entries");
    for (std::size_t i = 0; i < list.size(); ++i) v[i] = list[i];
    return v;
  }
  for (const auto& item : states.cast<py::dict>()) {
    const int s = set.find_state(item.first.cast<std::string>());
    if (s < 0) continue;
    const DSStateVariable& var = set.states[static_cast<std::size_t>(s)];
    if (!py::isinstance<py::str>(item.second)) {
      v[static_cast<std::size_t>(s)] = item.second.cast<int>();
      continue;
    }
    const std::string value = item.second.cast<std::string>();
    int index = -1;
    std::string names;
    for (std::size_t k = 0; k < var.values.size(); ++k) {
      if (var.values[k] == value) index = static_cast<int>(k);
      names += (k ? ", " : "") + var.values[k];
    }
    if (index < 0) {
      raise(Status::invalid_argument,
            "'" + value + "' is not a value of state '" + var.name + "' (" + names + ")");
    }
    v[static_cast<std::size_t>(s)] = index;
  }
  return v;
}

}  // namespace

void bind_skill_ds(py::module_& m) {
  // Skill is registered by bind_skill(): add the phases' properties to it.
  auto cls = py::reinterpret_borrow<py::class_<Skill>>(m.attr("Skill"));
  cls.def_property_readonly(
         "ds_states",
         [](const Skill& s) {
           py::dict d;
           for (const DSStateVariable& v : s.ds_phases().states) d[py::str(v.name)] = v.values;
           return d;
         },
         "The states the DS phases name: {name: [values]} (empty without phases).")
      .def_property_readonly(
          "ds_phases",
          [](const Skill& s) {
            py::list out;
            const DSPhaseSet& set = s.ds_phases();
            for (const DSPhase& p : set.phases) {
              py::dict when;
              for (const DSCondition& c : p.when) {
                const DSStateVariable& v = set.states[static_cast<std::size_t>(c.state)];
                when[py::str(v.name)] = v.values[static_cast<std::size_t>(c.value)];
              }
              py::dict d;
              d["name"] = p.name;
              d["when"] = when;
              d["end_action"] = p.end_action == MovementAction::none
                                    ? py::object(py::none())
                                    : py::object(py::str(movement_action_name(p.end_action)));
              d["tolerance"] = p.tolerance;
              d["target"] = Eigen::Vector3d(p.ds.target());
              d["speed"] = p.ds.speed();
              d["n_maps"] = p.ds.n_maps();
              out.append(d);
            }
            return out;
          },
          "The DS phases in priority order: dicts {name, when, end_action, tolerance, target "
          "(3,) relative to the object, speed, n_maps}.");

  m.def(
      "step_ds",
      [](const Skill& skill, SkillState& state, const Eigen::Vector3d& eef,
         const Eigen::Vector3d& object, const py::object& states) {
        const DSStateValues v = state_values(skill.ds_phases(), states);
        StepOutput out;
        step_ds(skill, state, eef, object, v, out);
        return out;
      },
      py::arg("skill"), py::arg("state"), py::arg("eef"), py::arg("object"),
      py::arg("states") = py::none(), R"doc(
One step of the skill's DS phases (the C++ runtime's step_ds()).

Parameters
----------
skill : Skill
state : SkillState
eef, object : array_like, shape (3,)
    End-effector and object positions (m).
states : dict of str to (str or int), or list of int, optional
    High-level state values by name (states the phases do not name are ignored), or value
    indices in ``skill.ds_states`` order.

Returns
-------
StepOutput
    ``ok`` with a displacement (3,) of at most one movement's length along the phase's DS
    velocity, or with the phase's end ``action`` within its tolerance; else ``converged``,
    ``step_cap``, ``unknown_context`` (no phase matches, non-finite position) or
    ``not_initialized`` (no phase). ``record.phase`` is the phase used.
)doc");
}

}  // namespace a2l::bindings
