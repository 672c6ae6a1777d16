// Bindings of the compiled policy table (policy_table.hpp): PolicyTable, its posterior and
// argmax as read-only numpy views.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <string>
#include <vector>

#include "a2l/policy_table.hpp"
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

}  // namespace

void bind_policy_table(py::module_& m) {
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
}

}  // namespace a2l::bindings
