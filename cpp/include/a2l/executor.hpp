//! \file executor.hpp
//! \brief Turns end-effector steps into joint commands, one control tick at a time, by
//! differential (Jacobian) inverse kinematics on a2l::Kinematics, with safety checks.
//!
//! Each tick moves a reference point toward the target by at most max_speed * period, and
//! solves the damped least-squares problem dq = J^T (J J^T + lambda^2 I)^-1 [dp; w] for the
//! position error dp and the orientation error w (the orientation at reset() is held, or the one
//! set_orientation() aims at; its correction per tick at most max_angular_speed * period).
//! A command over a joint's velocity limit is scaled down, every joint by the same factor (the
//! end-effector keeps its direction and slows down; the reference point advances by the same
//! share), as a robot's controller slows a motion near a singularity; with
//! ExecutorOptions::scale_velocity off it is refused instead (`velocity_limit`). On a chain of
//! more than 6 joints, a joint within ExecutorOptions::limit_band of a limit is pushed back
//! toward the interior in the task's null space (the end-effector's motion unchanged). A command is
//! checked against the joint position limits and the target against the workspace bounds; a
//! target that is not reached within the watchdog's tick budget stops with `unreachable`. tick()
//! allocates nothing and throws nothing (fixed-capacity Eigen objects).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>

#include "a2l/kinematics.hpp"
#include "a2l/status.hpp"

namespace a2l {

//! Options of an Executor.
struct ExecutorOptions {
  double period = 1e-3;              //!< control period (s); Baxter's is 1 ms
  double max_speed = 0.25;           //!< most end-effector speed (m/s)
  double damping = 1e-2;             //!< damped least-squares lambda
  double orientation_gain = 0.5;     //!< share of the orientation error corrected per tick
  double position_tolerance = 1e-6;  //!< a target is reached within this distance (m)
  double velocity_margin = 1.0;      //!< allowed share of the URDF joint velocity limits
  double limit_margin = 0.0;         //!< commands must stay this far inside the limits (rad)
  //! Workspace bounds of the end-effector target in the base frame (m).
  Eigen::Vector3d workspace_min =
      Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  //! Workspace bounds of the end-effector target in the base frame (m).
  Eigen::Vector3d workspace_max =
      Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  int watchdog_ticks = 20000;  //!< most ticks toward one target before `unreachable`
  //! most rotation the orientation correction asks for per second (rad/s); infinity: only
  //! orientation_gain limits it
  double max_angular_speed = std::numeric_limits<double>::infinity();
  //! a command over a joint's velocity limit is scaled down to it (every joint by the same
  //! factor: the end-effector slows and keeps its direction); false: it is refused
  //! (`velocity_limit`)
  bool scale_velocity = true;
  //! share of the range next to each joint limit where the joint is pushed back toward the
  //! interior, in the task's null space (the end-effector's motion unchanged)
  double limit_band = 0.1;
  //! how fast a joint at its limit is pushed back, as a share of its velocity limit (0: off);
  //! in [0, 1]
  double limit_avoidance = 0.5;
};

//! Differential-IK executor of end-effector position targets for one arm.
class Executor {
 public:
  //! An unusable executor; call init().
  Executor() = default;

  //! Bind to `kinematics` (kept by pointer: it must outlive the executor) and reset to q0.
  //! \return `not_initialized`, `size_mismatch`, `invalid_argument` (options or q0 outside
  //!         the limits) naming the problem, else `ok`.
  Result init(const Kinematics& kinematics, const Eigen::Ref<const Eigen::VectorXd>& q0,
              const ExecutorOptions& options = ExecutorOptions());

  //! Put the arm at q0, hold its current orientation, no target. No allocation.
  Status reset(const Eigen::Ref<const Eigen::VectorXd>& q0) noexcept;

  //! Aim at the orientation `rotation` (base frame) instead of the one held at reset(), until
  //! the next reset(); the correction turns the end-effector toward it at most
  //! max_angular_speed. reached() still says the position only. `invalid_argument` if
  //! `rotation` is not finite or not a rotation (orthonormal within 1e-6, determinant +1);
  //! the aim is then unchanged. No allocation.
  Status set_orientation(const Eigen::Matrix3d& rotation) noexcept;

  //! Aim at `position` (base frame, m). `workspace_limit` if outside the workspace bounds or
  //! not finite (the target is then unchanged).
  Status set_target(const Eigen::Vector3d& position) noexcept;

  //! One control tick: the next joint command into q() (unchanged on failure).
  //! \return `ok` (scaled to the velocity limits if it was over them), or `velocity_limit`
  //!         (over them, with ExecutorOptions::scale_velocity off) / `joint_limit` (the
  //!         command was refused),
  //!         `unreachable` (watchdog), `not_initialized`, `internal_error` (kinematics).
  Status tick() noexcept;

  //! True when the end-effector is within position_tolerance of the target.
  bool reached() const noexcept { return reached_; }
  //! The current joint command (rad).
  const JointVector& q() const noexcept { return q_; }
  //! The end-effector position at q() (base frame, m).
  Eigen::Vector3d position() const noexcept { return pose_.translation(); }
  //! The end-effector pose at q().
  const Eigen::Isometry3d& pose() const noexcept { return pose_; }
  //! The orientation aimed at (base frame).
  const Eigen::Matrix3d& orientation() const noexcept { return hold_; }
  //! The current target (base frame, m).
  const Eigen::Vector3d& target() const noexcept { return target_; }
  //! Ticks since the last set_target().
  int ticks() const noexcept { return ticks_; }
  //! Ticks since reset() whose command was scaled down to the joint velocity limits.
  long scaled_ticks() const noexcept { return scaled_ticks_; }
  //! The options.
  const ExecutorOptions& options() const noexcept { return options_; }

 private:
  //! The push away from the joint limits into `away` (n): a joint inside the band next to a
  //! limit (ExecutorOptions::limit_band) is pushed toward the interior, the deeper the faster
  //! (at most ExecutorOptions::limit_avoidance of its velocity limit); false (`away` zero)
  //! when no joint is in a band, the push is off, or the chain has no null space beside the
  //! 6-D task (6 joints or fewer).
  bool limit_push(JointVector& away) const noexcept;

  const Kinematics* kin_ = nullptr;
  ExecutorOptions options_;
  JointVector q_, lower_, upper_, max_step_;
  Jacobian jac_;
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();
  Eigen::Matrix3d hold_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d target_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d reference_ = Eigen::Vector3d::Zero();
  int ticks_ = 0;
  long scaled_ticks_ = 0;
  bool reached_ = true;
};

}  // namespace a2l
