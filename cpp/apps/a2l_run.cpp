// a2l-run: load a skill bundle and run it in closed loop against a C++ scene, every
// end-effector step going through the differential IK of Baxter's arm, or of the arm of a
// resolved robot file (--robot; see --help). The parts around the loop are in a2l_run/: the
// command line (options), the request to the skill (request), the robot, the scene, the task
// semantics (task), the records and the report.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "a2l/bundle.hpp"
#include "a2l/executor.hpp"
#include "a2l/scene/virtual.hpp"
#include "a2l/skill.hpp"
#include "a2l_run/options.hpp"
#include "a2l_run/records.hpp"
#include "a2l_run/report.hpp"
#include "a2l_run/request.hpp"
#include "a2l_run/robot.hpp"
#include "a2l_run/scene.hpp"
#include "a2l_run/support.hpp"
#include "a2l_run/task.hpp"

using Clock = std::chrono::steady_clock;

namespace {

using namespace a2l_run;  // NOLINT: the executable's own parts

// What the episodes run against, set up before the loop (start-up: allocation and I/O
// allowed). The executor points to the robot's kinematics: a World stays where it was made.
struct World {
  a2l::Skill skill;
  Request req;
  a2l::ExecutorOptions xo;
  Robot robot;
  Eigen::Vector3d object0;
  std::unique_ptr<a2l::Scene> scene;
  a2l::VirtualScene* virt = nullptr;
};

// The skill from the bundle and what is asked of it (--effect, the world's states...). 0, or
// the exit code after a message.
int load_skill(Args& args, World& w) {
  if (const a2l::Result r = a2l::load_bundle(args.bundle, w.skill); !r.ok()) {
    std::cerr << "a2l-run: " << r.message << "\n";
    return 2;
  }
  return resolve_request(args, w.skill, w.req);
}

// A robot file's scene scale on the lengths the command line left at their defaults: the
// start distances and height (what the Python scenes scale on a small arm).
void scale_start_defaults(double scale, Args& args) {
  if (!args.has_radius) args.radius *= scale;
  if (!args.has_radius_range) {
    args.radius_min *= scale;
    args.radius_max *= scale;
  }
  if (!args.has_start_height) args.start_height *= scale;
}

// The robot (unless --no-robot), the object's place, the scene and the workspace; the
// executor started in it. With --robot, the object at the robot file's work point on its
// table (the push scene's box, or the other objects and the start lengths scaled), in its
// workspace. 0, or the exit code after a message.
int set_up_scene(Args& args, World& w) {
  if (args.rate > 0.0) w.xo.period = 1.0 / args.rate;
  if (const int rc = setup_robot(args, w.skill, w.xo, w.robot); rc != 0) return rc;
  const a2l::RobotSceneGeometry* geometry = w.robot.from_file ? &w.robot.file.scene : nullptr;
  const double scale = geometry != nullptr ? geometry->scale : 1.0;
  if (geometry != nullptr) scale_start_defaults(scale, args);
  const bool file_box = geometry != nullptr && w.req.task == Task::push;
  const Eigen::Vector3d half = file_box ? Eigen::Vector3d(0.5 * geometry->push_box_size)
                                        : scale * object_half_size(w.req.task);
  w.object0 = args.object;
  if (!args.has_object && geometry != nullptr) {
    w.object0 << geometry->work_point, geometry->table_z + half.z();
  } else if (!args.has_object) {
    w.object0 = args.no_robot ? Eigen::Vector3d(0.58, -0.18, 0.11) : w.robot.exec.position();
  }
  const double table_z = w.object0.z() - half.z();
  if (const int rc = make_scene(args, w.req.task, half, table_z, w.scene, w.virt); rc != 0) {
    return rc;
  }
  if (args.no_robot) {
    w.xo.workspace_min = w.object0 - Eigen::Vector3d(1.0, 1.0, 0.5);
    w.xo.workspace_max = w.object0 + Eigen::Vector3d(1.0, 1.0, 0.5);
    return 0;
  }
  if (geometry != nullptr && !args.has_object) {
    w.xo.workspace_min = geometry->workspace_min;
    w.xo.workspace_max = geometry->workspace_max;
  } else {
    w.xo.workspace_min = w.object0 - Eigen::Vector3d(0.6, 0.6, 0.3);
    w.xo.workspace_max = w.object0 + Eigen::Vector3d(0.6, 0.6, 0.5);
  }
  w.robot.exec.init(w.robot.kin, w.robot.q_neutral, w.xo);
  return 0;
}

// The --trace file opened, with the CSV header if it ends in .csv (`csv`). 0, or 2 after a
// message.
int open_trace(const Args& args, const a2l::Skill& skill, std::ofstream& trace, bool& csv) {
  csv = args.trace.size() >= 4 && args.trace.substr(args.trace.size() - 4) == ".csv";
  if (args.trace.empty()) return 0;
  trace.open(args.trace);
  if (!trace) {
    std::cerr << "a2l-run: --trace: cannot write '" << args.trace << "'\n";
    return 2;
  }
  if (csv) write_trace_header(trace, skill);
  return 0;
}

// The preallocation of everything the loop times, for `n_episodes` (the loop never
// reallocates: it stops recording when full).
void reserve_timings(const Args& args, const World& w, std::size_t n_episodes, Timings& timings) {
  const int cap = w.skill.settings().step_cap;
  const double ticks_per_move =
      std::ceil(w.skill.movements().step() / (w.xo.max_speed * w.xo.period)) + 16.0;
  timings.step_us.reserve(std::min<std::size_t>(n_episodes * static_cast<std::size_t>(cap + 2),
                                                std::size_t(5) * 1000 * 1000));
  const std::size_t tick_capacity =
      args.no_robot ? 0
                    : std::min<std::size_t>(n_episodes * static_cast<std::size_t>(cap) *
                                                static_cast<std::size_t>(ticks_per_move),
                                            std::size_t(5) * 1000 * 1000);
  timings.tick_us.reserve(tick_capacity);
  timings.late_us.reserve(
      args.rate > 0 ? std::max<std::size_t>(tick_capacity, timings.step_us.capacity()) : 0);
}

// The wake-ups at --rate: each one period after the last, how late it was recorded
// (Timings::late_us, while it has room).
struct Pacer {
  Clock::time_point next;
  Clock::duration period;
  std::vector<double>& late_us;

  void wait() {
    next += period;
    std::this_thread::sleep_until(next);
    if (late_us.size() < late_us.capacity()) {
      late_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - next).count());
    }
  }
};

// The run's start line, for a human.
void print_banner(const Args& args, const World& w) {
  const a2l::Skill& skill = w.skill;
  std::cout << "a2l-run: skill '" << skill.name() << "' (" << skill.discretizer().n_variables()
            << " variables, " << skill.n_moves() << " movements, step cap "
            << skill.settings().step_cap << "), scene " << args.scene << ", robot " << w.robot.desc
            << "\n"
            << "  box at (" << w.object0.transpose() << "), starts " << describe_starts(args)
            << ", " << args.episodes << " episodes per effect, rate "
            << (args.rate > 0 ? std::to_string(args.rate) + " Hz" : "as fast as possible") << "\n";
}

// What the control loop runs with and records into.
struct Loop {
  const Args& args;
  World& w;
  const EffectDetector& detector;
  const WorldStates& world;
  a2l::SkillState& state;
  Timings& timings;
  std::vector<TraceRow>& rows;
  Pacer& pacer;
};

// Start-up of an episode with the robot (not real-time): full IK to `start`, the arm put
// there (`start` then where it is). "" or why the episode cannot start.
std::string move_to_start(const Args& args, Robot& robot, int episode_id, Eigen::Vector3d& start) {
  Eigen::Isometry3d target = Eigen::Isometry3d::Identity();
  target.linear() = start_rotation(robot);
  target.translation() = start;
  a2l::JointVector q0;
  a2l::IkOptions io;
  io.seed = args.seed + static_cast<unsigned long long>(episode_id);
  io.position_tolerance = 1e-9;
  const a2l::Status s = robot.kin.ik(target, robot.q_neutral, q0, io);
  if (s != a2l::Status::ok || robot.exec.reset(q0) != a2l::Status::ok) {
    return std::string("start_") +
           a2l::status_name(s == a2l::Status::ok ? a2l::Status::joint_limit : s);
  }
  start = robot.exec.position();
  return "";
}

// The skill's step from the scene's positions and the world's states, timed and recorded.
a2l::Status timed_step(Loop& l, a2l::Context& ctx, a2l::DSStateValues& ds_values,
                       a2l::StepOutput& out) {
  World& w = l.w;
  ctx.eef = w.scene->eef_position();
  ctx.object = w.scene->object_position();
  if (w.virt != nullptr) {
    l.world.apply(w.virt->light_on(), w.virt->gripper_closed(), ctx.high_level, ds_values);
  }
  const auto t0 = Clock::now();
  const a2l::Status s = w.req.ds_mode
                            ? a2l::step_ds(w.skill, l.state, ctx.eef, ctx.object, ds_values, out)
                            : a2l::step(w.skill, l.state, ctx, out);
  const auto t1 = Clock::now();
  std::vector<double>& step_us = l.timings.step_us;
  if (step_us.size() < step_us.capacity()) {  // never reallocate inside the loop
    step_us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
  if (l.rows.size() < l.rows.capacity()) l.rows.push_back({out.record, ctx.eef, ctx.object});
  return s;
}

// The arm moved by `displacement` through the executor's ticks (timed, paced at --rate); the
// executor's status.
a2l::Status move_arm(Loop& l, const Eigen::Vector3d& displacement) {
  Robot& robot = l.w.robot;
  std::vector<double>& tick_us = l.timings.tick_us;
  const Eigen::Vector3d before = robot.exec.position();
  a2l::Status xs = robot.exec.set_target(before + displacement);
  while (xs == a2l::Status::ok && !robot.exec.reached()) {
    if (l.args.rate > 0) l.pacer.wait();
    const auto a = Clock::now();
    xs = robot.exec.tick();
    const auto b = Clock::now();
    if (tick_us.size() < tick_us.capacity()) {
      tick_us.push_back(std::chrono::duration<double, std::micro>(b - a).count());
    }
    ++l.timings.total_ticks;
  }
  return xs;
}

// The step's movement or action carried out (`moved_by`: how far the end-effector moved);
// false after setting `stop` when the robot stopped.
bool execute(Loop& l, const a2l::StepOutput& out, Eigen::Vector3d& moved_by, std::string& stop) {
  World& w = l.w;
  if (out.action == a2l::MovementAction::open || out.action == a2l::MovementAction::close) {
    if (w.virt != nullptr) w.virt->set_gripper(out.action == a2l::MovementAction::close);
  }
  if (out.action != a2l::MovementAction::none) {
    // an action moves no arm; stay holds still for one movement
    if (l.args.rate > 0) l.pacer.wait();
  } else if (!l.args.no_robot) {
    const a2l::Status xs = move_arm(l, out.displacement);
    if (xs != a2l::Status::ok) {
      stop = std::string("robot_") + a2l::status_name(xs);
      return false;
    }
    moved_by = w.robot.exec.position() - w.scene->eef_position();
  }
  if (l.args.rate > 0 && l.args.no_robot && out.action == a2l::MovementAction::none) {
    l.pacer.wait();
  }
  return true;
}

// The episode's control loop, until a stop (`stop`, empty to start with: go): the outcome, 1
// success, 2 false positive (another effect produced), 0 fail.
int control_loop(Loop& l, int effect, const Eigen::Vector3d& obj_start, int presses_start,
                 std::string& stop) {
  World& w = l.w;
  a2l::Context ctx;
  ctx.effect = effect;
  ctx.high_level = w.req.high_level;
  a2l::DSStateValues ds_values = w.req.ds_values;
  int outcome = 0;
  a2l::StepOutput out;
  while (stop.empty()) {
    if (w.req.ds_mode && ctx.effect_produced) {
      stop = "effect_produced";
      break;
    }
    const a2l::Status s = timed_step(l, ctx, ds_values, out);
    if (s != a2l::Status::ok) {
      stop = a2l::status_name(s);
      break;
    }
    ++l.timings.total_steps;
    Eigen::Vector3d moved_by = out.displacement;
    if (!execute(l, out, moved_by, stop)) break;
    const bool moved = out.action == a2l::MovementAction::none && w.scene->move(moved_by);
    const int e = l.detector.detect(*w.scene, w.virt, moved, obj_start, presses_start);
    if (e >= 0) {
      ctx.effect_produced = true;
      outcome = e == effect ? 1 : 2;
    }
  }
  return outcome;
}

// An episode's outcome counted into the effect's results.
void tally(EffectResult& res, int outcome, const std::string& stop, int steps) {
  if (outcome == 1) {
    ++res.success;
    res.steps_success += steps;
  } else if (outcome == 2) {
    ++res.false_positive;
  } else {
    ++res.fail;
  }
  ++res.stops[outcome == 0 ? stop : (outcome == 1 ? "success" : "false_positive")];
}

// One episode of `effect` from `start`: set up, the control loop, its outcome counted into
// `res`; the skill's steps and the scene's states in l.rows.
void run_episode(Loop& l, int effect, int episode_id, Eigen::Vector3d start, EffectResult& res) {
  World& w = l.w;
  std::string stop;
  if (!l.args.no_robot) stop = move_to_start(l.args, w.robot, episode_id, start);
  w.scene->reset(start, w.object0);
  int presses_start = 0;
  if (w.virt != nullptr) {
    w.virt->set_light(w.req.light);
    w.virt->set_gripper(w.req.gripper);
    presses_start = w.virt->presses();
  }
  l.state.reset();
  l.state.clear_trace();
  l.rows.clear();
  const Eigen::Vector3d obj_start = w.scene->object_position();
  const int outcome = control_loop(l, effect, obj_start, presses_start, stop);
  tally(res, outcome, stop, l.state.steps());
}

int run(Args args) {
  World w;
  if (const int rc = load_skill(args, w); rc != 0) return rc;
  const a2l::Skill& skill = w.skill;
  const Request& req = w.req;
  const WorldStates world = WorldStates::of(skill);
  if (const int rc = set_up_scene(args, w); rc != 0) return rc;
  const EffectDetector detector = EffectDetector::of(
      req.task, req.effect_names, w.robot.from_file ? w.robot.file.scene.scale : 1.0);

  const std::size_t trace_capacity =
      std::min<std::size_t>(static_cast<std::size_t>(skill.settings().step_cap) + 8, 100000);
  a2l::SkillState state(skill, trace_capacity);
  if (args.smoothing == "on") state.smoothing = a2l::Smoothing::on;
  if (args.smoothing == "off") state.smoothing = a2l::Smoothing::off;
  std::ofstream trace;
  bool csv = false;
  if (const int rc = open_trace(args, skill, trace, csv); rc != 0) return rc;

  Timings timings;
  reserve_timings(args, w, req.wanted.size() * static_cast<std::size_t>(args.episodes), timings);
  std::vector<TraceRow> rows;
  rows.reserve(trace_capacity);
  std::vector<EffectResult> results(req.effect_names.size());
  const std::vector<Eigen::Vector3d> starts = start_points(args, w.object0);
  const auto t_start = Clock::now();
  Pacer pacer{Clock::now(),
              std::chrono::duration_cast<Clock::duration>(
                  std::chrono::duration<double>(args.rate > 0 ? 1.0 / args.rate : 0.0)),
              timings.late_us};
  if (!args.quiet) print_banner(args, w);

  Loop l{args, w, detector, world, state, timings, rows, pacer};
  int episode_id = 0;
  for (int effect : req.wanted) {
    for (int ep = 0; ep < args.episodes; ++ep, ++episode_id) {
      run_episode(l, effect, episode_id, starts[static_cast<std::size_t>(ep)],
                  results[static_cast<size_t>(effect)]);
      if (trace) {
        write_trace(trace, csv, skill, episode_id, req.effect_names[static_cast<size_t>(effect)],
                    rows);
      }
      if (args.rate > 0) pacer.next = Clock::now();
    }
  }
  timings.elapsed = std::chrono::duration<double>(Clock::now() - t_start).count();
  return report(args, skill, req, w.robot, results, timings, trace);
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
