#include "a2l/effects.hpp"

#include <cmath>

namespace a2l {

namespace {

//! The push effects in classify_effect's index order.
constexpr const char* kEffectNames[kMaxPushEffects] = {
    "left", "right", "close", "far", "close_left", "close_right", "far_left", "far_right"};
//! Their planar directions (x, y).
constexpr double kEffectDirections[kMaxPushEffects][2] = {{0.0, 1.0}, {0.0, -1.0}, {-1.0, 0.0},
                                                          {1.0, 0.0}, {-1.0, 1.0}, {-1.0, -1.0},
                                                          {1.0, 1.0}, {1.0, -1.0}};

}  // namespace

Eigen::Vector3d retreat_offset() noexcept { return {-0.12, 0.0, 0.16}; }

const char* effect_name(int index) noexcept {
  return index >= 0 && index < kMaxPushEffects ? kEffectNames[index] : "none";
}

std::vector<std::string> effect_names(int n_effects) {
  if (n_effects != 4 && n_effects != 8) return {};
  return std::vector<std::string>(kEffectNames, kEffectNames + n_effects);
}

int effect_index(const std::string& name) noexcept {
  for (int i = 0; i < kMaxPushEffects; ++i) {
    if (name == kEffectNames[i]) return i;
  }
  return -1;
}

Eigen::Vector2d effect_direction(int index) noexcept {
  if (index < 0 || index >= kMaxPushEffects) return Eigen::Vector2d::Zero();
  return {kEffectDirections[index][0], kEffectDirections[index][1]};
}

int classify_effect(const Eigen::Vector3d& d, int n_effects, double threshold,
                    double ratio) noexcept {
  if (n_effects != 4 && n_effects != 8) return -1;
  const double dx = d.x(), dy = d.y();
  if (!std::isfinite(dx) || !std::isfinite(dy)) return -1;
  if (!(std::hypot(dx, dy) >= threshold)) return -1;
  const double ax = std::abs(dx), ay = std::abs(dy);
  const int x_axis = dx > 0 ? 3 : 2;  // far / close
  const int y_axis = dy > 0 ? 0 : 1;  // left / right
  int out = ax >= ay ? x_axis : y_axis;
  if (n_effects == 8 && !(ax > ratio * ay || ay > ratio * ax)) {
    out = 4 + (dx > 0 ? 2 : 0) + (dy > 0 ? 0 : 1);
  }
  return out;
}

TestOutcome push_test(const Eigen::Vector2d& produced, int index, double distance) noexcept {
  TestOutcome out;
  if (index < 0 || index >= 4) return out;
  const Eigen::Vector2d d = effect_direction(index);
  const double along = produced.x() * d.x() + produced.y() * d.y();
  const double across = std::abs(produced.x() * -d.y() + produced.y() * d.x());
  if (along >= distance) {
    out.done = true;
    out.success = along > across;
  } else {
    out.done = across >= distance;
  }
  return out;
}

bool stayed_away(const Eigen::Vector3d& eef, const Eigen::Vector3d& object,
                 const Eigen::Vector3d& moved, const Eigen::Vector3d& retreat, double radius,
                 double tolerance) noexcept {
  return (eef - object - retreat).norm() <= radius && moved.norm() < tolerance;
}

}  // namespace a2l
