// a2l-run's task semantics (internal): which object semantics the virtual scene gets, the
// high-level states that follow the scene (light, gripper), and the effect detection.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "a2l/effects.hpp"
#include "a2l/scene/virtual.hpp"
#include "a2l/skill.hpp"

namespace a2l_run {

//! What the skill does to its object.
enum class Task { push, grasp, press };

//! "push", "grasp", "press".
const char* task_name(Task task) noexcept;

//! The task of `arg` (push, grasp, press), or for "auto" from the effect names: grasp if one
//! is "grasped", press if one is "pressed", else push.
Task resolve_task(const std::string& arg, const std::vector<std::string>& effects);

//! Where a two-valued state lives in a skill's table (axis) or DS states (index), and the
//! value indices of its two values; -1 where absent.
struct StateSlot {
  int at = -1;       //!< table axis or DS state index, -1 if the skill does not use it
  int value_0 = -1;  //!< index of the value meaning false (light off, gripper open)
  int value_1 = -1;  //!< index of the value meaning true (light on, gripper closed)
};

//! The states light (off, on) and gripper (open, closed) of the skill, which follow the scene.
struct WorldStates {
  StateSlot table_light, table_gripper, ds_light, ds_gripper;

  //! Find them in `skill`'s table variables and DS states.
  static WorldStates of(const a2l::Skill& skill);

  //! Write the scene's light and gripper into the table's and the DS's state values (slots
  //! the skill does not use are left as they are). No allocation.
  void apply(bool light_on, bool gripper_closed, std::array<int, a2l::kMaxVariables>& table,
             a2l::DSStateValues& ds) const noexcept;
};

//! The effects a2l-run detects after each movement, by the index of their names.
struct EffectDetector {
  Task task = Task::push;
  int n_classify = 4;  //!< push: 4 or 8 effects
  int grasped = -1, pressed = -1, away = -1;
  double threshold = a2l::kEffectThreshold;  //!< push: the shortest displacement that counts (m)

  //! Built from the effect names of the skill; the push threshold scaled by `scale` (a robot
  //! file's scene scale, as the Python scenes scale theirs).
  static EffectDetector of(Task task, const std::vector<std::string>& effects, double scale = 1.0);

  //! The effect produced since the episode's start, or -1: the push effect
  //! (a2l::classify_effect with `threshold`), grasped (held a2l::kLiftThreshold above the start),
  //! pressed, or away (a2l::stayed_away, the object's displacement since the start). No allocation.
  int detect(const a2l::Scene& scene, const a2l::VirtualScene* virt, bool box_moved,
             const Eigen::Vector3d& object_start, int presses_start) const noexcept;
};

}  // namespace a2l_run
