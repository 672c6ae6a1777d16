//! \file common.hpp
//! \brief Helpers shared by the bind_*.cpp files: status -> Python exception.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "a2l/status.hpp"

namespace a2l::bindings {

namespace py = pybind11;

//! Raise the Python exception that matches `status` (classes from a2l.errors), with
//! `message`. Never returns.
[[noreturn]] inline void raise(Status status, const std::string& message) {
  const char* cls = "A2LError";
  switch (status) {
    case Status::file_error:
      cls = "A2LFileNotFoundError";
      break;
    case Status::parse_error:
      cls = "URDFError";
      break;
    case Status::unknown_link:
      cls = "UnknownLinkError";
      break;
    case Status::size_mismatch:
    case Status::invalid_argument:
      cls = "A2LValueError";
      break;
    case Status::unreachable:
      cls = "IKError";
      break;
    case Status::checksum_mismatch:
    case Status::version_mismatch:
      cls = "BundleError";
      break;
    default:
      break;
  }
  py::object type = py::module_::import("a2l.errors").attr(cls);
  PyErr_SetString(type.ptr(), message.c_str());
  throw py::error_already_set();
}

//! Raise if `r` is a failure.
inline void check(const Result& r) {
  if (!r.ok()) raise(r.status, r.message);
}

//! Raise if a bundle failed to load: a missing file is an A2LFileNotFoundError, everything
//! else a BundleError.
inline void check_bundle(const Result& r) {
  if (r.ok()) return;
  const char* cls = r.status == Status::file_error ? "A2LFileNotFoundError" : "BundleError";
  py::object type = py::module_::import("a2l.errors").attr(cls);
  PyErr_SetString(type.ptr(), r.message.c_str());
  throw py::error_already_set();
}

}  // namespace a2l::bindings
