// a2l-run's report: results, timings, summary.
#include "report.hpp"

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "support.hpp"

namespace a2l_run {

int report(const Args& args, const a2l::Skill& skill, const Request& request, const Robot& robot,
           const std::vector<EffectResult>& results, const Timings& timings, std::ofstream& trace) {
  const Percentiles sp = percentiles(timings.step_us), tp = percentiles(timings.tick_us),
                    lp = percentiles(timings.late_us);
  const double elapsed = timings.elapsed;
  nlohmann::json summary;
  summary["bundle"] = args.bundle;
  summary["skill"] = skill.name();
  summary["scene"] = args.scene;
  summary["mode"] = args.mode;
  summary["task"] = task_name(request.task);
  summary["robot"] = robot.desc;
  summary["episodes_per_effect"] = args.episodes;
  summary["rate_hz"] = args.rate;
  summary["seed"] = args.seed;
  summary["starts"] = {{"mode", args.starts}, {"description", describe_starts(args)}};
  if (args.starts == "random") {
    summary["starts"]["radius_range"] = {args.radius_min, args.radius_max};
  } else {
    summary["starts"]["radius"] = args.radius;
  }
  if (!robot.urdf_hash.empty()) summary["urdf_sha256"] = robot.urdf_hash;
  if (robot.from_file) {
    summary["robot_file"] = {{"path", robot.file.source},
                             {"name", robot.file.name},
                             {"scene_scale", robot.file.scene.scale}};
  }
  int total_success = 0, total_episodes = 0;
  print_results(request.wanted, request.effect_names, results, summary, total_success,
                total_episodes);
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
  const long long total_steps = timings.total_steps, total_ticks = timings.total_ticks;
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

}  // namespace a2l_run
