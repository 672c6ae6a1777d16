#include "a2l/scene/virtual.hpp"

#include <cmath>

namespace a2l {

bool VirtualScene::in_contact(const Eigen::Vector3d& p) const noexcept {
  const Eigen::Vector3d rel = (p - object_).cwiseAbs();
  const Eigen::Vector3d grown = options_.half_size.array() + options_.eef_radius;
  return (rel.array() < grown.array()).all();
}

bool VirtualScene::set_gripper(bool closed) noexcept {
  if (!closed) {
    if (holding_) object_.z() = options_.table_z + options_.half_size.z();  // dropped
    gripper_closed_ = holding_ = false;
    return false;
  }
  if (!gripper_closed_ && options_.object_kind == ObjectKind::graspable) {
    const Eigen::Vector3d rel = (eef_ - object_).cwiseAbs();
    const Eigen::Vector3d reach = options_.half_size.array() + options_.grasp_margin;
    holding_ = eef_.allFinite() && (rel.array() <= reach.array()).all();
  }
  gripper_closed_ = true;
  return holding_;
}

bool VirtualScene::move(const Eigen::Vector3d& d) {
  const Eigen::Vector3d p = eef_ + d;
  eef_ = p;
  if (!p.allFinite()) return false;
  if (holding_) {
    object_ += d;
    return !d.isZero();
  }
  if (options_.object_kind == ObjectKind::button) {
    const Eigen::Vector3d rel = (p - object_).cwiseAbs();
    const double top = object_.z() + options_.half_size.z();
    const bool on = rel.x() < options_.half_size.x() + options_.eef_radius &&
                    rel.y() < options_.half_size.y() + options_.eef_radius &&
                    p.z() <= top + options_.eef_radius;
    if (on && !pressing_ && d.z() < 0.0) {
      light_on_ = !light_on_;
      ++presses_;
    }
    pressing_ = on;
    return false;
  }
  if ((d.x() == 0.0 && d.y() == 0.0) || !in_contact(p)) return false;
  if (options_.object_kind == ObjectKind::graspable && !gripper_closed_ &&
      std::abs(d.z()) >= std::hypot(d.x(), d.y())) {
    return false;  // the open fingers come down around the block
  }
  const int k = std::abs(d.x()) >= std::abs(d.y()) - options_.tie_tolerance ? 0 : 1;
  const double reach = options_.half_size[k] + options_.eef_radius;
  const double before = object_[k];
  object_[k] = d[k] > 0 ? p[k] + reach : p[k] - reach;
  return object_[k] != before;
}

}  // namespace a2l
