// a2l-run's robot: Baxter's arm from its URDF.
#include "robot.hpp"

#include <iostream>

#include "support.hpp"

namespace a2l_run {

int setup_robot(const Args& args, const a2l::Skill& skill, const a2l::ExecutorOptions& options,
                Robot& robot) {
  if (args.no_robot) return 0;
  a2l::Kinematics& kin = robot.kin;
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
  if (const a2l::Result r = robot.exec.init(kin, robot.q_neutral, options); !r.ok()) {
    std::cerr << "a2l-run: " << r.message << "\n";
    return 2;
  }
  robot.desc = kin.robot_name() + " " + kin.base_link() + " -> " + kin.tip_link() + " (" +
               std::to_string(kin.n_joints()) + " joints), URDF " + urdf;
  return 0;
}

}  // namespace a2l_run
