//! \file scene/scene.hpp
//! \brief What a skill runs against: an end-effector point and one box on a table, and the
//! effect classification of the box's displacement.
#pragma once

#include <Eigen/Core>

namespace a2l {

//! A scene with an end-effector point and one box (see scene/virtual.hpp, scene/bullet.hpp).
class Scene {
 public:
  virtual ~Scene() = default;
  //! Put the end-effector at `eef` and the box centre at `object` (m), both at rest.
  virtual void reset(const Eigen::Vector3d& eef, const Eigen::Vector3d& object) = 0;
  //! Move the end-effector by `displacement` (m); true if the box moved.
  virtual bool move(const Eigen::Vector3d& displacement) = 0;
  //! End-effector position (m).
  virtual Eigen::Vector3d eef_position() const = 0;
  //! Box centre (m).
  virtual Eigen::Vector3d object_position() const = 0;
};

//! Effect index of an object displacement, as a2l.skills.EffectDiscretizer: with 4 effects
//! (left = +y, right = -y, close = -x, far = +x, in this order) the dominant planar axis
//! decides; with 8, an axis effect needs that axis to move more than `ratio` times the
//! other, else it is a diagonal (4 close_left, 5 close_right, 6 far_left, 7 far_right).
//! \return the index, or -1 if the planar displacement is shorter than `threshold` (m) or
//!         not finite, or n_effects is neither 4 nor 8.
int classify_effect(const Eigen::Vector3d& displacement, int n_effects = 4, double threshold = 0.01,
                    double ratio = 3.0) noexcept;

}  // namespace a2l
