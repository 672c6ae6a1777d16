// a2l-run's records: the trace of each episode and the results per effect.
#include "records.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace a2l_run {

void write_trace_header(std::ostream& out, const a2l::Skill& skill) {
  out << "episode,effect,step,status,movement,label,probability";
  for (const auto& v : skill.discretizer().variables()) out << ",bin_" << v.name;
  out << ",eef_x,eef_y,eef_z,obj_x,obj_y,obj_z,phase,fallback\n";
}

void write_trace(std::ostream& out, bool csv, const a2l::Skill& skill, int episode,
                 const std::string& effect, const std::vector<TraceRow>& rows) {
  for (const TraceRow& row : rows) {
    const a2l::TraceRecord& r = row.record;
    const std::string label = r.movement >= 0 ? skill.movements().label(r.movement)
                              : r.phase >= 0 && r.status == a2l::Status::ok ? "ds"
                                                                            : "";
    if (csv) {
      out << episode << "," << effect << "," << r.step << "," << a2l::status_name(r.status) << ","
          << r.movement << "," << label << "," << r.probability;
      for (int i = 0; i < r.n_variables; ++i) out << "," << r.bins[static_cast<size_t>(i)];
      out << "," << row.eef.x() << "," << row.eef.y() << "," << row.eef.z() << "," << row.object.x()
          << "," << row.object.y() << "," << row.object.z() << "," << r.phase << ","
          << (r.fallback ? 1 : 0) << "\n";
      continue;
    }
    nlohmann::json j;
    j["episode"] = episode;
    j["effect"] = effect;
    j["step"] = r.step;
    j["status"] = a2l::status_name(r.status);
    j["movement"] = r.movement;
    j["label"] = label;
    j["probability"] = r.probability;
    j["fallback"] = r.fallback;
    nlohmann::json bins = nlohmann::json::object();
    for (int i = 0; i < r.n_variables; ++i) {
      bins[skill.discretizer().variable(i).name] = r.bins[static_cast<size_t>(i)];
    }
    j["bins"] = bins;
    j["eef"] = {row.eef.x(), row.eef.y(), row.eef.z()};
    j["object"] = {row.object.x(), row.object.y(), row.object.z()};
    if (r.phase >= 0) {
      j["phase"] = skill.ds_phases().phases[static_cast<std::size_t>(r.phase)].name;
    }
    out << j.dump() << "\n";
  }
}

void print_results(const std::vector<int>& wanted, const std::vector<std::string>& effect_names,
                   const std::vector<EffectResult>& results, nlohmann::json& summary,
                   int& total_success, int& total_episodes) {
  std::printf("%-12s %8s %10s %6s %14s  %s\n", "effect", "success", "false_pos", "fail",
              "steps/action", "stops");
  for (int effect : wanted) {
    const EffectResult& r = results[static_cast<size_t>(effect)];
    const int n = r.success + r.false_positive + r.fail;
    total_success += r.success;
    total_episodes += n;
    const double spa = r.success ? static_cast<double>(r.steps_success) / r.success : 0.0;
    std::string stops;
    for (const auto& kv : r.stops) {
      stops += (stops.empty() ? "" : ", ") + kv.first + " " + std::to_string(kv.second);
    }
    std::printf("%-12s %5d/%-3d %10d %6d %14.2f  %s\n",
                effect_names[static_cast<size_t>(effect)].c_str(), r.success, n, r.false_positive,
                r.fail, spa, stops.c_str());
    summary["effects"][effect_names[static_cast<size_t>(effect)]] = {
        {"episodes", n},  {"success", r.success},    {"false_positive", r.false_positive},
        {"fail", r.fail}, {"steps_per_action", spa}, {"stops", r.stops}};
  }
  std::printf("success %d/%d (%.1f%%)\n", total_success, total_episodes,
              total_episodes ? 100.0 * total_success / total_episodes : 0.0);
}

bool ds_state_values(const a2l::Skill& skill, const Args& args, a2l::DSStateValues& out) {
  out.fill(0);
  const a2l::DSPhaseSet& set = skill.ds_phases();
  for (const auto& kv : args.states) {
    const int s = set.find_state(kv.first);
    if (s < 0) continue;
    const auto& values = set.states[static_cast<std::size_t>(s)].values;
    const auto it = std::find(values.begin(), values.end(), kv.second);
    if (it == values.end()) {
      std::cerr << "a2l-run: --state: '" << kv.second << "' is not a value of the DS phases' "
                << "state '" << kv.first << "'\n";
      return false;
    }
    out[static_cast<std::size_t>(s)] = static_cast<int>(it - values.begin());
  }
  return true;
}

}  // namespace a2l_run
