// Bindings of the skill runtime: Discretizer, PolicyTable, MovementRepertoire, Skill,
// SkillState, step() and the bundle loader (skill.hpp, bundle.hpp and their parts).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "a2l/bundle.hpp"
#include "a2l/discretizer.hpp"
#include "a2l/movement_repertoire.hpp"
#include "a2l/policy_table.hpp"
#include "a2l/skill.hpp"
#include "common.hpp"

namespace py = pybind11;

namespace a2l::bindings {
namespace {

std::vector<int> to_bins(const PolicyTable& t, const std::vector<int>& bins) {
  if (static_cast<int>(bins.size()) != t.n_axes()) {
    raise(Status::size_mismatch, "bins: expected " + std::to_string(t.n_axes()) +
                                     " entries (one per variable), got " +
                                     std::to_string(bins.size()));
  }
  return bins;
}

std::size_t checked_row(const PolicyTable& t, std::int64_t row) {
  if (row < 0 || static_cast<std::uint64_t>(row) >= t.n_rows()) {
    raise(Status::invalid_argument,
          "row " + std::to_string(row) + " is outside [0, " + std::to_string(t.n_rows()) + ")");
  }
  return static_cast<std::size_t>(row);
}

std::vector<py::ssize_t> table_shape(const PolicyTable& t, bool with_moves) {
  std::vector<py::ssize_t> s(t.shape().begin(), t.shape().end());
  if (with_moves) s.push_back(t.n_moves());
  return s;
}

// A read-only numpy view of a vector owned by `owner`.
template <typename T>
py::array view(const std::vector<T>& v, std::vector<py::ssize_t> shape, py::handle owner) {
  std::vector<py::ssize_t> strides(shape.size(), static_cast<py::ssize_t>(sizeof(T)));
  for (int i = static_cast<int>(shape.size()) - 2; i >= 0; --i) {
    strides[static_cast<size_t>(i)] =
        strides[static_cast<size_t>(i) + 1] * shape[static_cast<size_t>(i) + 1];
  }
  py::array a(py::dtype::of<T>(), shape, strides, v.data(), owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

py::dict trace_dict(const TraceRecord& r) {
  py::dict d;
  d["step"] = r.step;
  d["bins"] = std::vector<int>(r.bins.begin(), r.bins.begin() + r.n_variables);
  d["movement"] = r.movement;
  d["probability"] = r.probability;
  d["status"] = r.status;
  d["phase"] = r.phase;
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
  py::enum_<VariableKind>(m, "VariableKind", "What an evidence variable measures.")
      .value("effect", VariableKind::effect)
      .value("distance", VariableKind::distance)
      .value("orientation", VariableKind::orientation)
      .value("inclination", VariableKind::inclination)
      .value("high_level", VariableKind::high_level)
      .value("offset_x", VariableKind::offset_x)
      .value("offset_y", VariableKind::offset_y);

  py::enum_<Smoothing>(m, "Smoothing", "Smoothing choice of a run (SkillState.smoothing).")
      .value("from_skill", Smoothing::from_skill)
      .value("off", Smoothing::off)
      .value("on", Smoothing::on);

  py::class_<Variable>(m, "Variable", "One evidence variable (one axis of the policy table).")
      .def_readonly("name", &Variable::name)
      .def_readonly("kind", &Variable::kind)
      .def_readonly("n_bins", &Variable::n_bins)
      .def_readonly("low", &Variable::low)
      .def_readonly("high", &Variable::high)
      .def_readonly("values", &Variable::values)
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

  py::class_<PolicyTable>(m, "PolicyTable", "The compiled table P(move | evidence).")
      .def_property_readonly("n_axes", &PolicyTable::n_axes)
      .def_property_readonly("shape", &PolicyTable::shape, "Bins of each evidence axis.")
      .def_property_readonly("strides", &PolicyTable::strides, "Row stride of each axis.")
      .def_property_readonly("n_moves", &PolicyTable::n_moves)
      .def_property_readonly("n_rows", &PolicyTable::n_rows)
      .def(
          "posterior",
          [](const py::object& self) {
            const auto& t = self.cast<const PolicyTable&>();
            return view(t.posterior(), table_shape(t, true), self);
          },
          "The whole posterior, read-only, shape (*shape, n_moves).")
      .def(
          "argmax",
          [](const py::object& self, const py::object& row) -> py::object {
            const auto& t = self.cast<const PolicyTable&>();
            if (row.is_none()) return view(t.argmax(), table_shape(t, false), self);
            return py::int_(t.argmax(checked_row(t, row.cast<std::int64_t>())));
          },
          py::arg("row") = py::none(),
          "argmax(row) -> int (-1 = uniform); argmax() -> int32 array, shape (*shape,).")
      .def(
          "posterior_row",
          [](const PolicyTable& t, std::int64_t row) {
            const double* p = t.posterior_row(checked_row(t, row));
            return std::vector<double>(p, p + t.n_moves());
          },
          py::arg("row"), "P(move | evidence) of one row, length n_moves.")
      .def(
          "row_index",
          [](const PolicyTable& t, const std::vector<int>& bins) {
            const auto b = to_bins(t, bins);
            if (!t.in_range(b.data())) raise(Status::invalid_argument, "bins: out of range");
            return t.row_index(b.data());
          },
          py::arg("bins"), "Row of an evidence combination.")
      .def(
          "in_range",
          [](const PolicyTable& t, const std::vector<int>& bins) {
            return t.in_range(to_bins(t, bins).data());
          },
          py::arg("bins"))
      .def(
          "lookup",
          [](const PolicyTable& t, const std::vector<int>& bins) {
            return t.lookup(to_bins(t, bins).data());
          },
          py::arg("bins"), "Most probable movement of `bins`; -1 if uniform or out of range.");

  py::enum_<MovementAction>(m, "MovementAction",
                            "What a movement does besides a displacement (none for one).")
      .value("none", MovementAction::none)
      .value("open", MovementAction::open)
      .value("close", MovementAction::close)
      .value("stay", MovementAction::stay);
  m.def("movement_action_name", &movement_action_name, py::arg("action"),
        "The bundle name of an action ('open', 'close', 'stay'; 'none').");

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
      .def("to_dict", &trace_dict);

  py::class_<StepOutput>(m, "StepOutput", "What step() returns.")
      .def(py::init<>())
      .def_readonly("status", &StepOutput::status)
      .def_readonly("movement", &StepOutput::movement)
      .def_readonly("probability", &StepOutput::probability)
      .def_readonly("displacement", &StepOutput::displacement)
      .def_readonly("action", &StepOutput::action)
      .def_readonly("record", &StepOutput::record);

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
    (non-finite position, index out of range, uniform row: never a guess).
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
