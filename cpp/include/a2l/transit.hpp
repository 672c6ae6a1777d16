//! \file transit.hpp
//! \brief Collision-free transit of an arm between two joint configurations: OMPL's
//! RRT-Connect in joint space, checked with a CollisionModel, shortened, and time-parameterised
//! within joint velocity and acceleration limits.
//!
//! The path is a polyline in joint space whose every edge was checked for collisions at a
//! joint-space resolution (TransitOptions::resolution). The trajectory follows that polyline
//! exactly: on each edge a trapezoidal (or triangular) velocity profile, synchronised over the
//! joints, from rest to rest, so that no joint exceeds its velocity or acceleration limit and
//! the arm never leaves the checked edges. Available when the core was built with Bullet and
//! OMPL (A2L_HAVE_BULLET, A2L_HAVE_OMPL).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>

#include "a2l/collision_model.hpp"

namespace a2l {

//! Outcome of one TransitPlanner::plan() call.
enum class TransitStatus : int {
  ok = 0,               //!< a collision-free path and its trajectory
  invalid_argument,     //!< a size, NaN or option out of its domain (message says which)
  start_out_of_limits,  //!< the start violates the joint limits
  goal_out_of_limits,   //!< the goal violates the joint limits
  start_in_collision,   //!< the start collides (the message names the pair)
  goal_in_collision,    //!< the goal collides (the message names the pair)
  no_path,              //!< no collision-free path found within the time limit
};

//! The snake_case name of a transit status, e.g. "goal_in_collision".
const char* transit_status_name(TransitStatus status) noexcept;

//! True if this build has the transit planner (Bullet and OMPL).
bool transit_available() noexcept;

//! Options of TransitPlanner::plan().
struct TransitOptions {
  double time_limit = 1.0;   //!< s: the search stops at 90 % of it, the shortening at it
  double resolution = 0.01;  //!< rad: longest joint-space step between collision checks
  //! rad: the search and the shortening check motions this coarsely (a path found is then
  //! checked at `resolution`, and searched again at `resolution` if that check fails);
  //! 0 or <= resolution: everything at `resolution`
  double coarse_resolution = 0.05;
  bool shorten = true;       //!< shortcut and reduce the path (OMPL's PathSimplifier)
  int shortcut_rounds = 20;  //!< at most this many rounds of 10 shortcut attempts (>= 0)
  //! stop shortcutting after this many rounds in a row that shortened nothing (0: never)
  int shortcut_patience = 1;
  double velocity_scale = 1.0;    //!< fraction (0, 1] of the URDF's velocity limits
  double acceleration = 2.0;      //!< rad/s^2 (or m/s^2): the limit of every joint
  double sample_period = 0.01;    //!< s between trajectory samples (> 0)
  double default_velocity = 1.0;  //!< rad/s for joints whose URDF gives no velocity limit
  std::uint32_t seed = 0;         //!< seed of the planner's random sampling (reproducible)
};

//! A planned transit. On failure only status, message and planning_time are meaningful.
struct TransitResult {
  TransitStatus status = TransitStatus::no_path;  //!< what happened
  std::string message;                            //!< why, for a human; empty on success
  double planning_time = 0.0;                     //!< s of wall time in plan()
  Eigen::MatrixXd waypoints;       //!< (m, n): the collision-free polyline, start to goal
  double path_length = 0.0;        //!< rad: summed joint-space length of the polyline
  Eigen::VectorXd times;           //!< (k,): s, from 0 to duration, every sample_period
  Eigen::MatrixXd positions;       //!< (k, n): joint positions at `times`
  Eigen::MatrixXd velocities;      //!< (k, n)
  Eigen::MatrixXd accelerations;   //!< (k, n)
  double duration = 0.0;           //!< s
  long long collision_checks = 0;  //!< states checked during the call
};

//! Time-parameterise a joint-space polyline from rest to rest at every vertex within the
//! limits. \param waypoints (m, n) with m >= 1; \param velocity, acceleration (n,) > 0;
//! \param out receives times, positions, velocities, accelerations and duration.
//! \return `size_mismatch` or `invalid_argument` (non-positive limit or period), else `ok`.
Result time_parameterize(const Eigen::Ref<const Eigen::MatrixXd>& waypoints,
                         const Eigen::Ref<const Eigen::VectorXd>& velocity,
                         const Eigen::Ref<const Eigen::VectorXd>& acceleration,
                         double sample_period, TransitResult& out);

#if A2L_HAVE_BULLET && A2L_HAVE_OMPL
//! Plans transits of the arm of a CollisionModel. Not thread-safe (one per thread).
class TransitPlanner {
 public:
  //! A planner over `model` (taken over).
  explicit TransitPlanner(CollisionModel model);
  ~TransitPlanner();
  TransitPlanner(TransitPlanner&&) noexcept;
  TransitPlanner& operator=(TransitPlanner&&) noexcept;

  //! The collision model (set obstacles and the other joints through it).
  CollisionModel& model() noexcept;
  //! A path from `q_start` to `q_goal` (n_joints() each) and its trajectory, or a status
  //! saying why not. Never throws for a failed search; it returns within about
  //! options.time_limit.
  TransitResult plan(const Eigen::Ref<const Eigen::VectorXd>& q_start,
                     const Eigen::Ref<const Eigen::VectorXd>& q_goal,
                     const TransitOptions& options = TransitOptions());

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};
#endif

}  // namespace a2l
