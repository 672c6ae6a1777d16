//! \file movement_repertoire.hpp
//! \brief The discrete movements a skill chooses from (the last axis of its policy table).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "a2l/status.hpp"

namespace a2l {

//! Most movements a repertoire may hold.
constexpr int kMaxMoves = 1024;

//! What a movement of the repertoire does besides displacing the end-effector: `none` for a
//! displacement; the actions `open` and `close` (the gripper) and `stay` (hold still for one
//! movement's duration) displace nothing.
enum class MovementAction : int {
  none = 0,   //!< a displacement (not an action)
  open = 1,   //!< open the gripper
  close = 2,  //!< close the gripper
  stay = 3,   //!< hold still one movement's duration
};

//! The bundle name of an action ("open", "close", "stay"; "none" for a displacement).
const char* movement_action_name(MovementAction action) noexcept;
//! The action named `name` ("open", "close" or "stay"); false for any other name.
bool parse_movement_action(const std::string& name, MovementAction& action) noexcept;

//! The default directions of a repertoire, in table order: every sign vector but zero (26;
//! the 8 with z = 0 if `planar`), the axis moves first (+x, -x, +y, -y, +z, -z), then those
//! with 2 and then 3 non-zero signs; within a count, the sign vectors whose first non-zero
//! axes come first, then + before - axis by axis (+x+y, +x-y, -x+y, -x-y, +x+z, ...).
std::vector<Eigen::Vector3i> default_directions(bool planar = false);

//! The label of direction `d`: its signed axes, "+x", "-x+y", "+x-y+z" (empty for zero).
std::string direction_label(const Eigen::Vector3i& d);

//! Movement i < n_directions() displaces the end-effector by step * d_i / ||d_i||, d_i a
//! 3-vector of signs; movement n_directions() + j is the action j (no displacement). Immutable
//! once created.
class MovementRepertoire {
 public:
  //! An empty repertoire.
  MovementRepertoire() = default;

  //! Build a repertoire.
  //! \param step       movement length (m), finite and > 0
  //! \param directions sign vectors, entries in {-1, 0, 1}, not all zero
  //! \param labels     one name per direction (empty: "m0", "m1", ...; a bundle without
  //!                   labels; a2l writes direction_label())
  //! \param actions    actions after the directions (each at most once, never `none`); their
  //!                   labels are their names
  //! \return `invalid_argument` or `size_mismatch` naming the movement, else `ok`.
  static Result create(double step, std::vector<Eigen::Vector3i> directions,
                       std::vector<std::string> labels, MovementRepertoire& out,
                       std::vector<MovementAction> actions = {});

  //! Number of movements (directions and actions).
  int size() const noexcept { return static_cast<int>(displacements_.size()); }
  //! Number of directions (the first movements).
  int n_directions() const noexcept { return static_cast<int>(directions_.size()); }
  //! Number of actions (the last movements).
  int n_actions() const noexcept { return size() - n_directions(); }
  //! Movement length (m).
  double step() const noexcept { return step_; }
  //! Sign vector of direction i (i < n_directions()).
  const Eigen::Vector3i& direction(int i) const noexcept {
    return directions_[static_cast<size_t>(i)];
  }
  //! The action of movement i (`none` for a direction).
  MovementAction action(int i) const noexcept {
    return i < n_directions() ? MovementAction::none
                              : actions_[static_cast<size_t>(i - n_directions())];
  }
  //! True if movement i is an action.
  bool is_action(int i) const noexcept { return i >= n_directions(); }
  //! Index of the movement of `action`, or -1 if the repertoire does not hold it.
  int index_of(MovementAction action) const noexcept {
    for (std::size_t j = 0; j < actions_.size(); ++j) {
      if (actions_[j] == action) return n_directions() + static_cast<int>(j);
    }
    return -1;
  }
  //! The actions, in movement order.
  const std::vector<MovementAction>& actions() const noexcept { return actions_; }
  //! Displacement of movement i: step * d / ||d|| (m); zero for an action.
  const Eigen::Vector3d& displacement(int i) const noexcept {
    return displacements_[static_cast<size_t>(i)];
  }
  //! Name of movement i.
  const std::string& label(int i) const noexcept { return labels_[static_cast<size_t>(i)]; }
  //! All sign vectors (n_directions()).
  const std::vector<Eigen::Vector3i>& directions() const noexcept { return directions_; }
  //! All labels (directions', then actions' names).
  const std::vector<std::string>& labels() const noexcept { return labels_; }

 private:
  double step_ = 0.0;
  std::vector<Eigen::Vector3i> directions_;
  std::vector<Eigen::Vector3d> displacements_;
  std::vector<std::string> labels_;
  std::vector<MovementAction> actions_;
};

}  // namespace a2l
