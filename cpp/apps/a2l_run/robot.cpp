// a2l-run's robot: Baxter's arm from its URDF, or a resolved robot file's arm (--robot).
#include "robot.hpp"

#include <iostream>

#include "support.hpp"

namespace a2l_run {

namespace {

// Baxter's right or left arm (--arm, --urdf): the chain base -> <arm>_gripper and the typed
// neutral pose. 0, or 2 after a message.
int load_baxter(const Args& args, const a2l::Skill& skill, Robot& robot) {
  std::string urdf = args.urdf, tried;
  if (urdf.empty()) urdf = find_baxter_urdf(tried);
  if (urdf.empty()) {
    std::cerr << "a2l-run: cannot find Baxter's URDF; pass --urdf PATH or set A2L_ROBOTS_DIR "
                 "(python -m a2l.robot --robots-dir prints it), or use --no-robot. Tried:"
              << tried << "\n";
    return 2;
  }
  if (const int rc = check_urdf_hash(skill, args.bundle, urdf, robot.urdf_hash); rc != 0) {
    return rc;
  }
  a2l::Kinematics& kin = robot.kin;
  const std::string tip = args.arm + "_gripper";
  if (const a2l::Result r = a2l::Kinematics::load(urdf, "base", tip, kin); !r.ok()) {
    std::cerr << "a2l-run: " << r.message << "\n";
    return 2;
  }
  const double sgn = args.arm == "right" ? 1.0 : -1.0;
  const double neutral[7] = {0.08 * sgn, -1.0, 1.19 * sgn, 1.94, -0.67 * sgn, 1.03, 0.5 * sgn};
  if (kin.n_joints() != 7) {
    std::cerr << "a2l-run: '" << urdf << "': the chain base -> " << tip << " has " << kin.n_joints()
              << " joints; a2l-run drives Baxter's 7-joint arms\n";
    return 2;
  }
  robot.q_neutral.resize(7);
  for (int i = 0; i < 7; ++i) robot.q_neutral[i] = neutral[i];
  robot.desc = kin.robot_name() + " " + kin.base_link() + " -> " + kin.tip_link() + " (" +
               std::to_string(kin.n_joints()) + " joints), URDF " + urdf;
  return 0;
}

// The robot file's arm: its URDF (the hash it was exported with, then the bundle's), its
// chain (the joints it names) and its neutral pose. 0, or 2 after a message.
int load_file_arm(const Args& args, const a2l::Skill& skill, Robot& robot) {
  const a2l::ResolvedRobot& f = robot.file;
  const std::string src = "a2l-run: robot file '" + f.source + "': ";
  if (const int rc = check_urdf_hash(skill, args.bundle, f.urdf, robot.urdf_hash); rc != 0) {
    return rc;
  }
  if (robot.urdf_hash != f.urdf_sha256) {
    std::cerr << src << "urdf: '" << f.urdf << "' has SHA-256 " << robot.urdf_hash
              << ", not the urdf_sha256 " << f.urdf_sha256
              << " it was exported with; export the robot again\n";
    return 2;
  }
  a2l::Kinematics& kin = robot.kin;
  if (const a2l::Result r = a2l::Kinematics::load(f.urdf, f.base_link, f.tool_link, kin); !r.ok()) {
    std::cerr << src << "urdf, base_link, tool_link: " << r.message << "\n";
    return 2;
  }
  if (kin.joint_names() != f.joint_names) {
    std::string urdf_names, file_names;
    for (const auto& n : kin.joint_names()) urdf_names += (urdf_names.empty() ? "" : ", ") + n;
    for (const auto& n : f.joint_names) file_names += (file_names.empty() ? "" : ", ") + n;
    std::cerr << src << "joint_names: " << file_names << ", but the chain " << f.base_link << " -> "
              << f.tool_link << " of the URDF has the joints " << urdf_names << "\n";
    return 2;
  }
  robot.q_neutral.resize(kin.n_joints());
  for (int i = 0; i < kin.n_joints(); ++i) robot.q_neutral[i] = f.neutral[std::size_t(i)];
  robot.desc = f.name + " (robot file " + f.source + ") " + f.base_link + " -> " + f.tool_link +
               " (" + std::to_string(kin.n_joints()) + " joints), URDF " + f.urdf;
  return 0;
}

// The robot file of --robot, and the bundle's robot name against it. 0, or 2 after a message.
int load_robot_file(const Args& args, const a2l::Skill& skill, Robot& robot) {
  if (const a2l::Result r = a2l::load_resolved_robot(args.robot, robot.file); !r.ok()) {
    std::cerr << "a2l-run: --robot: " << r.message << "\n";
    return 2;
  }
  robot.from_file = true;
  const a2l::RobotInfo& learned = skill.robot();
  if (learned.present && learned.name != robot.file.name) {
    std::cerr << "a2l-run: the skill bundle '" << args.bundle << "' was learned for robot '"
              << learned.name << "', not for the robot '" << robot.file.name
              << "' of the robot file '" << args.robot << "': learn the skill on this robot\n";
    return 2;
  }
  return 0;
}

}  // namespace

int setup_robot(const Args& args, const a2l::Skill& skill, const a2l::ExecutorOptions& options,
                Robot& robot) {
  if (!args.robot.empty()) {
    if (const int rc = load_robot_file(args, skill, robot); rc != 0) return rc;
    if (args.no_robot)
      robot.desc = "none (--no-robot), the scene of robot '" + robot.file.name + "'";
  }
  if (args.no_robot) return 0;
  const int rc =
      robot.from_file ? load_file_arm(args, skill, robot) : load_baxter(args, skill, robot);
  if (rc != 0) return rc;
  if (const a2l::Result r = robot.exec.init(robot.kin, robot.q_neutral, options); !r.ok()) {
    std::cerr << "a2l-run: " << r.message << "\n";
    return 2;
  }
  return 0;
}

Eigen::Matrix3d start_rotation(Robot& robot) {
  if (robot.from_file && robot.file.has_tool_down) return robot.file.tool_down;
  robot.exec.reset(robot.q_neutral);
  return robot.exec.pose().linear();
}

}  // namespace a2l_run
