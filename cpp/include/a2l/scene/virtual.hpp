//! \file scene/virtual.hpp
//! \brief The fast "virtual setup": a kinematic model without physics of a box pushed
//! by the end-effector, a block the gripper grasps, or a button toggling a light
//! (docs/virtual_scene.md). Deterministic; bound to Python as a2l._core.VirtualScene.
#pragma once

#include <Eigen/Core>

#include "a2l/scene/scene.hpp"

namespace a2l {

//! What the scene's object is (docs/virtual_scene.md).
enum class ObjectKind : int {
  box = 0,        //!< pushed by the end-effector
  graspable = 1,  //!< pushed too, and held by a closed gripper that reached it
  button = 2,     //!< fixed; the end-effector going down on it toggles the light
};

//! Options of a VirtualScene.
struct VirtualSceneOptions {
  Eigen::Vector3d half_size{0.035, 0.0425, 0.04};  //!< half-extents of the box (m)
  double table_z = 0.0;                            //!< height of the table plane (m)
  double eef_radius = 0.01;  //!< the end-effector is a sphere of this radius (m)
  //! |dx| and |dy| closer than this (m) are a tie, resolved as x: a diagonal movement executed
  //! by a real controller (differential IK, within 1e-6 m) pushes like the exact diagonal.
  double tie_tolerance = 1e-5;
  ObjectKind object_kind = ObjectKind::box;  //!< the object's semantics
  //! graspable: closing the gripper holds the object when the end-effector lies within the
  //! object's box grown by this margin on every side (m).
  double grasp_margin = 0.01;
};

//! A box pushed by an end-effector point, a graspable block or a button (docs/virtual_scene.md).
//!
//! move(d): the end-effector goes to p' = eef + d. A held object moves with it. Otherwise, if p'
//! lies strictly inside the box grown by eef_radius on every side, the box is pushed along the
//! dominant planar axis k = argmax(|dx|, |dy|) of d (x on a tie, within options.tie_tolerance)
//! until its face touches p' (+- eef_radius); the other coordinates are unchanged. A purely
//! vertical displacement never moves the box, nor (graspable, gripper open) one going down at
//! least as much as sideways, |dz| >= |(dx, dy)| (the open fingers come down around it). A
//! button never moves: p' on its top (within the footprint grown by eef_radius, at most
//! eef_radius above the top face) reached by a downward displacement toggles the light, once
//! until the end-effector leaves it.
class VirtualScene final : public Scene {
 public:
  //! A scene with default options, eef and box at the origin.
  VirtualScene() = default;
  //! A scene with the given options.
  explicit VirtualScene(const VirtualSceneOptions& options) : options_(options) {}

  //! Put the eef and the object back; gripper open, nothing held, the button released (the
  //! light and the press count are kept: see set_light()).
  void reset(const Eigen::Vector3d& eef, const Eigen::Vector3d& object) override {
    eef_ = eef;
    object_ = object;
    gripper_closed_ = holding_ = pressing_ = false;
  }
  bool move(const Eigen::Vector3d& displacement) override;
  Eigen::Vector3d eef_position() const override { return eef_; }
  Eigen::Vector3d object_position() const override { return object_; }

  //! Half-extents of the box (m).
  const Eigen::Vector3d& half_size() const noexcept { return options_.half_size; }
  //! Height of the table plane (m).
  double table_z() const noexcept { return options_.table_z; }
  //! Radius of the end-effector sphere (m).
  double eef_radius() const noexcept { return options_.eef_radius; }
  //! |dx| and |dy| closer than this (m) are a tie (pushed along x).
  double tie_tolerance() const noexcept { return options_.tie_tolerance; }
  //! True if `p` lies strictly inside the box grown by eef_radius.
  bool in_contact(const Eigen::Vector3d& p) const noexcept;

  //! Close (or open) the gripper. Closing holds a graspable object when the end-effector lies
  //! within its box grown by grasp_margin; opening releases it onto the table plane.
  //! \return true if the object is held afterwards. No allocation.
  bool set_gripper(bool closed) noexcept;
  //! True when the gripper is closed.
  bool gripper_closed() const noexcept { return gripper_closed_; }
  //! True when the closed gripper holds the object.
  bool holding() const noexcept { return holding_; }
  //! The light (toggled by pressing a button).
  bool light_on() const noexcept { return light_on_; }
  //! Set the light.
  void set_light(bool on) noexcept { light_on_ = on; }
  //! Presses of the button since construction.
  int presses() const noexcept { return presses_; }
  //! The object's semantics.
  ObjectKind object_kind() const noexcept { return options_.object_kind; }

 private:
  VirtualSceneOptions options_;
  Eigen::Vector3d eef_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d object_ = Eigen::Vector3d::Zero();
  bool gripper_closed_ = false, holding_ = false, pressing_ = false, light_on_ = false;
  int presses_ = 0;
};

}  // namespace a2l
