#include "a2l/urdf_to_kdl.hpp"

#include <console_bridge/console.h>
#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <fstream>
#include <kdl/frames.hpp>
#include <kdl/joint.hpp>
#include <kdl/segment.hpp>
#include <limits>
#include <mutex>
#include <sstream>

namespace a2l {
namespace {

// Collects urdfdom's console_bridge messages while it parses, so that the reason of a parse
// failure reaches the caller instead of stderr only.
class CollectingHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) {
      if (!messages.empty()) messages += "; ";
      messages += text;
    }
  }
  std::string messages;
};

std::mutex& parser_mutex() {
  static std::mutex m;
  return m;
}

KDL::Vector to_kdl(const urdf::Vector3& v) { return KDL::Vector(v.x, v.y, v.z); }

KDL::Rotation to_kdl(const urdf::Rotation& r) {
  return KDL::Rotation::Quaternion(r.x, r.y, r.z, r.w);
}

KDL::Frame to_kdl(const urdf::Pose& p) {
  return KDL::Frame(to_kdl(p.rotation), to_kdl(p.position));
}

KDL::Joint to_kdl(const urdf::JointSharedPtr& jnt) {
  const KDL::Frame f = to_kdl(jnt->parent_to_joint_origin_transform);
  switch (jnt->type) {
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS: {
      const KDL::Vector axis = to_kdl(jnt->axis);
      return KDL::Joint(jnt->name, f.p, f.M * axis, KDL::Joint::RotAxis);
    }
    case urdf::Joint::PRISMATIC: {
      const KDL::Vector axis = to_kdl(jnt->axis);
      return KDL::Joint(jnt->name, f.p, f.M * axis, KDL::Joint::TransAxis);
    }
    default:
      return KDL::Joint(jnt->name, KDL::Joint::Fixed);
  }
}

// As kdl_parser: the rotational inertia is rotated into the link frame (KDL's
// RigidBodyInertia takes it about the centre of mass), the com is the inertial origin.
KDL::RigidBodyInertia to_kdl(const urdf::InertialSharedPtr& i) {
  if (!i) return KDL::RigidBodyInertia();
  const KDL::Frame origin = to_kdl(i->origin);
  const KDL::RotationalInertia urdf_inertia(i->ixx, i->iyy, i->izz, i->ixy, i->ixz, i->iyz);
  const KDL::RigidBodyInertia rotated =
      origin.M * KDL::RigidBodyInertia(0, KDL::Vector::Zero(), urdf_inertia);
  return KDL::RigidBodyInertia(i->mass, origin.p, rotated.getRotationalInertia());
}

bool add_children(const urdf::LinkConstSharedPtr& root, KDL::Tree& tree) {
  for (const auto& child : root->child_links) {
    const auto& jnt = child->parent_joint;
    KDL::Segment seg(child->name, to_kdl(jnt), to_kdl(jnt->parent_to_joint_origin_transform),
                     to_kdl(child->inertial));
    if (!tree.addSegment(seg, root->name)) return false;
    if (!add_children(child, tree)) return false;
  }
  return true;
}

}  // namespace

Result urdf_string_to_kdl_tree(const std::string& urdf_xml, KDL::Tree& tree,
                               const std::string& source, UrdfInfo* info) {
  urdf::ModelInterfaceSharedPtr model;
  std::string messages;
  {
    std::lock_guard<std::mutex> lock(parser_mutex());
    CollectingHandler handler;
    console_bridge::useOutputHandler(&handler);
    model = urdf::parseURDF(urdf_xml);
    console_bridge::restorePreviousOutputHandler();
    messages = handler.messages;
  }
  if (!model) {
    return Result::failure(
        Status::parse_error,
        "malformed URDF " + source + ": " +
            (messages.empty() ? std::string("urdfdom could not parse it") : messages));
  }
  const urdf::LinkConstSharedPtr root = model->getRoot();
  if (!root) {
    return Result::failure(Status::parse_error, "malformed URDF " + source + ": no root link");
  }
  KDL::Tree result(root->name);
  if (!add_children(root, result)) {
    return Result::failure(Status::parse_error,
                           "URDF " + source + ": could not build the KDL tree (duplicate link?)");
  }
  tree = result;
  if (info) {
    info->robot_name = model->getName();
    info->joints.clear();
    for (const auto& [name, jnt] : model->joints_) {
      UrdfJointInfo j;
      j.movable = jnt->type == urdf::Joint::REVOLUTE || jnt->type == urdf::Joint::CONTINUOUS ||
                  jnt->type == urdf::Joint::PRISMATIC;
      j.continuous = jnt->type == urdf::Joint::CONTINUOUS;
      if (jnt->limits) {
        j.lower = jnt->limits->lower;
        j.upper = jnt->limits->upper;
        j.velocity = jnt->limits->velocity;
        j.effort = jnt->limits->effort;
      }
      if (j.continuous) {
        j.lower = -std::numeric_limits<double>::infinity();
        j.upper = std::numeric_limits<double>::infinity();
      }
      info->joints[name] = j;
    }
  }
  return Result::success();
}

Result urdf_file_to_kdl_tree(const std::string& urdf_path, KDL::Tree& tree, UrdfInfo* info) {
  std::ifstream in(urdf_path, std::ios::in | std::ios::binary);
  if (!in) {
    return Result::failure(Status::file_error, "cannot open URDF file '" + urdf_path + "'");
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) {
    return Result::failure(Status::file_error, "cannot read URDF file '" + urdf_path + "'");
  }
  return urdf_string_to_kdl_tree(ss.str(), tree, "'" + urdf_path + "'", info);
}

}  // namespace a2l
