//! \file scene/scene.hpp
//! \brief What a skill runs against: an end-effector point and one box on a table (the
//! effect classification of the box's displacement: effects.hpp).
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

}  // namespace a2l
