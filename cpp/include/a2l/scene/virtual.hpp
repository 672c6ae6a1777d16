//! \file scene/virtual.hpp
//! \brief METHOD.md's fast "virtual setup": a kinematic push model without physics
//! (docs/virtual_scene.md). Deterministic; bound to Python as a2l._core.VirtualScene.
#pragma once

#include <Eigen/Core>

#include "a2l/scene/scene.hpp"

namespace a2l {

//! Options of a VirtualScene.
struct VirtualSceneOptions {
  Eigen::Vector3d half_size{0.035, 0.0425, 0.04};  //!< half-extents of the box (m)
  double table_z = 0.0;                            //!< height of the table plane (m)
  double eef_radius = 0.01;  //!< the end-effector is a sphere of this radius (m)
  //! |dx| and |dy| closer than this (m) are a tie, resolved as x: a diagonal movement executed
  //! by a real controller (differential IK, within 1e-6 m) pushes like the exact diagonal.
  double tie_tolerance = 1e-5;
};

//! A box pushed by an end-effector point (docs/virtual_scene.md).
//!
//! move(d): the end-effector goes to p' = eef + d. If p' lies strictly inside the box grown
//! by eef_radius on every side, the box is pushed along the dominant planar axis
//! k = argmax(|dx|, |dy|) of d (x on a tie, within options.tie_tolerance) until its face touches p'
//! (+- eef_radius); the other coordinates are unchanged. A purely vertical displacement never moves
//! the box.
class VirtualScene final : public Scene {
 public:
  //! A scene with default options, eef and box at the origin.
  VirtualScene() = default;
  //! A scene with the given options.
  explicit VirtualScene(const VirtualSceneOptions& options) : options_(options) {}

  void reset(const Eigen::Vector3d& eef, const Eigen::Vector3d& object) override {
    eef_ = eef;
    object_ = object;
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

 private:
  VirtualSceneOptions options_;
  Eigen::Vector3d eef_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d object_ = Eigen::Vector3d::Zero();
};

}  // namespace a2l
