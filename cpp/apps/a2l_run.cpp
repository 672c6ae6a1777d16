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
#include "a2l_run/options.hpp"
#include "a2l_run/records.hpp"
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
  const Task task = resolve_task(args.task, effect_names);
  const EffectDetector detector = EffectDetector::of(task, effect_names);
  const WorldStates world = WorldStates::of(skill);
  if (task != Task::push) {  // start above the object, closer
    if (!args.has_start_height) args.start_height = 0.15;
    if (!args.has_radius_range) {
      args.radius_min = 0.02;
      args.radius_max = 0.10;
    }
  }
  const bool ds_mode = args.mode == "ds";
  if (ds_mode && skill.ds_phases().empty()) {
    std::cerr << "a2l-run: --mode ds: skill bundle '" << args.bundle
              << "' has no DS phases (section ds_phases)\n";
    return 2;
  }
  if (args.scene != "virtual" && task != Task::push) {
    std::cerr << "a2l-run: --scene " << args.scene << ": a " << task_name(task)
              << " needs the virtual scene's grasp and press semantics (--scene virtual)\n";
    return 2;
  }
  a2l::DSStateValues ds_values0{};
  if (!ds_state_values(skill, args, ds_values0)) return 2;
  bool light0 = false, gripper0 = false;
  for (const auto& kv : args.states) {
    if (kv.first == "light") light0 = kv.second == "on";
    if (kv.first == "gripper") gripper0 = kv.second == "closed";
  }

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
  // the push box, the grasp scene's block, the press scene's button (a2l.sim's defaults)
  const Eigen::Vector3d half = task == Task::grasp   ? Eigen::Vector3d(0.015, 0.015, 0.03)
                               : task == Task::press ? Eigen::Vector3d(0.03, 0.03, 0.01)
                                                     : Eigen::Vector3d(0.035, 0.0425, 0.04);
  const double table_z = object0.z() - half.z();

  std::unique_ptr<a2l::Scene> scene;
  a2l::VirtualScene* virt = nullptr;
  if (args.scene == "virtual") {
    a2l::VirtualSceneOptions vo;
    vo.half_size = half;
    vo.table_z = table_z;
    vo.object_kind = task == Task::grasp   ? a2l::ObjectKind::graspable
                     : task == Task::press ? a2l::ObjectKind::button
                                           : a2l::ObjectKind::box;
    auto v = std::make_unique<a2l::VirtualScene>(vo);
    virt = v.get();
    scene = std::move(v);
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
    if (csv) write_trace_header(trace, skill);
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
      int presses_start = 0;
      if (virt != nullptr) {
        virt->set_light(light0);
        virt->set_gripper(gripper0);
        presses_start = virt->presses();
      }
      state.reset();
      state.clear_trace();
      rows.clear();
      const Eigen::Vector3d obj_start = scene->object_position();
      a2l::Context ctx;
      ctx.effect = effect;
      ctx.high_level = high_level;
      a2l::DSStateValues ds_values = ds_values0;
      int outcome = 0;  // 1 success, 2 false positive, 0 fail
      a2l::StepOutput out;
      while (stop.empty()) {
        if (ds_mode && ctx.effect_produced) {
          stop = "effect_produced";
          break;
        }
        ctx.eef = scene->eef_position();
        ctx.object = scene->object_position();
        if (virt != nullptr) {
          world.apply(virt->light_on(), virt->gripper_closed(), ctx.high_level, ds_values);
        }
        const auto t0 = Clock::now();
        const a2l::Status s = ds_mode
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
        write_trace(trace, csv, skill, episode_id, effect_names[static_cast<size_t>(effect)], rows);
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
  summary["mode"] = args.mode;
  summary["task"] = task_name(task);
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
  print_results(wanted, effect_names, results, summary, total_success, total_episodes);
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
