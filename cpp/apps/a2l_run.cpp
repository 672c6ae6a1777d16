// a2l-run: load a skill bundle and run it in closed loop against a C++ scene, every
// end-effector step going through Baxter's differential IK (see --help). The parts around the
// loop are in a2l_run/: the command line (options), the request to the skill (request), the
// robot, the scene, the task semantics (task), the records and the report.
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

int run(Args args) {
  // ---- loading (start-up: allocation and I/O allowed) ----
  a2l::Skill skill;
  if (const a2l::Result r = a2l::load_bundle(args.bundle, skill); !r.ok()) {
    std::cerr << "a2l-run: " << r.message << "\n";
    return 2;
  }
  const a2l::Discretizer& disc = skill.discretizer();
  Request req;
  if (const int rc = resolve_request(args, skill, req); rc != 0) return rc;
  const EffectDetector detector = EffectDetector::of(req.task, req.effect_names);
  const WorldStates world = WorldStates::of(skill);

  a2l::ExecutorOptions xo;
  if (args.rate > 0.0) xo.period = 1.0 / args.rate;
  Robot robot;
  if (const int rc = setup_robot(args, skill, xo, robot); rc != 0) return rc;

  Eigen::Vector3d object0 = args.object;
  if (!args.has_object) {
    object0 = args.no_robot ? Eigen::Vector3d(0.58, -0.18, 0.11) : robot.exec.position();
  }
  const Eigen::Vector3d half = object_half_size(req.task);
  const double table_z = object0.z() - half.z();
  std::unique_ptr<a2l::Scene> scene;
  a2l::VirtualScene* virt = nullptr;
  if (const int rc = make_scene(args, req.task, half, table_z, scene, virt); rc != 0) return rc;
  if (args.no_robot) {
    xo.workspace_min = object0 - Eigen::Vector3d(1.0, 1.0, 0.5);
    xo.workspace_max = object0 + Eigen::Vector3d(1.0, 1.0, 0.5);
  } else {
    xo.workspace_min = object0 - Eigen::Vector3d(0.6, 0.6, 0.3);
    xo.workspace_max = object0 + Eigen::Vector3d(0.6, 0.6, 0.5);
    robot.exec.init(robot.kin, robot.q_neutral, xo);
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
    if (csv) write_trace_header(trace, skill);
  }

  // ---- preallocation of everything the loop records ----
  const int cap = skill.settings().step_cap;
  const std::size_t n_episodes = req.wanted.size() * static_cast<std::size_t>(args.episodes);
  const double ticks_per_move =
      std::ceil(skill.movements().step() / (xo.max_speed * xo.period)) + 16.0;
  Timings timings;
  std::vector<double>& step_us = timings.step_us;
  std::vector<double>& tick_us = timings.tick_us;
  step_us.reserve(std::min<std::size_t>(n_episodes * static_cast<std::size_t>(cap + 2),
                                        std::size_t(5) * 1000 * 1000));
  const std::size_t tick_capacity =
      args.no_robot ? 0
                    : std::min<std::size_t>(n_episodes * static_cast<std::size_t>(cap) *
                                                static_cast<std::size_t>(ticks_per_move),
                                            std::size_t(5) * 1000 * 1000);
  tick_us.reserve(tick_capacity);
  std::vector<double>& late_us = timings.late_us;  // how late each wake-up at --rate was
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
  std::vector<EffectResult> results(req.effect_names.size());

  const std::vector<Eigen::Vector3d> starts = start_points(args, object0);
  long long& total_steps = timings.total_steps;
  long long& total_ticks = timings.total_ticks;
  const auto t_start = Clock::now();
  auto next_tick = Clock::now();
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(args.rate > 0 ? 1.0 / args.rate : 0.0));

  if (!args.quiet) {
    std::cout << "a2l-run: skill '" << skill.name() << "' (" << disc.n_variables() << " variables, "
              << skill.n_moves() << " movements, step cap " << cap << "), scene " << args.scene
              << ", robot " << robot.desc << "\n"
              << "  box at (" << object0.transpose() << "), starts " << describe_starts(args)
              << ", " << args.episodes << " episodes per effect, rate "
              << (args.rate > 0 ? std::to_string(args.rate) + " Hz" : "as fast as possible")
              << "\n";
  }

  int episode_id = 0;
  for (int effect : req.wanted) {
    EffectResult& res = results[static_cast<size_t>(effect)];
    for (int ep = 0; ep < args.episodes; ++ep, ++episode_id) {
      Eigen::Vector3d start = starts[static_cast<std::size_t>(ep)];
      std::string stop;
      if (!args.no_robot) {
        // Start-up of the episode (not real-time): full IK to the start point.
        Eigen::Isometry3d target = robot.exec.pose();
        robot.exec.reset(robot.q_neutral);
        target.linear() = robot.exec.pose().linear();
        target.translation() = start;
        a2l::JointVector q0;
        a2l::IkOptions io;
        io.seed = args.seed + static_cast<unsigned long long>(episode_id);
        io.position_tolerance = 1e-9;
        const a2l::Status s = robot.kin.ik(target, robot.q_neutral, q0, io);
        if (s != a2l::Status::ok || robot.exec.reset(q0) != a2l::Status::ok) {
          stop = std::string("start_") +
                 a2l::status_name(s == a2l::Status::ok ? a2l::Status::joint_limit : s);
        } else {
          start = robot.exec.position();
        }
      }
      scene->reset(start, object0);
      int presses_start = 0;
      if (virt != nullptr) {
        virt->set_light(req.light);
        virt->set_gripper(req.gripper);
        presses_start = virt->presses();
      }
      state.reset();
      state.clear_trace();
      rows.clear();
      const Eigen::Vector3d obj_start = scene->object_position();
      a2l::Context ctx;
      ctx.effect = effect;
      ctx.high_level = req.high_level;
      a2l::DSStateValues ds_values = req.ds_values;
      int outcome = 0;  // 1 success, 2 false positive, 0 fail
      a2l::StepOutput out;
      while (stop.empty()) {
        if (req.ds_mode && ctx.effect_produced) {
          stop = "effect_produced";
          break;
        }
        ctx.eef = scene->eef_position();
        ctx.object = scene->object_position();
        if (virt != nullptr) {
          world.apply(virt->light_on(), virt->gripper_closed(), ctx.high_level, ds_values);
        }
        const auto t0 = Clock::now();
        const a2l::Status s = req.ds_mode
                                  ? a2l::step_ds(skill, state, ctx.eef, ctx.object, ds_values, out)
                                  : a2l::step(skill, state, ctx, out);
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
        if (out.action == a2l::MovementAction::open || out.action == a2l::MovementAction::close) {
          if (virt != nullptr) virt->set_gripper(out.action == a2l::MovementAction::close);
        }
        if (out.action != a2l::MovementAction::none) {
          // an action moves no arm; stay holds still for one movement
          if (args.rate > 0) wait_next(next_tick, period);
        } else if (!args.no_robot) {
          const Eigen::Vector3d before = robot.exec.position();
          a2l::Status xs = robot.exec.set_target(before + out.displacement);
          while (xs == a2l::Status::ok && !robot.exec.reached()) {
            if (args.rate > 0) wait_next(next_tick, period);
            const auto a = Clock::now();
            xs = robot.exec.tick();
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
          moved_by = robot.exec.position() - scene->eef_position();
        }
        if (args.rate > 0 && args.no_robot && out.action == a2l::MovementAction::none) {
          wait_next(next_tick, period);
        }
        const bool moved = out.action == a2l::MovementAction::none && scene->move(moved_by);
        const int e = detector.detect(*scene, virt, moved, obj_start, presses_start);
        if (e >= 0) {
          ctx.effect_produced = true;
          outcome = e == effect ? 1 : 2;
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
      if (trace)
        write_trace(trace, csv, skill, episode_id, req.effect_names[static_cast<size_t>(effect)],
                    rows);
      if (args.rate > 0) next_tick = Clock::now();
    }
  }
  timings.elapsed = std::chrono::duration<double>(Clock::now() - t_start).count();

  return report(args, skill, req, robot, results, timings, trace);
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
