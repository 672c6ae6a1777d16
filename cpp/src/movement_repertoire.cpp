#include "a2l/movement_repertoire.hpp"

#include <cmath>
#include <sstream>

namespace a2l {

const char* movement_action_name(MovementAction action) noexcept {
  switch (action) {
    case MovementAction::open:
      return "open";
    case MovementAction::close:
      return "close";
    case MovementAction::stay:
      return "stay";
    case MovementAction::none:
      break;
  }
  return "none";
}

bool parse_movement_action(const std::string& name, MovementAction& action) noexcept {
  for (MovementAction a : {MovementAction::open, MovementAction::close, MovementAction::stay}) {
    if (name == movement_action_name(a)) {
      action = a;
      return true;
    }
  }
  return false;
}

Result MovementRepertoire::create(double step, std::vector<Eigen::Vector3i> directions,
                                  std::vector<std::string> labels, MovementRepertoire& out,
                                  std::vector<MovementAction> actions) {
  if (!std::isfinite(step) || !(step > 0.0)) {
    std::ostringstream ss;
    ss << "movements.step: must be finite and > 0, got " << step;
    return Result::failure(Status::invalid_argument, ss.str());
  }
  if (directions.empty() || directions.size() + actions.size() > static_cast<size_t>(kMaxMoves)) {
    return Result::failure(Status::invalid_argument,
                           "movements.directions: needs 1 to " + std::to_string(kMaxMoves) +
                               " movements, got " + std::to_string(directions.size()) +
                               " directions and " + std::to_string(actions.size()) + " actions");
  }
  if (labels.empty()) {
    for (size_t i = 0; i < directions.size(); ++i) labels.push_back("m" + std::to_string(i));
  }
  if (labels.size() != directions.size()) {
    return Result::failure(Status::size_mismatch,
                           "movements.labels: " + std::to_string(labels.size()) + " labels for " +
                               std::to_string(directions.size()) + " directions");
  }
  std::vector<Eigen::Vector3d> displacements;
  displacements.reserve(directions.size() + actions.size());
  for (size_t i = 0; i < directions.size(); ++i) {
    const Eigen::Vector3i& d = directions[i];
    if ((d.array() < -1).any() || (d.array() > 1).any() || d.isZero()) {
      return Result::failure(Status::invalid_argument,
                             "movements.directions[" + std::to_string(i) +
                                 "]: entries must be signs in {-1, 0, 1}, not all zero");
    }
    const Eigen::Vector3d v = d.cast<double>();
    displacements.push_back(step * v / v.norm());
  }
  for (size_t j = 0; j < actions.size(); ++j) {
    const std::string field = "movements.actions[" + std::to_string(j) + "]";
    if (actions[j] != MovementAction::open && actions[j] != MovementAction::close &&
        actions[j] != MovementAction::stay) {
      return Result::failure(Status::invalid_argument,
                             field + ": not an action (open, close or stay)");
    }
    for (size_t k = 0; k < j; ++k) {
      if (actions[k] == actions[j]) {
        return Result::failure(Status::invalid_argument,
                               field + ": '" + movement_action_name(actions[j]) +
                                   "' repeats movements.actions[" + std::to_string(k) + "]");
      }
    }
    displacements.push_back(Eigen::Vector3d::Zero());
    labels.emplace_back(movement_action_name(actions[j]));
  }
  out.step_ = step;
  out.directions_ = std::move(directions);
  out.displacements_ = std::move(displacements);
  out.labels_ = std::move(labels);
  out.actions_ = std::move(actions);
  return Result::success();
}

}  // namespace a2l
