#include "a2l/status.hpp"

namespace a2l {

const char* status_name(Status status) noexcept {
  switch (status) {
    case Status::ok:
      return "ok";
    case Status::file_error:
      return "file_error";
    case Status::parse_error:
      return "parse_error";
    case Status::unknown_link:
      return "unknown_link";
    case Status::size_mismatch:
      return "size_mismatch";
    case Status::invalid_argument:
      return "invalid_argument";
    case Status::unreachable:
      return "unreachable";
    case Status::joint_limit:
      return "joint_limit";
    case Status::velocity_limit:
      return "velocity_limit";
    case Status::workspace_limit:
      return "workspace_limit";
    case Status::unknown_context:
      return "unknown_context";
    case Status::effect_produced:
      return "effect_produced";
    case Status::step_cap:
      return "step_cap";
    case Status::checksum_mismatch:
      return "checksum_mismatch";
    case Status::version_mismatch:
      return "version_mismatch";
    case Status::not_initialized:
      return "not_initialized";
    case Status::internal_error:
      return "internal_error";
    case Status::converged:
      return "converged";
  }
  return "unknown_status";
}

}  // namespace a2l
