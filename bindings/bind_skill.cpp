// Bindings of the skill runtime (skill.hpp, bundle.hpp): Smoothing, Skill, SkillState,
// TraceRecord, StepOutput, step() and the bundle loader. Its parts have their own files:
// bind_discretizer.cpp, bind_policy_table.cpp, bind_movement_repertoire.cpp (bound first).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "a2l/bundle.hpp"
#include "a2l/discretizer.hpp"
#include "a2l/skill.hpp"
#include "common.hpp"

namespace py = pybind11;

namespace a2l::bindings {
namespace {

py::dict trace_dict(const TraceRecord& r) {
  py::dict d;
  d["step"] = r.step;
  d["bins"] = std::vector<int>(r.bins.begin(), r.bins.begin() + r.n_variables);
  d["movement"] = r.movement;
  d["probability"] = r.probability;
  d["status"] = r.status;
  d["phase"] = r.phase;
  d["fallback"] = r.fallback;
  return d;
}

// The value index of `value` (an int or one of `names`) for variable `what`.
int value_index(const py::handle& value, const Variable& v) {
  if (py::isinstance<py::str>(value)) {
    const std::string s = value.cast<std::string>();
    for (size_t i = 0; i < v.values.size(); ++i) {
      if (v.values[i] == s) return static_cast<int>(i);
    }
    std::string names;
    for (const auto& n : v.values) names += (names.empty() ? "" : ", ") + n;
    raise(Status::invalid_argument,
          "'" + s + "' is not a value of variable '" + v.name + "' (" + names + ")");
  }
  return value.cast<int>();
}

}  // namespace

void bind_skill(py::module_& m) {
  py::enum_<Smoothing>(m, "Smoothing", "Smoothing choice of a run (SkillState.smoothing).")
      .value("from_skill", Smoothing::from_skill)
      .value("off", Smoothing::off)
      .value("on", Smoothing::on);

  py::class_<Skill>(m, "Skill", R"doc(
A skill loaded from a bundle (immutable). Load with ``a2l._core.load_bundle(path)`` or
``load_bundle_from_memory(data)``.
)doc")
      .def_property_readonly("name", &Skill::name)
      .def_property_readonly("loaded", &Skill::loaded)
      .def_property_readonly("n_variables", &Skill::n_variables)
      .def_property_readonly("n_moves", &Skill::n_moves)
      .def_property_readonly("discretizer", &Skill::discretizer,
                             py::return_value_policy::reference_internal)
      .def_property_readonly("table", &Skill::table, py::return_value_policy::reference_internal)
      .def_property_readonly("movements", &Skill::movements,
                             py::return_value_policy::reference_internal)
      .def_property_readonly("variables",
                             [](const Skill& s) { return s.discretizer().variables(); })
      .def_property_readonly("step_cap", [](const Skill& s) { return s.settings().step_cap; })
      .def_property_readonly("smoothing", [](const Skill& s) { return s.settings().smoothing; })
      .def_property_readonly("uniform_tolerance",
                             [](const Skill& s) { return s.settings().uniform_tolerance; })
      .def_property_readonly(
          "fallback",
          [](const Skill& s) { return std::string(fallback_name(s.settings().fallback)); },
          "The answer for a cell with no information: 'none' (stop), 'nearest' or 'approach'.")
      .def(
          "fallback_row",
          [](const Skill& s, std::size_t row) {
            if (row >= s.table().n_rows()) raise(Status::invalid_argument, "row out of range");
            return s.fallback_row(row);
          },
          py::arg("row"), "The row step() reads for table row `row` (itself, its fallback, or -1).")
      .def_property_readonly(
          "robot",
          [](const Skill& s) -> py::object {
            if (!s.robot().present) return py::none();
            py::dict d;
            d["name"] = s.robot().name;
            d["urdf_sha256"] = s.robot().urdf_sha256;
            d["base_link"] = s.robot().base_link;
            d["tip_link"] = s.robot().tip_link;
            return std::move(d);
          },
          "The robot's {name, urdf_sha256, base_link, tip_link}, or None.")
      .def_property_readonly(
          "effect_values",
          [](const Skill& s) {
            const int a = s.discretizer().effect_axis();
            return a < 0 ? std::vector<std::string>() : s.discretizer().variable(a).values;
          },
          "Names of the effects (empty if the table has no effect variable).")
      .def(
          "context",
          [](const Skill& s, const Eigen::Vector3d& eef, const Eigen::Vector3d& object,
             const py::object& effect, const py::object& high_level, bool effect_produced) {
            Context c;
            c.eef = eef;
            c.object = object;
            c.effect_produced = effect_produced;
            const Discretizer& d = s.discretizer();
            if (d.effect_axis() >= 0) {
              c.effect = value_index(effect, d.variable(d.effect_axis()));
            } else if (!py::isinstance<py::str>(effect)) {
              c.effect = effect.cast<int>();
            }
            if (!high_level.is_none()) {
              for (const auto& item : high_level.cast<py::dict>()) {
                const std::string name = item.first.cast<std::string>();
                const int axis = d.find(name);
                if (axis < 0 || d.variable(axis).kind != VariableKind::high_level) {
                  continue;  // not in the table: does not change the posterior
                }
                c.high_level[static_cast<size_t>(axis)] =
                    value_index(item.second, d.variable(axis));
              }
            }
            return c;
          },
          py::arg("eef"), py::arg("object"), py::arg("effect") = 0,
          py::arg("high_level") = py::none(), py::arg("effect_produced") = false,
          R"doc(A Context for this skill.

Parameters
----------
eef, object : array_like, shape (3,)
effect : int or str
    The wanted effect, by index or name.
high_level : dict of str to (int or str), optional
    High-level states by variable name, values by index or name; states that are not
    variables of the table are ignored (they do not change the posterior).
effect_produced : bool
)doc")
      .def("__repr__", [](const Skill& s) {
        return "<a2l.Skill '" + s.name() + "' " + std::to_string(s.n_variables()) + " variables, " +
               std::to_string(s.n_moves()) + " movements, " + std::to_string(s.table().n_rows()) +
               " rows>";
      });

  py::class_<TraceRecord>(m, "TraceRecord", "One step as the trace records it.")
      .def_readonly("step", &TraceRecord::step)
      .def_readonly("n_variables", &TraceRecord::n_variables)
      .def_property_readonly("bins",
                             [](const TraceRecord& r) {
                               return std::vector<int>(r.bins.begin(),
                                                       r.bins.begin() + r.n_variables);
                             })
      .def_readonly("movement", &TraceRecord::movement)
      .def_readonly("probability", &TraceRecord::probability)
      .def_readonly("status", &TraceRecord::status)
      .def_readonly("phase", &TraceRecord::phase)
      .def_readonly("fallback", &TraceRecord::fallback,
                    "True if the cell had no information and the movement is its fallback's.")
      .def("to_dict", &trace_dict);

  py::class_<StepOutput>(m, "StepOutput", "What step() returns.")
      .def(py::init<>())
      .def_readonly("status", &StepOutput::status)
      .def_readonly("movement", &StepOutput::movement)
      .def_readonly("probability", &StepOutput::probability)
      .def_readonly("displacement", &StepOutput::displacement)
      .def_readonly("action", &StepOutput::action)
      .def_readonly("record", &StepOutput::record);

  m.attr("CLEARANCE_RATIO") = kClearanceRatio;

  py::class_<SkillState>(m, "SkillState", R"doc(
The mutable state of one run of a skill (step counter, scratch buffers, trace ring buffer),
allocated once here.

Parameters
----------
skill : Skill
trace_capacity : int
    Records the ring buffer holds (oldest are overwritten).
)doc")
      .def(py::init([](const Skill& s, std::size_t cap) {
             if (!s.loaded()) raise(Status::not_initialized, "the skill is not loaded");
             return SkillState(s, cap);
           }),
           py::arg("skill"), py::arg("trace_capacity") = 1024)
      .def("reset", &SkillState::reset, "Start a new run (keeps the trace).")
      .def_property_readonly("steps", &SkillState::steps)
      .def_readwrite("smoothing", &SkillState::smoothing)
      .def_property_readonly("trace_size", &SkillState::trace_size)
      .def_property_readonly("trace_capacity", &SkillState::trace_capacity)
      .def_property_readonly("trace_dropped", &SkillState::trace_dropped)
      .def(
          "trace",
          [](const SkillState& st, const py::object& i) -> py::object {
            if (i.is_none()) {
              py::list out;
              for (std::size_t k = 0; k < st.trace_size(); ++k) out.append(py::cast(st.trace(k)));
              return std::move(out);
            }
            const auto k = i.cast<std::int64_t>();
            if (k < 0 || static_cast<std::size_t>(k) >= st.trace_size()) {
              raise(Status::invalid_argument, "trace index out of range");
            }
            return py::cast(st.trace(static_cast<std::size_t>(k)));
          },
          py::arg("i") = py::none(), "Record i (oldest first), or all records as a list.")
      .def("clear_trace", &SkillState::clear_trace);

  m.def(
      "step",
      [](const Skill& skill, SkillState& state, const Context& context) {
        StepOutput out;
        step(skill, state, context, out);
        return out;
      },
      py::arg("skill"), py::arg("state"), py::arg("context"), R"doc(
One step of a skill: context -> bins -> table -> movement (the C++ runtime's step()).

Returns
-------
StepOutput
    ``status`` is ``Status.ok`` with ``movement``, ``probability`` and ``displacement``
    (3,), or why the run stops: ``effect_produced``, ``step_cap``, ``unknown_context``
    (non-finite position, index out of range, uniform row without a fallback: never a
    guess). A uniform row with the skill's ``nearest`` or ``approach`` fallback is
    answered from its nearest informative cell (``record.fallback`` True).
)doc");

  m.attr("BUNDLE_SCHEMA_VERSION") = kBundleSchemaVersion;
  m.def(
      "load_bundle",
      [](const py::object& path) {
        const std::string p = py::str(py::module_::import("os").attr("fspath")(path));
        Skill s;
        Result r;
        {
          py::gil_scoped_release release;
          r = load_bundle(p, s);
        }
        check_bundle(r);
        return s;
      },
      py::arg("path"), R"doc(Load and validate a skill bundle file.

Raises
------
a2l.BundleError
    Malformed, corrupted or of another schema version (the message names the field or check).
a2l.A2LFileNotFoundError
    The file cannot be read.
)doc");
  m.def(
      "load_bundle_from_memory",
      [](const py::bytes& data, const std::string& source) {
        const std::string_view v = data;
        Skill s;
        Result r;
        {
          py::gil_scoped_release release;
          r = load_bundle_from_memory(reinterpret_cast<const std::uint8_t*>(v.data()), v.size(), s,
                                      source);
        }
        check_bundle(r);
        return s;
      },
      py::arg("data"), py::arg("source") = "<memory>",
      "Load and validate a skill bundle held in bytes; raises a2l.BundleError.");
  m.def(
      "bundle_crc32",
      [](const py::bytes& data) {
        const std::string_view v = data;
        return bundle_crc32(v.data(), v.size());
      },
      py::arg("data"), "zlib's CRC-32 of bytes.");
}

}  // namespace a2l::bindings
