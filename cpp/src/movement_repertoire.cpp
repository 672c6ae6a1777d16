#include "a2l/movement_repertoire.hpp"

#include <cmath>
#include <sstream>

namespace a2l {

Result MovementRepertoire::create(double step, std::vector<Eigen::Vector3i> directions,
                                  std::vector<std::string> labels, MovementRepertoire& out) {
  if (!std::isfinite(step) || !(step > 0.0)) {
    std::ostringstream ss;
    ss << "movements.step: must be finite and > 0, got " << step;
    return Result::failure(Status::invalid_argument, ss.str());
  }
  if (directions.empty() || directions.size() > static_cast<size_t>(kMaxMoves)) {
    return Result::failure(Status::invalid_argument,
                           "movements.directions: needs 1 to " + std::to_string(kMaxMoves) +
                               " movements, got " + std::to_string(directions.size()));
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
  displacements.reserve(directions.size());
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
  out.step_ = step;
  out.directions_ = std::move(directions);
  out.displacements_ = std::move(displacements);
  out.labels_ = std::move(labels);
  return Result::success();
}

}  // namespace a2l
