// a2l-run's command line: the usage text and the parser.
#include "options.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <iostream>
#include <sstream>
#include <utility>

namespace a2l_run {

const char* const kUsage = R"(usage: a2l-run BUNDLE [options]

Load a skill bundle and run it in closed loop against a C++ scene. Each episode starts the
end-effector around the object (at its height for a push, above it for a grasp or a press),
asks the skill for a movement (a2l::step on the compiled table, or a2l::step_ds on the DS
phases with --mode ds), executes it as joint commands by differential IK on the robot's arm
(one command per control tick, slowed to the joint velocity limits, with joint-limit and
workspace checks), moves the scene, and stops when an effect was produced (success if it is
the wanted one), at the step cap, or on an unknown context. Actions: open/close move the gripper (the high-level
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
                            neutral end-effector position; with --robot, its work point)
  --rate HZ                 control rate of the joint commands; 0 = as fast as possible
                            (default 0)
  --seed S                  seed of the random starts, or of the circle's rotation (default 0)
  --trace FILE              write the trace: CSV if FILE ends in .csv, else JSON lines
  --summary FILE            write the results as JSON
  --robot FILE.json         run on the arm of a robot resolved by `a2l robot export ROBOT
                            --out FILE.json` (its URDF, chain, neutral pose, tool orientation
                            and scene: the object at its work point, the push scene's box, the
                            other objects, start distances and effect threshold scaled, its
                            workspace); a bundle learned for another robot (name, URDF
                            SHA-256) is refused (default: Baxter, see below)
  --urdf PATH               Baxter's URDF (default: see below; not with --robot)
  --arm {right,left}        Baxter arm (default right; not with --robot)
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
that SHA-256 (OpenSSL's libcrypto), else a2l-run refuses to run. With --robot, the URDF is
the robot file's, and must still have the SHA-256 it was exported with; a bundle that names
a robot must name the file's (robot.name).

exit status: 0 after the run (whatever the success rate), 2 on a bad argument, bundle, robot
file or URDF, 1 on an I/O error while writing the outputs.
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

// The non-empty items of a list such as --effect left,right.
std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream ss(s);
  while (std::getline(ss, cur, sep)) {
    if (!cur.empty()) out.push_back(cur);
  }
  return out;
}

// Every field of `s` between the separators, empty ones included ("1,,2" has 3 fields), so
// that a number list with a missing value is refused rather than read shorter.
std::vector<std::string> fields(const std::string& s, char sep) {
  std::vector<std::string> out(1);
  for (const char c : s) {
    if (c == sep) {
      out.emplace_back();
    } else {
      out.back() += c;
    }
  }
  return out;
}

// `value` if it is one of `choices`, else a usage error ("--scene: 'x' is not one of virtual,
// bullet").
std::string one_of(const std::string& opt, const std::string& value,
                   std::initializer_list<const char*> choices) {
  std::string names;
  for (const char* c : choices) {
    if (value == c) return value;
    names += (names.empty() ? "" : ", ") + std::string(c);
  }
  usage_error(opt + ": '" + value + "' is not one of " + names);
}

// --radius R: the circle of --starts circle, > 0.
void set_radius(const std::string& o, const std::string& v, Args& a) {
  a.radius = parse_double(o, v);
  a.has_radius = true;
  if (!(a.radius > 0.0)) usage_error("--radius: must be > 0");
}

// --radius-range A,B: the distances of random starts, 0 < A <= B.
void set_radius_range(const std::string& o, const std::string& v, Args& a) {
  const auto parts = fields(v, ',');
  if (parts.size() != 2) usage_error("--radius-range: needs A,B, got '" + v + "'");
  a.radius_min = parse_double(o, parts[0]);
  a.radius_max = parse_double(o, parts[1]);
  a.has_radius_range = true;
  if (!(a.radius_min > 0.0 && a.radius_min <= a.radius_max)) {
    usage_error("--radius-range: needs 0 < A <= B");
  }
}

// --object X,Y,Z: the box centre.
void set_object(const std::string& o, const std::string& v, Args& a) {
  const auto parts = fields(v, ',');
  if (parts.size() != 3) usage_error("--object: needs X,Y,Z, got '" + v + "'");
  for (int k = 0; k < 3; ++k) a.object[k] = parse_double(o, parts[static_cast<size_t>(k)]);
  a.has_object = true;
}

// --state NAME=VALUE: a high-level state's value (repeatable).
void add_state(const std::string&, const std::string& kv, Args& a) {
  const auto eq = kv.find('=');
  if (eq == std::string::npos || eq == 0) {
    usage_error("--state: needs NAME=VALUE, got '" + kv + "'");
  }
  a.states.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
}

// Parses and checks the value `v` of option `o` into `a` (a usage error names the option).
using SetOption = void (*)(const std::string& o, const std::string& v, Args& a);

// The options that take a value (the next argument), each with its setter.
const std::pair<const char*, SetOption> kValueOptions[] = {
    {"--scene",
     [](const std::string& o, const std::string& v, Args& a) {
       a.scene = one_of(o, v, {"virtual", "bullet"});
     }},
    {"--effect",
     [](const std::string&, const std::string& v, Args& a) {
       for (auto& e : split(v, ',')) a.effects.push_back(e);
     }},
    {"--episodes", [](const std::string& o, const std::string& v,
                      Args& a) { a.episodes = static_cast<int>(parse_int(o, v, 1, 100000)); }},
    {"--starts",
     [](const std::string& o, const std::string& v, Args& a) {
       a.starts = one_of(o, v, {"random", "circle"});
     }},
    {"--radius", set_radius},
    {"--radius-range", set_radius_range},
    {"--object", set_object},
    {"--rate",
     [](const std::string& o, const std::string& v, Args& a) {
       a.rate = parse_double(o, v);
       if (a.rate < 0.0) usage_error("--rate: must be >= 0 (0 = as fast as possible)");
     }},
    {"--seed",
     [](const std::string& o, const std::string& v, Args& a) {
       a.seed = static_cast<unsigned long long>(parse_int(o, v, 0, (1LL << 62)));
     }},
    {"--trace", [](const std::string&, const std::string& v, Args& a) { a.trace = v; }},
    {"--summary", [](const std::string&, const std::string& v, Args& a) { a.summary = v; }},
    {"--urdf", [](const std::string&, const std::string& v, Args& a) { a.urdf = v; }},
    {"--arm",
     [](const std::string& o, const std::string& v, Args& a) {
       a.arm = one_of(o, v, {"right", "left"});
       a.has_arm = true;
     }},
    {"--robot", [](const std::string&, const std::string& v, Args& a) { a.robot = v; }},
    {"--smoothing",
     [](const std::string& o, const std::string& v, Args& a) {
       a.smoothing = one_of(o, v, {"bundle", "on", "off"});
     }},
    {"--state", add_state},
    {"--mode",
     [](const std::string& o, const std::string& v, Args& a) {
       a.mode = one_of(o, v, {"table", "ds"});
     }},
    {"--task",
     [](const std::string& o, const std::string& v, Args& a) {
       a.task = one_of(o, v, {"auto", "push", "grasp", "press"});
     }},
    {"--start-height",
     [](const std::string& o, const std::string& v, Args& a) {
       a.start_height = parse_double(o, v);
       a.has_start_height = true;
     }},
};

// The setter of option `o` if it takes a value, else null.
SetOption value_option(const std::string& o) {
  for (const auto& [name, set] : kValueOptions) {
    if (o == name) return set;
  }
  return nullptr;
}

// The checks across options: a BUNDLE given, --radius only for circle starts,
// --radius-range only for random ones, neither --urdf nor --arm with --robot.
void check_combination(const Args& a) {
  if (a.bundle.empty()) usage_error("missing BUNDLE");
  if (a.starts == "random" && a.has_radius) {
    usage_error(
        "--radius: sets the circle of --starts circle; random starts (the default) "
        "take --radius-range A,B");
  }
  if (a.starts == "circle" && a.has_radius_range) {
    usage_error("--radius-range: sets the random starts; --starts circle takes --radius R");
  }
  if (!a.robot.empty() && !a.urdf.empty()) {
    usage_error("--urdf: the robot file of --robot names its URDF (export it again to change it)");
  }
  if (!a.robot.empty() && a.has_arm) {
    usage_error("--arm: chooses Baxter's arm; the robot file of --robot names its chain");
  }
}

}  // namespace

Args parse_args(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string o = argv[i];
    if (o == "-h" || o == "--help") {
      std::cout << kUsage;
      std::exit(0);
    } else if (const SetOption set = value_option(o)) {
      if (i + 1 >= argc) usage_error(o + ": needs a value");
      set(o, argv[++i], a);
    } else if (o == "--no-robot") {
      a.no_robot = true;
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
  check_combination(a);
  return a;
}

}  // namespace a2l_run
