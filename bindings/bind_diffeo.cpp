// Bindings of the diffeomorphic DS (diffeo.hpp): the class DiffeoDS for d = 2 and d = 3, its
// per-query timing, and the loader of a bundle's DS section.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "a2l/bundle.hpp"
#include "a2l/diffeo.hpp"
#include "common.hpp"

namespace py = pybind11;

namespace a2l::bindings {
namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A DS of dimension 2 or 3 and the description it was built from.
struct PyDiffeo {
  DiffeoMaps maps;
  DiffeoDS<2> d2;
  DiffeoDS<3> d3;
};

PyDiffeo make_ds(DiffeoMaps maps, double negligible = kDiffeoNegligible) {
  PyDiffeo p;
  Result r = maps.dim == 3 ? DiffeoDS<3>::create(maps, p.d3, negligible)
                           : DiffeoDS<2>::create(maps, p.d2, negligible);
  check(r);
  p.maps = std::move(maps);
  return p;
}

std::string shape_str(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) {
    s += (i ? ", " : "") + std::to_string(a.shape(i));
  }
  return s + (a.ndim() == 1 ? ",)" : ")");
}

std::vector<double> flat(const Array& a) {
  return std::vector<double>(a.data(), a.data() + a.size());
}

DiffeoDirection parse_direction(const std::string& direction) {
  if (direction == "to_demo") return DiffeoDirection::to_demo;
  if (direction == "to_line") return DiffeoDirection::to_line;
  raise(Status::invalid_argument,
        "diffeomorphic DS: direction must be 'to_demo' or 'to_line', got '" + direction + "'");
}

PyDiffeo from_arrays(const Array& target, const Array& centers, const Array& vectors,
                     const Array& rhos, double speed, double negligible,
                     const std::string& direction) {
  const DiffeoDirection dir = parse_direction(direction);
  if (target.ndim() != 1 || (target.shape(0) != 2 && target.shape(0) != 3)) {
    raise(Status::size_mismatch,
          "diffeomorphic DS: target must have shape (2,) or (3,), got " + shape_str(target));
  }
  const py::ssize_t d = target.shape(0);
  if (rhos.ndim() != 1) {
    raise(Status::size_mismatch,
          "diffeomorphic DS: rhos must have shape (K,), got " + shape_str(rhos));
  }
  const py::ssize_t k = rhos.shape(0);
  const std::string want = "(" + std::to_string(k) + ", " + std::to_string(d) + ")";
  if (centers.ndim() != 2 || centers.shape(0) != k || centers.shape(1) != d) {
    raise(Status::size_mismatch, "diffeomorphic DS: centers must have shape " + want +
                                     " (K from rhos, d from target), got " + shape_str(centers));
  }
  if (vectors.ndim() != 2 || vectors.shape(0) != k || vectors.shape(1) != d) {
    raise(Status::size_mismatch, "diffeomorphic DS: vectors must have shape " + want +
                                     " (K from rhos, d from target), got " + shape_str(vectors));
  }
  DiffeoMaps m;
  m.dim = static_cast<int>(d);
  m.target = flat(target);
  m.centers = flat(centers);
  m.vectors = flat(vectors);
  m.rhos = flat(rhos);
  m.speed = speed;
  m.direction = dir;
  return make_ds(std::move(m), negligible);
}

// Apply `f(in, out) -> Status` (D doubles each) to x of shape (d,) or (M, d); out has the shape
// of x with `extra` appended (d for a Jacobian).
template <int D, class F>
py::array_t<double> per_point(const Array& x, const char* what, bool jac, F f) {
  const bool single = x.ndim() == 1;
  if (!((single && x.shape(0) == D) || (x.ndim() == 2 && x.shape(1) == D))) {
    raise(Status::size_mismatch, std::string(what) + ": x must have shape (" + std::to_string(D) +
                                     ",) or (M, " + std::to_string(D) + "), got " + shape_str(x));
  }
  const py::ssize_t n = single ? 1 : x.shape(0);
  std::vector<py::ssize_t> shape;
  if (!single) shape.push_back(n);
  shape.push_back(D);
  if (jac) shape.push_back(D);
  py::array_t<double> out(shape);
  const double* in = x.data();
  double* o = out.mutable_data();
  const py::ssize_t out_stride = jac ? D * D : D;
  py::ssize_t bad = -1;
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) {
      if (f(in + i * D, o + i * out_stride) != Status::ok) {
        bad = i;
        break;
      }
    }
  }
  if (bad >= 0) {
    raise(Status::invalid_argument,
          std::string(what) + ": " +
              (single ? std::string("x") : "x[" + std::to_string(bad) + "]") +
              " is not finite (or the result overflows)");
  }
  return out;
}

template <int D>
py::array_t<double> eval(const DiffeoDS<D>& ds, const Array& x, const std::string& op) {
  using Vec = typename DiffeoDS<D>::Vec;
  using Mat = typename DiffeoDS<D>::Mat;
  if (op == "forward") {
    return per_point<D>(x, "forward", false, [&](const double* in, double* o) {
      Vec y;
      const Status s = ds.forward(Eigen::Map<const Vec>(in), y);
      Eigen::Map<Vec> out(o);
      out = y;
      return s;
    });
  }
  if (op == "inverse") {
    return per_point<D>(x, "inverse", false, [&](const double* in, double* o) {
      Vec y;
      const Status s = ds.inverse(Eigen::Map<const Vec>(in), y);
      Eigen::Map<Vec> out(o);
      out = y;
      return s;
    });
  }
  if (op == "velocity") {
    return per_point<D>(x, "velocity", false, [&](const double* in, double* o) {
      Vec y;
      const Status s = ds.velocity(Eigen::Map<const Vec>(in), y);
      Eigen::Map<Vec> out(o);
      out = y;
      return s;
    });
  }
  return per_point<D>(x, "jacobian", true, [&](const double* in, double* o) {
    Vec y;
    Mat j;
    const Status s = ds.jacobian(Eigen::Map<const Vec>(in), y, j);
    // row-major (d, d) output
    Eigen::Map<Eigen::Matrix<double, D, D, Eigen::RowMajor>> out(o);
    out = j;
    return s;
  });
}

py::array_t<double> dispatch(const PyDiffeo& p, const Array& x, const std::string& op) {
  return p.maps.dim == 3 ? eval<3>(p.d3, x, op) : eval<2>(p.d2, x, op);
}

template <int D>
py::array_t<double> rollout_d(const DiffeoDS<D>& ds, const Array& x0, double dt, std::int64_t steps,
                              DiffeoIntegrator method) {
  using Vec = typename DiffeoDS<D>::Vec;
  if (x0.ndim() != 1 || x0.shape(0) != D) {
    raise(Status::size_mismatch,
          "rollout: x0 must have shape (" + std::to_string(D) + ",), got " + shape_str(x0));
  }
  if (steps < 1) raise(Status::invalid_argument, "rollout: steps must be >= 1");
  if (!(dt > 0.0) || !std::isfinite(dt)) raise(Status::invalid_argument, "rollout: dt must be > 0");
  std::vector<Vec> out(static_cast<std::size_t>(steps));
  const Vec start = Eigen::Map<const Vec>(x0.data());
  Status s;
  {
    py::gil_scoped_release release;
    s = ds.rollout(start, dt, out.size(), out.data(), method);
  }
  if (s != Status::ok) {
    raise(s, "rollout: x0 is not finite or the state overflowed (" + std::string(status_name(s)) +
                 ")");
  }
  py::array_t<double> a({static_cast<py::ssize_t>(steps), static_cast<py::ssize_t>(D)});
  double* o = a.mutable_data();
  for (std::size_t i = 0; i < out.size(); ++i) {
    Eigen::Map<Vec> row(o + i * D);
    row = out[i];
  }
  return a;
}

template <int D>
py::dict timing_d(const DiffeoDS<D>& ds, const Array& points, int repeats) {
  if (points.ndim() != 2 || points.shape(1) != D) {
    raise(Status::size_mismatch, "time_velocity: points must have shape (M, " + std::to_string(D) +
                                     "), got " + shape_str(points));
  }
  DiffeoTiming t;
  Result r;
  {
    py::gil_scoped_release release;
    r = time_velocity<D>(ds, points.data(), static_cast<std::size_t>(points.shape(0)), repeats, t);
  }
  check(r);
  py::dict d;
  d["median_ns"] = t.median_ns;
  d["p999_ns"] = t.p999_ns;
  d["mean_ns"] = t.mean_ns;
  d["max_ns"] = t.max_ns;
  d["n"] = t.n;
  return d;
}

py::array_t<double> as_array(const std::vector<double>& v, std::vector<py::ssize_t> shape) {
  py::array_t<double> a(shape);
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

DiffeoIntegrator parse_method(const std::string& method) {
  if (method == "exact") return DiffeoIntegrator::exact;
  if (method == "euler") return DiffeoIntegrator::euler;
  if (method == "rk4") return DiffeoIntegrator::rk4;
  raise(Status::invalid_argument,
        "rollout: method must be 'exact', 'euler' or 'rk4', got '" + method + "'");
}

}  // namespace

void bind_diffeo(py::module_& m) {
  m.attr("DIFFEO_INVERTIBILITY_BOUND") = kDiffeoInvertibilityBound;
  m.attr("DIFFEO_MAX_ITERATIONS") = kDiffeoMaxIterations;
  m.attr("DIFFEO_NEGLIGIBLE") = kDiffeoNegligible;
  m.attr("DIFFEO_UNDERFLOW") = kDiffeoUnderflow;
  py::class_<PyDiffeo>(m, "DiffeoDS", R"doc(
Diffeomorphic dynamical system (fast diffeomorphic matching), evaluated in C++.

C = psi_{K-1} o ... o psi_0 with psi_i(x) = x + exp(-rho_i^2 ||x - c_i||^2) v_i; Phi = C
(direction "to_demo") or Phi = C^{-1} ("to_line"); the DS x_dot = speed * J_Phi(z) (target - z),
z = Phi^{-1}(x), globally stable at ``target``.

Parameters
----------
target : array_like, shape (d,)
    The attractor, d in {2, 3}.
centers, vectors : array_like, shape (K, d)
    Centers c_i and displacements v_i of the K maps (applied in index order).
rhos : array_like, shape (K,)
    Inverse widths rho_i >= 0, with rho_i ||v_i|| < sqrt(e/2) (invertibility).
speed : float
    Gain (> 0) of the line-space system z_dot = -speed (z - target).
negligible : float
    Cutoff t in [DIFFEO_NEGLIGIBLE, DIFFEO_UNDERFLOW] (40 and 746): a map is skipped where its
    weight is below exp(-t). The default changes results by less than double precision;
    DIFFEO_UNDERFLOW skips only weights that underflow (to measure what the cutoff saves).
direction : str
    ``"to_demo"`` (the maps carry the line space onto the demonstration: a velocity query
    solves K scalar equations) or ``"to_line"`` (they carry the demonstration onto the line:
    a velocity query is explicit, one forward sweep and one d x d solve).

Raises
------
a2l.A2LValueError
    Wrong shapes, non-finite values, or a map breaking the bound (the message names the first
    bad map's index).
)doc")
      .def(py::init(&from_arrays), py::arg("target"), py::arg("centers"), py::arg("vectors"),
           py::arg("rhos"), py::arg("speed") = 1.0, py::arg("negligible") = kDiffeoNegligible,
           py::arg("direction") = "to_demo")
      .def(
          "forward", [](const PyDiffeo& p, const Array& x) { return dispatch(p, x, "forward"); },
          py::arg("x"), "y = Phi(x); x (d,) or (M, d) -> same shape.")
      .def(
          "inverse", [](const PyDiffeo& p, const Array& y) { return dispatch(p, y, "inverse"); },
          py::arg("y"), "x = Phi^{-1}(y); y (d,) or (M, d) -> same shape.")
      .def(
          "velocity", [](const PyDiffeo& p, const Array& x) { return dispatch(p, x, "velocity"); },
          py::arg("x"), "The DS's velocity; x (d,) or (M, d) -> same shape.")
      .def(
          "jacobian", [](const PyDiffeo& p, const Array& x) { return dispatch(p, x, "jacobian"); },
          py::arg("x"), "dPhi/dx at x; x (d,) -> (d, d), (M, d) -> (M, d, d).")
      .def(
          "rollout",
          [](const PyDiffeo& p, const Array& x0, double dt, std::int64_t steps,
             const std::string& method) {
            const DiffeoIntegrator how = parse_method(method);
            return p.maps.dim == 3 ? rollout_d<3>(p.d3, x0, dt, steps, how)
                                   : rollout_d<2>(p.d2, x0, dt, steps, how);
          },
          py::arg("x0"), py::arg("dt"), py::arg("steps"), py::arg("method") = "exact", R"doc(
A trajectory from x0: row i is the state at time i * dt (row 0 = x0), shape (steps, d).

``method``: ``"exact"`` (default) follows the exact flow z(t) = target + (z0 - target)
exp(-speed t) mapped through Phi (no integration error); ``"euler"`` and ``"rk4"`` integrate
x_dot = f(x) with step dt.
)doc")
      .def(
          "time_velocity",
          [](const PyDiffeo& p, const Array& points, int repeats) {
            return p.maps.dim == 3 ? timing_d<3>(p.d3, points, repeats)
                                   : timing_d<2>(p.d2, points, repeats);
          },
          py::arg("points"), py::arg("repeats") = 1, R"doc(
Time velocity() per query in C++ (std::chrono::steady_clock around each call).

Returns
-------
dict
    ``median_ns``, ``p999_ns``, ``mean_ns``, ``max_ns`` and ``n`` (M * repeats timed queries,
    after one untimed warm-up pass over the M points).
)doc")
      .def_property_readonly("dim", [](const PyDiffeo& p) { return p.maps.dim; })
      .def_property_readonly(
          "negligible",
          [](const PyDiffeo& p) { return p.maps.dim == 3 ? p.d3.negligible() : p.d2.negligible(); })
      .def_property_readonly("n_maps", [](const PyDiffeo& p) { return p.maps.n_maps(); })
      .def_property_readonly(
          "direction",
          [](const PyDiffeo& p) { return std::string(diffeo_direction_name(p.maps.direction)); })
      .def_property_readonly("speed", [](const PyDiffeo& p) { return p.maps.speed; })
      .def_property_readonly(
          "target", [](const PyDiffeo& p) { return as_array(p.maps.target, {p.maps.dim}); })
      .def_property_readonly("centers",
                             [](const PyDiffeo& p) {
                               return as_array(p.maps.centers, {p.maps.n_maps(), p.maps.dim});
                             })
      .def_property_readonly("vectors",
                             [](const PyDiffeo& p) {
                               return as_array(p.maps.vectors, {p.maps.n_maps(), p.maps.dim});
                             })
      .def_property_readonly(
          "rhos", [](const PyDiffeo& p) { return as_array(p.maps.rhos, {p.maps.n_maps()}); })
      .def("__repr__", [](const PyDiffeo& p) {
        return "<a2l._core.DiffeoDS d=" + std::to_string(p.maps.dim) +
               ", K=" + std::to_string(p.maps.n_maps()) + ", " +
               diffeo_direction_name(p.maps.direction) + ">";
      });

  m.def(
      "load_ds",
      [](const py::object& path) {
        const std::string s = py::str(py::module_::import("os").attr("fspath")(path));
        DiffeoMaps maps;
        Result r;
        {
          py::gil_scoped_release release;
          r = load_ds_bundle(s, maps);
        }
        check_bundle(r);
        return make_ds(std::move(maps));
      },
      py::arg("path"), R"doc(Load the DS of a bundle file (kind "ds", or a skill with a DS).

Raises
------
a2l.BundleError
    Malformed, corrupted, of another schema version, without a DS, or a map breaking the
    invertibility bound (the message names the field or the map's index).
a2l.A2LFileNotFoundError
    The file cannot be read.
)doc");
  m.def(
      "load_ds_from_memory",
      [](const py::bytes& data, const std::string& source) {
        const std::string_view v = data;
        DiffeoMaps maps;
        Result r;
        {
          py::gil_scoped_release release;
          r = load_ds_bundle_from_memory(reinterpret_cast<const std::uint8_t*>(v.data()), v.size(),
                                         maps, source);
        }
        check_bundle(r);
        return make_ds(std::move(maps));
      },
      py::arg("data"), py::arg("source") = "<memory>",
      "Load the DS of bundle bytes; raises a2l.BundleError naming the field or the map.");
}

}  // namespace a2l::bindings
