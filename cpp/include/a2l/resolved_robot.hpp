//! \file resolved_robot.hpp
//! \brief A robot resolved by Python for the C++ runtime: its URDF, arm chain, neutral pose,
//! tool orientation and scene geometry, read from one JSON file
//! (`a2l robot export ROBOT --out FILE.json`; docs/runtime.md).
//!
//! Set-up code: loading allocates and reads a file; nothing here is on the real-time path.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "a2l/status.hpp"

namespace a2l {

//! The `format` key of a resolved robot file.
inline constexpr const char* kResolvedRobotFormat = "a2l-resolved-robot";
//! The only `version` of the format this build reads.
inline constexpr int kResolvedRobotVersion = 1;

//! Where a robot's scenes put their objects (a2l.robot.table_layout; the push scene's box), in its
//! base frame (m).
struct RobotSceneGeometry {
  double table_z = 0.0;                                  //!< height of the table top
  Eigen::Vector2d work_point = Eigen::Vector2d::Zero();  //!< where the objects stand (x, y)
  double scale = 1.0;                                    //!< scene lengths / the thesis', (0, 1]
  //! Size (x, y, z) of the push scene's box: scaled, and lowered under the robot's hand.
  Eigen::Vector3d push_box_size = Eigen::Vector3d::Zero();
  Eigen::Vector3d workspace_min = Eigen::Vector3d::Zero();  //!< end-effector bounds, low corner
  Eigen::Vector3d workspace_max = Eigen::Vector3d::Zero();  //!< end-effector bounds, high corner
};

//! A robot arm resolved by Python (a2l.sim.resolved_robot): what a2l-run needs, nothing to look up.
struct ResolvedRobot {
  std::string source;  //!< the file it was read from (for messages)
  std::string name;    //!< the robot's name ("panda"): a skill bundle's robot.name
  std::string urdf;    //!< the URDF, absolute (a relative path is taken from the file's folder)
  std::string urdf_sha256;               //!< SHA-256 (hex) of the URDF when exported
  std::string base_link;                 //!< first link of the arm's chain
  std::string tool_link;                 //!< last link of the chain: the point the skills move
  std::vector<std::string> joint_names;  //!< the chain's movable joints, base to tool
  std::vector<double> neutral;           //!< joint positions of the neutral pose, per joint
  bool has_tool_down = false;            //!< whether `tool_down` was given (not null)
  //! Orientation of the tool frame in the base frame pointing down (a rotation), if given.
  Eigen::Matrix3d tool_down = Eigen::Matrix3d::Identity();
  RobotSceneGeometry scene;  //!< the scenes' geometry
};

//! Read and check a resolved robot file into `out`.
//! \return `file_error` naming the file when it cannot be read; `parse_error` when it is not
//!         JSON or a key is missing, unknown or of the wrong type or size, a number is not
//!         finite, `tool_down` is not a rotation, `scale` is outside (0, 1], a box size is not
//!         positive or the workspace is empty (the message names the file and the key, e.g.
//!         "scene.scale"); and `version_mismatch` for another format version. `out` is unspecified
//!         on failure.
Result load_resolved_robot(const std::string& path, ResolvedRobot& out);

}  // namespace a2l
