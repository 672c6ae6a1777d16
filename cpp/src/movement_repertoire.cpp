#include "a2l/movement_repertoire.hpp"

#include <algorithm>
#include <array>
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

std::vector<Eigen::Vector3i> default_directions(bool planar) {
  // Sort key (as a2l.skills.MovementRepertoire documents it): number of non-zero signs, then
  // for each axis whether it is zero, then for each axis the negated sign.
  using Key = std::array<int, 7>;
  auto key = [](const Eigen::Vector3i& d) {
    Key k{};
    k[0] = (d.array() != 0).count();
    for (int i = 0; i < 3; ++i) {
      k[static_cast<size_t>(1 + i)] = d[i] == 0 ? 1 : 0;
      k[static_cast<size_t>(4 + i)] = -d[i];
    }
    return k;
  };
  std::vector<Eigen::Vector3i> dirs;
  for (int x = -1; x <= 1; ++x) {
    for (int y = -1; y <= 1; ++y) {
      for (int z = -1; z <= 1; ++z) {
        if ((x == 0 && y == 0 && z == 0) || (planar && z != 0)) continue;
        dirs.emplace_back(x, y, z);
      }
    }
  }
  std::sort(dirs.begin(), dirs.end(),
            [&](const Eigen::Vector3i& a, const Eigen::Vector3i& b) { return key(a) < key(b); });
  return dirs;
}

std::string direction_label(const Eigen::Vector3i& d) {
  std::string out;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0) continue;
    out += d[i] > 0 ? '+' : '-';
    out += "xyz"[i];
  }
  return out;
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
