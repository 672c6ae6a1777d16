// a2l-run's helpers outside the loop.
#include "support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <random>
#include <sstream>

#include "a2l/file_hash.hpp"

namespace fs = std::filesystem;

namespace a2l_run {

std::string find_baxter_urdf(std::string& tried) {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("A2L_ROBOTS_DIR"); env && *env) dirs.emplace_back(env);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path lib = exe.parent_path().parent_path() / "lib";
    if (fs::is_directory(lib, ec)) {
      for (const auto& entry : fs::directory_iterator(lib, ec)) {
        if (entry.path().filename().string().rfind("python3", 0) == 0) {
          dirs.push_back(entry.path() / "site-packages" / "cmeel.prefix" / "share" /
                         "example-robot-data" / "robots");
        }
      }
    }
  }
  for (const auto& d : dirs) {
    const fs::path p = d / "baxter_description" / "urdf" / "baxter.urdf";
    tried += "\n  " + p.string();
    if (fs::is_regular_file(p, ec)) return p.string();
  }
  return "";
}

Percentiles percentiles(std::vector<double> v) {
  Percentiles p;
  p.n = v.size();
  if (v.empty()) return p;
  std::sort(v.begin(), v.end());
  auto at = [&](double q) {
    const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size()))) - 1;
    return v[std::min(i, v.size() - 1)];
  };
  p.p50 = at(0.5);
  p.p90 = at(0.9);
  p.p99 = at(0.99);
  p.p999 = at(0.999);
  p.max = v.back();
  double s = 0;
  for (double x : v) s += x;
  p.mean = s / static_cast<double>(v.size());
  return p;
}

nlohmann::json to_json(const Percentiles& p) {
  return {{"p50_us", p.p50}, {"p90_us", p.p90},   {"p99_us", p.p99}, {"p99.9_us", p.p999},
          {"max_us", p.max}, {"mean_us", p.mean}, {"n", p.n}};
}

// The bundle's URDF hash against the URDF loaded: 0 if they agree (or the bundle names no
// URDF), else 2 after a message naming both hashes.
int check_urdf_hash(const a2l::Skill& skill, const std::string& bundle, const std::string& urdf,
                    std::string& urdf_hash) {
  if (const a2l::Result r = a2l::sha256_file(urdf, urdf_hash); !r.ok()) {
    std::cerr << "a2l-run: --urdf: " << r.message << "\n";
    return 2;
  }
  const a2l::RobotInfo& robot = skill.robot();
  if (!robot.present || robot.urdf_sha256.empty() || robot.urdf_sha256 == urdf_hash) return 0;
  std::cerr << "a2l-run: the URDF '" << urdf << "' is not the one the skill bundle '" << bundle
            << "' was learned on: its SHA-256 is " << urdf_hash << ", the bundle's robot '"
            << robot.name << "' has urdf_sha256 " << robot.urdf_sha256
            << "; pass that URDF with --urdf\n";
  return 2;
}

// The episodes' start points around `object`, the same for every effect (see --starts).
std::vector<Eigen::Vector3d> start_points(const Args& args, const Eigen::Vector3d& object) {
  const double kPi = 3.14159265358979323846;
  std::mt19937_64 rng(args.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<Eigen::Vector3d> out;
  out.reserve(static_cast<std::size_t>(args.episodes));
  const double rotation =
      args.starts == "circle" && args.seed != 0 ? uni(rng) * 2.0 * kPi / args.episodes : 0.0;
  for (int ep = 0; ep < args.episodes; ++ep) {
    double angle = rotation + 2.0 * kPi * ep / args.episodes, radius = args.radius;
    if (args.starts == "random") {
      angle = uni(rng) * 2.0 * kPi;
      radius = args.radius_min + uni(rng) * (args.radius_max - args.radius_min);
    }
    out.push_back(object + radius * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0) +
                  Eigen::Vector3d(0.0, 0.0, args.start_height));
  }
  return out;
}

std::string describe_starts(const Args& args) {
  std::ostringstream s;
  if (args.starts == "random") {
    s << "random (seed " << args.seed << "): angle uniform, distance uniform in ["
      << args.radius_min << ", " << args.radius_max << "] m";
  } else {
    s << "circle of radius " << args.radius << " m"
      << (args.seed == 0 ? ", not turned (the framework's training starts)"
                         : ", turned by a random angle (seed " + std::to_string(args.seed) + ")");
  }
  return s.str();
}

}  // namespace a2l_run
