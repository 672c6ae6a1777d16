// Vectorised bindings of the context bins (discretizer.hpp: Discretizer::context_bin) and the
// effect classification (effects.hpp: classify_effect): the Python learning side
// (a2l.skills.bins, a2l.skills.effects) calls these, so each has one implementation.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "a2l/discretizer.hpp"
#include "a2l/effects.hpp"
#include "common.hpp"

namespace py = pybind11;

namespace a2l::bindings {

namespace {

using Points = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) {
    s += (i ? ", " : "") + std::to_string(a.shape(i));
  }
  return s + (a.ndim() == 1 ? ",)" : ")");
}

//! Number of points of `a`, which must be (n, 3) or (3,) (one point).
py::ssize_t n_points(const Points& a, const char* what) {
  if (a.ndim() == 1 && a.shape(0) == 3) return 1;
  if (a.ndim() == 2 && a.shape(1) == 3) return a.shape(0);
  raise(Status::size_mismatch,
        std::string(what) + " must have shape (n, 3) or (3,), got " + shape_of(a));
}

//! The variable of entry `where` of context_bins' list: a tuple (kind, n_bins, low, high) or
//! (kind, n_bins, low, high, edges), as Python gives it, unchecked.
Variable from_tuple(const py::sequence& t, const std::string& where) {
  if (t.size() != 4 && t.size() != 5) {
    raise(Status::invalid_argument, where +
                                        ": must be (kind, n_bins, low, high) or (kind, "
                                        "n_bins, low, high, edges), got " +
                                        std::to_string(t.size()) + " items");
  }
  Variable v;
  v.name = where;
  try {
    const auto kind_name = t[0].cast<std::string>();
    if (!parse_variable_kind(kind_name, v.kind) || !is_geometric(v.kind)) {
      raise(Status::invalid_argument, where +
                                          ": kind must be 'distance', 'orientation', "
                                          "'inclination', 'offset_x' or 'offset_y', got '" +
                                          kind_name + "'");
    }
    v.n_bins = t[1].cast<int>();
    v.low = t[2].cast<double>();
    v.high = t[3].cast<double>();
    if (t.size() == 5) v.edges = t[4].cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    raise(Status::invalid_argument, where +
                                        ": kind must be a str, n_bins an int, low and high "
                                        "numbers and edges a sequence of numbers");
  }
  return v;
}

//! The C++ variables of `variables`, validated (the message names the entry and the check).
std::vector<Variable> to_variables(const std::vector<py::sequence>& variables) {
  if (variables.size() > static_cast<size_t>(kMaxVariables)) {
    raise(Status::invalid_argument, "variables: at most " + std::to_string(kMaxVariables) +
                                        ", got " + std::to_string(variables.size()));
  }
  std::vector<Variable> out;
  for (size_t i = 0; i < variables.size(); ++i) {
    const std::string where = "variables[" + std::to_string(i) + "]";
    Variable v = from_tuple(variables[i], where);
    if (v.n_bins < 1 || v.n_bins > kMaxBins) {
      raise(Status::invalid_argument, where + ": n_bins must be in [1, " +
                                          std::to_string(kMaxBins) + "], got " +
                                          std::to_string(v.n_bins));
    }
    if (has_range(v.kind) && !(std::isfinite(v.low) && std::isfinite(v.high) && v.low < v.high)) {
      raise(Status::invalid_argument, where + ": need finite low < high, got [" +
                                          std::to_string(v.low) + ", " + std::to_string(v.high) +
                                          "]");
    }
    if (Result r = check_edges(v, where); !r.ok()) raise(Status::invalid_argument, r.message);
    out.push_back(std::move(v));
  }
  return out;
}

py::array_t<std::int32_t> context_bins(const Points& eef, const Points& object,
                                       const std::vector<py::sequence>& variables) {
  const py::ssize_t n = n_points(eef, "eef");
  if (n_points(object, "object") != n || eef.ndim() != object.ndim()) {
    raise(Status::size_mismatch,
          "eef and object shapes differ: " + shape_of(eef) + " vs " + shape_of(object));
  }
  const std::vector<Variable> vars = to_variables(variables);
  const auto m = static_cast<py::ssize_t>(vars.size());
  py::array_t<std::int32_t> out({n, m});
  const double* e = eef.data();
  const double* o = object.data();
  std::int32_t* b = out.mutable_data();
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) {
      const Eigen::Vector3d p(e[3 * i], e[3 * i + 1], e[3 * i + 2]);
      const Eigen::Vector3d q(o[3 * i], o[3 * i + 1], o[3 * i + 2]);
      for (py::ssize_t j = 0; j < m; ++j) {
        b[i * m + j] = Discretizer::context_bin(vars[static_cast<size_t>(j)], p, q);
      }
    }
  }
  return out;
}

py::array_t<std::int32_t> classify_effects(const Points& displacements, int n_effects,
                                           double threshold, double ratio) {
  const py::ssize_t n = n_points(displacements, "displacements");
  if (n_effects != 4 && n_effects != 8) {
    raise(Status::invalid_argument, "n_effects must be 4 or 8, got " + std::to_string(n_effects));
  }
  if (!(threshold >= 0.0)) {
    raise(Status::invalid_argument, "threshold must be >= 0, got " + std::to_string(threshold));
  }
  if (!(ratio >= 1.0)) {
    raise(Status::invalid_argument, "ratio must be >= 1, got " + std::to_string(ratio));
  }
  py::array_t<std::int32_t> out(n);
  const double* d = displacements.data();
  std::int32_t* c = out.mutable_data();
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) {
      const Eigen::Vector3d x(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
      c[i] = classify_effect(x, n_effects, threshold, ratio);
    }
  }
  return out;
}

}  // namespace

void bind_bins(py::module_& m) {
  m.def("context_bins", &context_bins, py::arg("eef"), py::arg("object"), py::arg("variables"),
        R"doc(
Context bins of n points: Discretizer::context_bin (the runtime's bin math) for each point
and variable.

Parameters
----------
eef, object : array_like, shape (n, 3) or (3,)
    End-effector and object positions (m).
variables : list of tuple
    ``(kind, n_bins, low, high)`` or ``(kind, n_bins, low, high, edges)`` of each context
    variable; kind is ``"distance"``, ``"orientation"``, ``"inclination"``, ``"offset_x"``
    or ``"offset_y"``; low and high (m) are read for a distance and the offsets only; edges
    (m; a distance only, optional, empty for none): the interior bin edges, finite, > 0 and
    strictly increasing, with n_bins = len(edges) + 1 (bin = the number of edges <= d).

Returns
-------
ndarray of int32, shape (n, len(variables))
    The bin of each point and variable, -1 where ``eef - object`` is not finite (an
    unknown context).

Raises
------
A2LValueError
    A shape is wrong, or a variable is invalid (the message names it).
)doc");
  m.def("classify_effects", &classify_effects, py::arg("displacements"), py::arg("n_effects") = 4,
        py::arg("threshold") = kEffectThreshold, py::arg("ratio") = kEffectRatio, R"doc(
classify_effect of n object displacements.

Parameters
----------
displacements : array_like, shape (n, 3) or (3,)
    Object displacements (m); z is ignored.
n_effects : {4, 8}
    Number of effects.
threshold : float
    Smallest planar displacement that is an effect (m), >= 0.
ratio : float
    Dominance ratio of an axis effect in 8-effect mode, >= 1.

Returns
-------
ndarray of int32, shape (n,)
    Effect index (left, right, close, far, then close_left, close_right, far_left,
    far_right), -1 for no effect or a non-finite displacement.

Raises
------
A2LValueError
    The shape is wrong, or n_effects, threshold or ratio is out of range.
)doc");
}

}  // namespace a2l::bindings
