// a2l-run's robot (internal): Baxter's arm through the C++ kinematics and executor, or none
// (--no-robot).
#pragma once

#include <string>

#include "a2l/executor.hpp"
#include "a2l/kinematics.hpp"
#include "a2l/skill.hpp"
#include "options.hpp"

namespace a2l_run {

//! The arm a2l-run drives. The executor points to `kin`: a Robot stays where it was made.
struct Robot {
  a2l::Kinematics kin;
  a2l::Executor exec;
  a2l::JointVector q_neutral;
  std::string desc = "none (--no-robot)";  //!< for a human
  std::string urdf_hash;                   //!< SHA-256 of the URDF loaded ("" without robot)
};

//! Unless --no-robot: find and check Baxter's URDF (--urdf, against the bundle's hash), load
//! the chain base -> <arm>_gripper and start the executor at the neutral pose with `options`.
//! 0, or 2 after a message.
int setup_robot(const Args& args, const a2l::Skill& skill, const a2l::ExecutorOptions& options,
                Robot& robot);

}  // namespace a2l_run
