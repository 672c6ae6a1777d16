// a2l-run's request: the command line resolved against the skill.
#include "request.hpp"

#include <algorithm>
#include <iostream>

#include "records.hpp"

namespace a2l_run {

int resolve_request(Args& args, const a2l::Skill& skill, Request& out) {
  const a2l::Discretizer& disc = skill.discretizer();
  const int effect_axis = disc.effect_axis();
  if (effect_axis < 0) {
    std::cerr << "a2l-run: skill bundle '" << args.bundle
              << "': the table has no effect variable, a2l-run cannot ask for an effect\n";
    return 2;
  }
  out.effect_names = disc.variable(effect_axis).values;
  const std::vector<std::string>& effect_names = out.effect_names;
  std::vector<int>& wanted = out.wanted;
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
    out.high_level[static_cast<size_t>(axis)] = static_cast<int>(it - v.values.begin());
  }
  const Task task = out.task = resolve_task(args.task, effect_names);
  if (task != Task::push) {  // start above the object, closer
    if (!args.has_start_height) args.start_height = 0.15;
    if (!args.has_radius_range) {
      args.radius_min = 0.02;
      args.radius_max = 0.10;
    }
  }
  out.ds_mode = args.mode == "ds";
  if (out.ds_mode && skill.ds_phases().empty()) {
    std::cerr << "a2l-run: --mode ds: skill bundle '" << args.bundle
              << "' has no DS phases (section ds_phases)\n";
    return 2;
  }
  if (args.scene != "virtual" && task != Task::push) {
    std::cerr << "a2l-run: --scene " << args.scene << ": a " << task_name(task)
              << " needs the virtual scene's grasp and press semantics (--scene virtual)\n";
    return 2;
  }
  if (!ds_state_values(skill, args, out.ds_values)) return 2;
  for (const auto& kv : args.states) {
    if (kv.first == "light") out.light = kv.second == "on";
    if (kv.first == "gripper") out.gripper = kv.second == "closed";
  }
  return 0;
}

}  // namespace a2l_run
