// a2l-run: load a skill bundle and run it in closed loop against a C++ scene, every
// end-effector step going through Baxter's differential IK (see --help).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "a2l/bundle.hpp"
#include "a2l/executor.hpp"
#include "a2l/file_hash.hpp"
#include "a2l/kinematics.hpp"
#include "a2l/scene/bullet.hpp"
#include "a2l/scene/virtual.hpp"
#include "a2l/skill.hpp"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

constexpr const char* kUsage = R"(usage: a2l-run BUNDLE [options]

Load a skill bundle and run it in closed loop against a C++ scene. Each episode starts the
end-effector around the box (at the box's height), asks the skill for a movement
(a2l::step), executes it as joint commands by differential IK on the robot's arm (one command
per control tick, with joint-limit, joint-velocity and workspace checks), moves the scene, and
stops when the box moved (success if the effect is the wanted one), at the step cap, or on an
unknown context. Prints success per effect, steps per action and step-time percentiles.

options:
  --scene {virtual,bullet}  scene to run against (default virtual): the kinematic push model
                            of docs/virtual_scene.md, or Bullet rigid bodies (table, box,
                            end-effector sphere)
  --effect E                wanted effect (a name of the bundle's effect variable); repeat or
                            separate by commas for several (default: every effect)
  --episodes N              episodes per effect, from N start points (the same for every
                            effect; default 8)
  --starts {random,circle}  where the episodes start (default random): random = N points
                            drawn from --seed, angle uniform around the box, distance uniform
                            in --radius-range; circle = N points evenly on a circle of radius
                            --radius, turned by a random angle drawn from --seed (none for
                            seed 0: the framework's training starts)
  --radius-range A,B        distances of random starts from the box, m (default 0.10,0.25)
  --radius R                radius of the circle of --starts circle, m (default 0.2)
  --object X,Y,Z            box centre in the robot's base frame, m (default: the arm's
                            neutral end-effector position)
  --rate HZ                 control rate of the joint commands; 0 = as fast as possible
                            (default 0)
  --seed S                  seed of the random starts, or of the circle's rotation (default 0)
  --trace FILE              write the trace: CSV if FILE ends in .csv, else JSON lines
  --summary FILE            write the results as JSON
  --urdf PATH               robot URDF (default: Baxter's, see below)
  --arm {right,left}        Baxter arm (default right)
  --no-robot                move the scene directly, without IK (no URDF needed)
  --smoothing {bundle,on,off}  neighbour smoothing (default: the bundle's setting)
  --state NAME=VALUE        value of a high-level state of the skill (repeatable; default:
                            its first value); states the table does not use are ignored
  --quiet                   print only the summary lines
  -h, --help                this help

Baxter's URDF: --urdf PATH, else $A2L_ROBOTS_DIR/baxter_description/urdf/baxter.urdf, else the
example-robot-data installed in the virtual environment a2l-run belongs to
(<venv>/lib/python3*/site-packages/cmeel.prefix/share/example-robot-data/robots); this lookup
happens once at start-up. `python -m a2l.robot --robots-dir` prints the directory. When the
bundle names the URDF it was learned on (its robot's urdf_sha256), the URDF loaded must have
that SHA-256 (OpenSSL's libcrypto), else a2l-run refuses to run.

exit status: 0 after the run (whatever the success rate), 2 on a bad argument, bundle or
URDF, 1 on an I/O error while writing the outputs.
)";

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
  bool no_robot = false;
  std::string smoothing = "bundle";
  std::vector<std::pair<std::string, std::string>> states;
  bool quiet = false;
};

struct UsageError {
  std::string message;
};

[[noreturn]] void usage_error(const std::string& msg) { throw UsageError{msg}; }

double parse_double(const std::string& opt, const std::string& s) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || errno != 0 || !std::isfinite(v)) {
    usage_error(opt + ": '" + s + "' is not a finite number");
  }
  return v;
}

long long parse_int(const std::string& opt, const std::string& s, long long lo, long long hi) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (s.empty() || end != s.c_str() + s.size() || errno != 0 || v < lo || v > hi) {
    usage_error(opt + ": '" + s + "' is not an integer in [" + std::to_string(lo) + ", " +
                std::to_string(hi) + "]");
  }
  return v;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream ss(s);
  while (std::getline(ss, cur, sep)) {
    if (!cur.empty()) out.push_back(cur);
  }
  return out;
}

Args parse_args(int argc, char** argv) {
  Args a;
  auto value = [&](int& i) -> std::string {
    if (i + 1 >= argc) usage_error(std::string(argv[i]) + ": needs a value");
    return argv[++i];
  };
  for (int i = 1; i < argc; ++i) {
    const std::string o = argv[i];
    if (o == "-h" || o == "--help") {
      std::cout << kUsage;
      std::exit(0);
    } else if (o == "--scene") {
      a.scene = value(i);
      if (a.scene != "virtual" && a.scene != "bullet") {
        usage_error("--scene: '" + a.scene + "' is not one of virtual, bullet");
      }
    } else if (o == "--effect") {
      for (auto& e : split(value(i), ',')) a.effects.push_back(e);
    } else if (o == "--episodes") {
      a.episodes = static_cast<int>(parse_int(o, value(i), 1, 100000));
    } else if (o == "--starts") {
      a.starts = value(i);
      if (a.starts != "random" && a.starts != "circle") {
        usage_error("--starts: '" + a.starts + "' is not one of random, circle");
      }
    } else if (o == "--radius") {
      a.radius = parse_double(o, value(i));
      a.has_radius = true;
      if (!(a.radius > 0.0)) usage_error("--radius: must be > 0");
    } else if (o == "--radius-range") {
      const auto parts = split(value(i), ',');
      if (parts.size() != 2) usage_error("--radius-range: needs A,B");
      a.radius_min = parse_double(o, parts[0]);
      a.radius_max = parse_double(o, parts[1]);
      a.has_radius_range = true;
      if (!(a.radius_min > 0.0 && a.radius_min <= a.radius_max)) {
        usage_error("--radius-range: needs 0 < A <= B");
      }
    } else if (o == "--object") {
      const auto parts = split(value(i), ',');
      if (parts.size() != 3) usage_error("--object: needs X,Y,Z");
      for (int k = 0; k < 3; ++k) a.object[k] = parse_double(o, parts[static_cast<size_t>(k)]);
      a.has_object = true;
    } else if (o == "--rate") {
      a.rate = parse_double(o, value(i));
      if (a.rate < 0.0) usage_error("--rate: must be >= 0 (0 = as fast as possible)");
    } else if (o == "--seed") {
      a.seed = static_cast<unsigned long long>(parse_int(o, value(i), 0, (1LL << 62)));
    } else if (o == "--trace") {
      a.trace = value(i);
    } else if (o == "--summary") {
      a.summary = value(i);
    } else if (o == "--urdf") {
      a.urdf = value(i);
    } else if (o == "--arm") {
      a.arm = value(i);
      if (a.arm != "right" && a.arm != "left") usage_error("--arm: must be right or left");
    } else if (o == "--no-robot") {
      a.no_robot = true;
    } else if (o == "--smoothing") {
      a.smoothing = value(i);
      if (a.smoothing != "bundle" && a.smoothing != "on" && a.smoothing != "off") {
        usage_error("--smoothing: must be bundle, on or off");
      }
    } else if (o == "--state") {
      const std::string kv = value(i);
      const auto eq = kv.find('=');
      if (eq == std::string::npos || eq == 0) usage_error("--state: needs NAME=VALUE");
      a.states.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
    } else if (o == "--quiet") {
      a.quiet = true;
    } else if (!o.empty() && o[0] == '-') {
      usage_error("unknown option '" + o + "'");
    } else if (a.bundle.empty()) {
      a.bundle = o;
    } else {
      usage_error("unexpected argument '" + o + "' (one BUNDLE only)");
    }
  }
  if (a.bundle.empty()) usage_error("missing BUNDLE");
  if (a.starts == "random" && a.has_radius) {
    usage_error(
        "--radius: sets the circle of --starts circle; random starts (the default) "
        "take --radius-range A,B");
  }
  if (a.starts == "circle" && a.has_radius_range) {
    usage_error("--radius-range: sets the random starts; --starts circle takes --radius R");
  }
  return a;
}

// Baxter's URDF: $A2L_ROBOTS_DIR, else the example-robot-data of the venv holding a2l-run.
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

struct Percentiles {
  double p50 = 0, p90 = 0, p99 = 0, p999 = 0, max = 0, mean = 0;
  std::size_t n = 0;
};

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

struct TraceRow {
  a2l::TraceRecord record;
  Eigen::Vector3d eef, object;
};

struct EffectResult {
  int success = 0, false_positive = 0, fail = 0;
  long long steps_success = 0;
  std::map<std::string, int> stops;
};

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
    out.push_back(object + radius * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0));
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

int run(const Args& args) {
  // ---- loading (start-up: allocation and I/O allowed) ----
  a2l::Skill skill;
  if (const a2l::Result r = a2l::load_bundle(args.bundle, skill); !r.ok()) {
    std::cerr << "a2l-run: " << r.message << "\n";
    return 2;
  }
  const a2l::Discretizer& disc = skill.discretizer();
  const int effect_axis = disc.effect_axis();
  if (effect_axis < 0) {
    std::cerr << "a2l-run: skill bundle '" << args.bundle
              << "': the table has no effect variable, a2l-run cannot ask for an effect\n";
    return 2;
  }
  const std::vector<std::string>& effect_names = disc.variable(effect_axis).values;
  std::vector<int> wanted;
  if (args.effects.empty()) {
    for (int i = 0; i < static_cast<int>(effect_names.size()); ++i) wanted.push_back(i);
  } else {
    for (const auto& e : args.effects) {
      const auto it = std::find(effect_names.begin(), effect_names.end(), e);
      if (it == effect_names.end()) {
        std::string names;
        for (const auto& n : effect_names) names += (names.empty() ? "" : ", ") + n;
        std::cerr << "a2l-run: --effect: '" << e << "' is not an effect of the skill (" << names
                  << ")\n";
        return 2;
      }
      wanted.push_back(static_cast<int>(it - effect_names.begin()));
    }
  }
  std::array<int, a2l::kMaxVariables> high_level{};
  for (const auto& [name, value] : args.states) {
    const int axis = disc.find(name);
    if (axis < 0) continue;  // not in the table: does not change the posterior
    const a2l::Variable& v = disc.variable(axis);
    const auto it = std::find(v.values.begin(), v.values.end(), value);
    if (v.kind != a2l::VariableKind::high_level || it == v.values.end()) {
      std::string names;
      for (const auto& n : v.values) names += (names.empty() ? "" : ", ") + n;
      std::cerr << "a2l-run: --state: '" << value << "' is not a value of the high-level state '"
                << name << "' (" << names << ")\n";
      return 2;
    }
    high_level[static_cast<size_t>(axis)] = static_cast<int>(it - v.values.begin());
  }
  const int n_effect_values = static_cast<int>(effect_names.size());
  const int classify_n = n_effect_values > 4 ? 8 : 4;

  a2l::Kinematics kin;
  a2l::Executor exec;
  a2l::JointVector q_neutral;
  std::string robot_desc = "none (--no-robot)", urdf_hash;
  a2l::ExecutorOptions xo;
  if (args.rate > 0.0) xo.period = 1.0 / args.rate;
  if (!args.no_robot) {
    std::string urdf = args.urdf, tried;
    if (urdf.empty()) urdf = find_baxter_urdf(tried);
    if (urdf.empty()) {
      std::cerr << "a2l-run: cannot find Baxter's URDF; pass --urdf PATH or set A2L_ROBOTS_DIR "
                   "(python -m a2l.robot --robots-dir prints it), or use --no-robot. Tried:"
                << tried << "\n";
      return 2;
    }
    if (const int rc = check_urdf_hash(skill, args.bundle, urdf, urdf_hash); rc != 0) return rc;
    const std::string tip = args.arm + "_gripper";
    if (const a2l::Result r = a2l::Kinematics::load(urdf, "base", tip, kin); !r.ok()) {
      std::cerr << "a2l-run: " << r.message << "\n";
      return 2;
    }
    const double sgn = args.arm == "right" ? 1.0 : -1.0;
    const double neutral[7] = {0.08 * sgn, -1.0, 1.19 * sgn, 1.94, -0.67 * sgn, 1.03, 0.5 * sgn};
    if (kin.n_joints() != 7) {
      std::cerr << "a2l-run: '" << urdf << "': the chain base -> " << tip << " has "
                << kin.n_joints() << " joints; a2l-run drives Baxter's 7-joint arms\n";
      return 2;
    }
    q_neutral.resize(7);
    for (int i = 0; i < 7; ++i) q_neutral[i] = neutral[i];
    if (const a2l::Result r = exec.init(kin, q_neutral, xo); !r.ok()) {
      std::cerr << "a2l-run: " << r.message << "\n";
      return 2;
    }
    robot_desc = kin.robot_name() + " " + kin.base_link() + " -> " + kin.tip_link() + " (" +
                 std::to_string(kin.n_joints()) + " joints), URDF " + urdf;
  }

  Eigen::Vector3d object0 = args.object;
  if (!args.has_object) {
    object0 = args.no_robot ? Eigen::Vector3d(0.58, -0.18, 0.11) : exec.position();
  }
  const Eigen::Vector3d half(0.035, 0.0425, 0.04);
  const double table_z = object0.z() - half.z();

  std::unique_ptr<a2l::Scene> scene;
  if (args.scene == "virtual") {
    a2l::VirtualSceneOptions vo;
    vo.half_size = half;
    vo.table_z = table_z;
    scene = std::make_unique<a2l::VirtualScene>(vo);
  } else {
#if A2L_HAVE_BULLET
    a2l::BulletSceneOptions bo;
    bo.half_size = half;
    bo.table_z = table_z;
    scene = std::make_unique<a2l::BulletScene>(bo);
#else
    std::cerr << "a2l-run: --scene bullet: this build has no Bullet (libbullet-dev)\n";
    return 2;
#endif
  }
  if (args.no_robot) {
    xo.workspace_min = object0 - Eigen::Vector3d(1.0, 1.0, 0.5);
    xo.workspace_max = object0 + Eigen::Vector3d(1.0, 1.0, 0.5);
  } else {
    xo.workspace_min = object0 - Eigen::Vector3d(0.6, 0.6, 0.3);
    xo.workspace_max = object0 + Eigen::Vector3d(0.6, 0.6, 0.5);
    exec.init(kin, q_neutral, xo);
  }

  const std::size_t trace_capacity =
      std::min<std::size_t>(static_cast<std::size_t>(skill.settings().step_cap) + 8, 100000);
  a2l::SkillState state(skill, trace_capacity);
  if (args.smoothing == "on") state.smoothing = a2l::Smoothing::on;
  if (args.smoothing == "off") state.smoothing = a2l::Smoothing::off;

  std::ofstream trace;
  const bool csv = args.trace.size() >= 4 && args.trace.substr(args.trace.size() - 4) == ".csv";
  if (!args.trace.empty()) {
    trace.open(args.trace);
    if (!trace) {
      std::cerr << "a2l-run: --trace: cannot write '" << args.trace << "'\n";
      return 2;
    }
    if (csv) {
      trace << "episode,effect,step,status,movement,label,probability";
      for (const auto& v : disc.variables()) trace << ",bin_" << v.name;
      trace << ",eef_x,eef_y,eef_z,obj_x,obj_y,obj_z\n";
    }
  }

  // ---- preallocation of everything the loop records ----
  const int cap = skill.settings().step_cap;
  const std::size_t n_episodes = wanted.size() * static_cast<std::size_t>(args.episodes);
  const double ticks_per_move =
      std::ceil(skill.movements().step() / (xo.max_speed * xo.period)) + 16.0;
  std::vector<double> step_us, tick_us;
  step_us.reserve(std::min<std::size_t>(n_episodes * static_cast<std::size_t>(cap + 2),
                                        std::size_t(5) * 1000 * 1000));
  const std::size_t tick_capacity =
      args.no_robot ? 0
                    : std::min<std::size_t>(n_episodes * static_cast<std::size_t>(cap) *
                                                static_cast<std::size_t>(ticks_per_move),
                                            std::size_t(5) * 1000 * 1000);
  tick_us.reserve(tick_capacity);
  std::vector<double> late_us;  // how late each wake-up at --rate was
  late_us.reserve(args.rate > 0 ? std::max<std::size_t>(tick_capacity, step_us.capacity()) : 0);
  auto wait_next = [&](Clock::time_point& next, Clock::duration period) {
    next += period;
    std::this_thread::sleep_until(next);
    if (late_us.size() < late_us.capacity()) {
      late_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - next).count());
    }
  };
  std::vector<TraceRow> rows;
  rows.reserve(trace_capacity);
  std::vector<EffectResult> results(static_cast<std::size_t>(n_effect_values));

  const std::vector<Eigen::Vector3d> starts = start_points(args, object0);
  long long total_steps = 0, total_ticks = 0;
  const auto t_start = Clock::now();
  auto next_tick = Clock::now();
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(args.rate > 0 ? 1.0 / args.rate : 0.0));

  if (!args.quiet) {
    std::cout << "a2l-run: skill '" << skill.name() << "' (" << disc.n_variables() << " variables, "
              << skill.n_moves() << " movements, step cap " << cap << "), scene " << args.scene
              << ", robot " << robot_desc << "\n"
              << "  box at (" << object0.transpose() << "), starts " << describe_starts(args)
              << ", " << args.episodes << " episodes per effect, rate "
              << (args.rate > 0 ? std::to_string(args.rate) + " Hz" : "as fast as possible")
              << "\n";
  }

  int episode_id = 0;
  for (int effect : wanted) {
    EffectResult& res = results[static_cast<size_t>(effect)];
    for (int ep = 0; ep < args.episodes; ++ep, ++episode_id) {
      Eigen::Vector3d start = starts[static_cast<std::size_t>(ep)];
      std::string stop;
      if (!args.no_robot) {
        // Start-up of the episode (not real-time): full IK to the start point.
        Eigen::Isometry3d target = exec.pose();
        exec.reset(q_neutral);
        target.linear() = exec.pose().linear();
        target.translation() = start;
        a2l::JointVector q0;
        a2l::IkOptions io;
        io.seed = args.seed + static_cast<unsigned long long>(episode_id);
        io.position_tolerance = 1e-9;
        const a2l::Status s = kin.ik(target, q_neutral, q0, io);
        if (s != a2l::Status::ok || exec.reset(q0) != a2l::Status::ok) {
          stop = std::string("start_") +
                 a2l::status_name(s == a2l::Status::ok ? a2l::Status::joint_limit : s);
        } else {
          start = exec.position();
        }
      }
      scene->reset(start, object0);
      state.reset();
      state.clear_trace();
      rows.clear();
      const Eigen::Vector3d obj_start = scene->object_position();
      a2l::Context ctx;
      ctx.effect = effect;
      ctx.high_level = high_level;
      int outcome = 0;  // 1 success, 2 false positive, 0 fail
      a2l::StepOutput out;
      while (stop.empty()) {
        ctx.eef = scene->eef_position();
        ctx.object = scene->object_position();
        const auto t0 = Clock::now();
        const a2l::Status s = a2l::step(skill, state, ctx, out);
        const auto t1 = Clock::now();
        if (step_us.size() < step_us.capacity()) {  // never reallocate inside the loop
          step_us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
        }
        if (rows.size() < rows.capacity()) rows.push_back({out.record, ctx.eef, ctx.object});
        if (s != a2l::Status::ok) {
          stop = a2l::status_name(s);
          break;
        }
        ++total_steps;
        Eigen::Vector3d moved_by = out.displacement;
        if (!args.no_robot) {
          const Eigen::Vector3d before = exec.position();
          a2l::Status xs = exec.set_target(before + out.displacement);
          while (xs == a2l::Status::ok && !exec.reached()) {
            if (args.rate > 0) wait_next(next_tick, period);
            const auto a = Clock::now();
            xs = exec.tick();
            const auto b = Clock::now();
            if (tick_us.size() < tick_us.capacity()) {
              tick_us.push_back(std::chrono::duration<double, std::micro>(b - a).count());
            }
            ++total_ticks;
          }
          if (xs != a2l::Status::ok) {
            stop = std::string("robot_") + a2l::status_name(xs);
            break;
          }
          moved_by = exec.position() - scene->eef_position();
        }
        if (args.rate > 0 && args.no_robot) wait_next(next_tick, period);
        if (scene->move(moved_by)) {
          const int e = a2l::classify_effect(scene->object_position() - obj_start, classify_n);
          if (e >= 0) {
            ctx.effect_produced = true;
            outcome = e == effect ? 1 : 2;
          }
        }
      }
      ctx.effect_produced = false;
      if (outcome == 1) {
        ++res.success;
        res.steps_success += state.steps();
      } else if (outcome == 2) {
        ++res.false_positive;
      } else {
        ++res.fail;
      }
      ++res.stops[outcome == 0 ? stop : (outcome == 1 ? "success" : "false_positive")];
      if (trace) {
        for (const TraceRow& row : rows) {
          const a2l::TraceRecord& r = row.record;
          const std::string label = r.movement >= 0 ? skill.movements().label(r.movement) : "";
          if (csv) {
            trace << episode_id << "," << effect_names[static_cast<size_t>(effect)] << "," << r.step
                  << "," << a2l::status_name(r.status) << "," << r.movement << "," << label << ","
                  << r.probability;
            for (int i = 0; i < r.n_variables; ++i) trace << "," << r.bins[static_cast<size_t>(i)];
            trace << "," << row.eef.x() << "," << row.eef.y() << "," << row.eef.z() << ","
                  << row.object.x() << "," << row.object.y() << "," << row.object.z() << "\n";
          } else {
            nlohmann::json j;
            j["episode"] = episode_id;
            j["effect"] = effect_names[static_cast<size_t>(effect)];
            j["step"] = r.step;
            j["status"] = a2l::status_name(r.status);
            j["movement"] = r.movement;
            j["label"] = label;
            j["probability"] = r.probability;
            nlohmann::json bins = nlohmann::json::object();
            for (int i = 0; i < r.n_variables; ++i) {
              bins[disc.variable(i).name] = r.bins[static_cast<size_t>(i)];
            }
            j["bins"] = bins;
            j["eef"] = {row.eef.x(), row.eef.y(), row.eef.z()};
            j["object"] = {row.object.x(), row.object.y(), row.object.z()};
            trace << j.dump() << "\n";
          }
        }
      }
      if (args.rate > 0) next_tick = Clock::now();
    }
  }
  const double elapsed = std::chrono::duration<double>(Clock::now() - t_start).count();

  // ---- report ----
  const Percentiles sp = percentiles(step_us), tp = percentiles(tick_us), lp = percentiles(late_us);
  nlohmann::json summary;
  summary["bundle"] = args.bundle;
  summary["skill"] = skill.name();
  summary["scene"] = args.scene;
  summary["robot"] = robot_desc;
  summary["episodes_per_effect"] = args.episodes;
  summary["rate_hz"] = args.rate;
  summary["seed"] = args.seed;
  summary["starts"] = {{"mode", args.starts}, {"description", describe_starts(args)}};
  if (args.starts == "random") {
    summary["starts"]["radius_range"] = {args.radius_min, args.radius_max};
  } else {
    summary["starts"]["radius"] = args.radius;
  }
  if (!urdf_hash.empty()) summary["urdf_sha256"] = urdf_hash;
  int total_success = 0, total_episodes = 0;
  std::printf("%-12s %8s %10s %6s %14s  %s\n", "effect", "success", "false_pos", "fail",
              "steps/action", "stops");
  for (int effect : wanted) {
    const EffectResult& r = results[static_cast<size_t>(effect)];
    const int n = r.success + r.false_positive + r.fail;
    total_success += r.success;
    total_episodes += n;
    const double spa = r.success ? static_cast<double>(r.steps_success) / r.success : 0.0;
    std::string stops;
    for (const auto& [k, v] : r.stops)
      stops += (stops.empty() ? "" : ", ") + k + " " + std::to_string(v);
    std::printf("%-12s %5d/%-3d %10d %6d %14.2f  %s\n",
                effect_names[static_cast<size_t>(effect)].c_str(), r.success, n, r.false_positive,
                r.fail, spa, stops.c_str());
    summary["effects"][effect_names[static_cast<size_t>(effect)]] = {
        {"episodes", n},  {"success", r.success},    {"false_positive", r.false_positive},
        {"fail", r.fail}, {"steps_per_action", spa}, {"stops", r.stops}};
  }
  std::printf("success %d/%d (%.1f%%)\n", total_success, total_episodes,
              total_episodes ? 100.0 * total_success / total_episodes : 0.0);
  std::printf(
      "step() time: p50 %.3f us, p90 %.3f us, p99 %.3f us, p99.9 %.3f us, max %.3f us "
      "(%zu calls)\n",
      sp.p50, sp.p90, sp.p99, sp.p999, sp.max, sp.n);
  if (!args.no_robot) {
    std::printf(
        "control tick (differential IK + checks): p50 %.3f us, p90 %.3f us, p99 %.3f us, "
        "p99.9 %.3f us, max %.3f us (%zu ticks)\n",
        tp.p50, tp.p90, tp.p99, tp.p999, tp.max, tp.n);
  }
  if (args.rate > 0) {
    std::printf(
        "wake-up lateness at %.0f Hz: p50 %.1f us, p99 %.1f us, p99.9 %.1f us, max %.1f us\n",
        args.rate, lp.p50, lp.p99, lp.p999, lp.max);
  }
  const double sps = elapsed > 0 ? static_cast<double>(total_steps) / elapsed : 0.0;
  std::printf(
      "closed loop: %lld skill steps, %lld control ticks in %.3f s: %.1f steps/s, "
      "%.1f ticks/s\n",
      total_steps, total_ticks, elapsed, sps,
      elapsed > 0 ? static_cast<double>(total_ticks) / elapsed : 0.0);
  summary["success"] = total_success;
  summary["episodes"] = total_episodes;
  summary["step_time"] = to_json(sp);
  summary["tick_time"] = to_json(tp);
  summary["wakeup_lateness"] = to_json(lp);
  summary["skill_steps"] = total_steps;
  summary["control_ticks"] = total_ticks;
  summary["elapsed_s"] = elapsed;
  summary["steps_per_s"] = sps;
  if (trace) {
    trace.flush();
    if (!trace) {
      std::cerr << "a2l-run: --trace: error while writing '" << args.trace << "'\n";
      return 1;
    }
  }
  if (!args.summary.empty()) {
    std::ofstream f(args.summary);
    f << summary.dump(2) << "\n";
    if (!f) {
      std::cerr << "a2l-run: --summary: cannot write '" << args.summary << "'\n";
      return 1;
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args args = parse_args(argc, argv);
    return run(args);
  } catch (const UsageError& e) {
    std::cerr << "a2l-run: " << e.message << "\n(a2l-run --help for usage)\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "a2l-run: error: " << e.what() << "\n";
    return 1;
  } catch (...) {
    std::cerr << "a2l-run: unexpected error\n";
    return 1;
  }
}
