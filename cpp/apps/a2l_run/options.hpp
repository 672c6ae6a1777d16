// a2l-run's command line (internal to the executable).
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

namespace a2l_run {

//! The parsed command line (see kUsage).
struct Args {
  std::string bundle;
  std::string scene = "virtual";
  std::vector<std::string> effects;
  int episodes = 8;
  std::string starts = "random";
  double radius = 0.2;
  bool has_radius = false;
  double radius_min = 0.10, radius_max = 0.25;
  bool has_radius_range = false;
  bool has_object = false;
  Eigen::Vector3d object = Eigen::Vector3d::Zero();
  double rate = 0.0;
  unsigned long long seed = 0;
  std::string trace, summary, urdf;
  std::string arm = "right";
  bool has_arm = false;
  std::string robot;  // --robot FILE.json: a resolved robot (a2l/resolved_robot.hpp)
  bool no_robot = false;
  std::string smoothing = "bundle";
  std::vector<std::pair<std::string, std::string>> states;
  bool quiet = false;
  std::string mode = "table";  // table | ds
  std::string task = "auto";   // auto | push | grasp | press
  double start_height = 0.0;   // start points' height above the object (m)
  bool has_start_height = false;
};

//! A bad command line: the message names the option.
struct UsageError {
  std::string message;
};

//! The --help text.
extern const char* const kUsage;

//! Parse the command line; throws UsageError; prints kUsage and exits 0 on --help.
Args parse_args(int argc, char** argv);

}  // namespace a2l_run
