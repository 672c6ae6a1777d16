//! \file status.hpp
//! \brief Status codes shared by the whole C++ core.
//!
//! Nothing in the core throws across its API: functions return a `Status` (real-time path)
//! or a `Result` (a status plus a human-readable message, for loading and set-up).
#pragma once

#include <string>

namespace a2l {

//! Outcome of a call into the core. `ok` is zero; everything else is a failure whose
//! meaning is given by its name.
enum class Status : int {
  ok = 0,             //!< success
  file_error,         //!< a file is missing or unreadable
  parse_error,        //!< a file is malformed (URDF, bundle, ...)
  unknown_link,       //!< a link name is not in the robot description
  size_mismatch,      //!< a vector or matrix has the wrong size
  invalid_argument,   //!< an argument is out of its domain (NaN, negative, ...)
  unreachable,        //!< inverse kinematics found no solution within the limits
  joint_limit,        //!< a command would leave the joint limits
  velocity_limit,     //!< a command would exceed the joint velocity limits
  workspace_limit,    //!< a command would leave the workspace bounds
  unknown_context,    //!< the skill has no information for this context
  effect_produced,    //!< the wanted effect was produced (a skill's normal end)
  step_cap,           //!< the skill reached its step cap
  checksum_mismatch,  //!< a stored checksum does not match the data
  version_mismatch,   //!< a file has a schema version this build does not read
  not_initialized,    //!< an object was used before it was loaded
  internal_error,     //!< a bug: please report it
  converged,          //!< a DS phase reached its target (within tolerance, no end action)
};

//! The snake_case name of a status, e.g. "unknown_link". Never allocates.
const char* status_name(Status status) noexcept;

//! A status with a message naming the file, the link, the field or the sizes involved.
struct Result {
  Status status = Status::ok;  //!< what happened
  std::string message;         //!< why, for a human; empty on success

  //! True on success.
  bool ok() const noexcept { return status == Status::ok; }
  //! A successful result.
  static Result success() { return Result{}; }
  //! A failed result.
  static Result failure(Status s, std::string msg) { return Result{s, std::move(msg)}; }
};

}  // namespace a2l
