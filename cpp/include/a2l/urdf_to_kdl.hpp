//! \file urdf_to_kdl.hpp
//! \brief Our own urdfdom -> KDL tree converter (Debian's kdl_parser pulls ROS).
#pragma once

#include <kdl/tree.hpp>
#include <map>
#include <string>

#include "a2l/status.hpp"

namespace a2l {

//! What the URDF says of one joint beyond its kinematics.
struct UrdfJointInfo {
  bool movable = false;     //!< revolute, continuous or prismatic
  bool continuous = false;  //!< a revolute joint without position limits
  double lower = 0.0;       //!< lower position limit (rad or m); -inf when continuous
  double upper = 0.0;       //!< upper position limit (rad or m); +inf when continuous
  double velocity = 0.0;    //!< velocity limit (rad/s or m/s); 0 when the URDF gives none
  double effort = 0.0;      //!< effort limit; 0 when the URDF gives none
};

//! What the URDF says of the robot beyond the KDL tree.
struct UrdfInfo {
  std::string robot_name;                       //!< the robot's name attribute
  std::map<std::string, UrdfJointInfo> joints;  //!< by joint name
};

//! Parse a URDF file with urdfdom and convert it into a KDL tree, as kdl_parser does:
//! revolute and continuous joints become `RotAxis`, prismatic `TransAxis`, every other
//! joint type is fixed; the joint origin is the segment's frame in its parent.
//! \param urdf_path path of the URDF file
//! \param tree      output tree (left untouched on failure)
//! \param info     if not null, receives the robot name and the joint limits
//! \return `file_error` if the file cannot be read, `parse_error` with urdfdom's message if
//!         it is malformed, `ok` otherwise.
Result urdf_file_to_kdl_tree(const std::string& urdf_path, KDL::Tree& tree,
                             UrdfInfo* info = nullptr);

//! Same as urdf_file_to_kdl_tree() for a URDF held in a string; `source` names it in
//! error messages.
Result urdf_string_to_kdl_tree(const std::string& urdf_xml, KDL::Tree& tree,
                               const std::string& source = "<string>", UrdfInfo* info = nullptr);

}  // namespace a2l
