// a2l-run's command line: the usage text and the parser.
#include "options.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>

namespace a2l_run {

const char* const kUsage = R"(usage: a2l-run BUNDLE [options]

Load a skill bundle and run it in closed loop against a C++ scene. Each episode starts the
end-effector around the object (at its height for a push, above it for a grasp or a press),
asks the skill for a movement (a2l::step on the compiled table, or a2l::step_ds on the DS
phases with --mode ds), executes it as joint commands by differential IK on the robot's arm
(one command per control tick, with joint-limit, joint-velocity and workspace checks), moves
the scene, and stops when an effect was produced (success if it is the wanted one), at the
step cap, or on an unknown context. Actions: open/close move the gripper (the high-level
state `gripper`), stay holds still. Prints success per effect, steps per action and
step-time percentiles.

options:
  --scene {virtual,bullet}  scene to run against (default virtual): the kinematic model of
                            docs/virtual_scene.md (push, grasp, press), or Bullet rigid
                            bodies (table, box, end-effector sphere; push only)
  --mode {table,ds}         run the compiled table (default) or the bundle's DS phases
  --task {auto,push,grasp,press}  the object's semantics (default auto: grasp if an effect is
                            'grasped', press if one is 'pressed', else push): a box pushed by
                            the end-effector; a block the closed gripper holds when it
                            reached it (effects grasped = held 5 cm up, away = waiting at the
                            retreat pose); a button toggling the light when the end-effector
                            goes down on it (effect pressed)
  --start-height H          start points' height above the object, m (default 0 for a push,
                            0.15 for a grasp or a press)
  --effect E                wanted effect (a name of the bundle's effect variable); repeat or
                            separate by commas for several (default: every effect)
  --episodes N              episodes per effect, from N start points (the same for every
                            effect; default 8)
  --starts {random,circle}  where the episodes start (default random): random = N points
                            drawn from --seed, angle uniform around the box, distance uniform
                            in --radius-range; circle = N points evenly on a circle of radius
                            --radius, turned by a random angle drawn from --seed (none for
                            seed 0: the framework's training starts)
  --radius-range A,B        distances of random starts from the box, m (default 0.10,0.25
                            for a push, 0.02,0.10 for a grasp or a press)
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
                            its first value); states the table does not use are ignored;
                            `light` and `gripper` then follow the scene (press, open, close)
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

namespace {

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

}  // namespace

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
    } else if (o == "--mode") {
      a.mode = value(i);
      if (a.mode != "table" && a.mode != "ds") {
        usage_error("--mode: '" + a.mode + "' is not one of table, ds");
      }
    } else if (o == "--task") {
      a.task = value(i);
      if (a.task != "auto" && a.task != "push" && a.task != "grasp" && a.task != "press") {
        usage_error("--task: '" + a.task + "' is not one of auto, push, grasp, press");
      }
    } else if (o == "--start-height") {
      a.start_height = parse_double(o, value(i));
      a.has_start_height = true;
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

}  // namespace a2l_run
