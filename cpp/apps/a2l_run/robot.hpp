// a2l-run's robot (internal): Baxter's arm, or the arm of a resolved robot file (--robot),
// through the C++ kinematics and executor, or none (--no-robot).
#pragma once

#include <Eigen/Core>
#include <string>

#include "a2l/executor.hpp"
#include "a2l/kinematics.hpp"
#include "a2l/resolved_robot.hpp"
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
  bool from_file = false;                  //!< --robot: `file` holds the resolved robot
  a2l::ResolvedRobot file;                 //!< the robot file of --robot (its scene too)
};

//! With --robot: read the resolved robot file and check the bundle's robot name against it
//! (even with --no-robot: its scene is used). Unless --no-robot: find and check the URDF
//! (Baxter's, --urdf, or the file's: against the bundle's hash and the file's), load the
//! chain (base -> <arm>_gripper, or the file's) and start the executor at the neutral pose
//! with `options`. 0, or 2 after a message.
int setup_robot(const Args& args, const a2l::Skill& skill, const a2l::ExecutorOptions& options,
                Robot& robot);

//! The orientation of the tool at the episodes' start: the robot file's tool_down when it
//! has one, else the neutral pose's (Baxter's, as always). Start-up only.
Eigen::Matrix3d start_rotation(Robot& robot);

}  // namespace a2l_run
