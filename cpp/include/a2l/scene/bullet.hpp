//! \file scene/bullet.hpp
//! \brief A physics scene with Debian's Bullet: a static table, a dynamic box and a
//! kinematic sphere as the end-effector proxy. Available when the core was built with
//! Bullet (A2L_HAVE_BULLET, set by CMake when find_package(Bullet) succeeds).
#pragma once

#include <Eigen/Core>
#include <memory>

#include "a2l/scene/scene.hpp"

namespace a2l {

//! Options of a BulletScene.
struct BulletSceneOptions {
  Eigen::Vector3d half_size{0.035, 0.0425, 0.04};  //!< half-extents of the box (m)
  double table_z = 0.0;                            //!< height of the table's top face (m)
  double eef_radius = 0.01;                        //!< radius of the end-effector sphere (m)
  double box_mass = 0.5;                           //!< kg
  double friction = 0.5;                           //!< friction of table, box and end-effector
  double time_step = 1.0 / 240;                    //!< physics step (s)
  double eef_speed = 0.25;                         //!< end-effector speed during move() (m/s)
  int settle_steps = 120;         //!< most physics steps to let the box come to rest
  double moved_threshold = 1e-3;  //!< planar box displacement that counts as moved (m)
};

//! True if this build has the Bullet scene.
bool bullet_scene_available() noexcept;

#if A2L_HAVE_BULLET
//! Table + box + kinematic end-effector sphere in a Bullet dynamics world.
//!
//! move(d) drives the end-effector along d at options.eef_speed (one physics step per
//! eef_speed * time_step of travel), then steps until the box rests (at most settle_steps);
//! it returns true if the box's centre moved more than moved_threshold in the table plane.
class BulletScene final : public Scene {
 public:
  //! A scene with the given options; the box rests on the table at the origin.
  explicit BulletScene(const BulletSceneOptions& options = BulletSceneOptions());
  ~BulletScene() override;
  BulletScene(const BulletScene&) = delete;
  BulletScene& operator=(const BulletScene&) = delete;

  //! Put the eef at `eef` and the box (unrotated, at rest) with its centre at `object`.
  void reset(const Eigen::Vector3d& eef, const Eigen::Vector3d& object) override;
  bool move(const Eigen::Vector3d& displacement) override;
  Eigen::Vector3d eef_position() const override;
  Eigen::Vector3d object_position() const override;
  //! Physics steps taken since construction.
  long long physics_steps() const noexcept;
  //! The options.
  const BulletSceneOptions& options() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};
#endif

}  // namespace a2l
