// a2l-run's task semantics: states that follow the scene, effect detection.
#include "task.hpp"

#include <algorithm>

namespace a2l_run {

namespace {

int index_of(const std::vector<std::string>& names, const char* name) {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

StateSlot slot(int at, const std::vector<std::string>& values, const char* v0, const char* v1) {
  StateSlot s;
  s.value_0 = index_of(values, v0);
  s.value_1 = index_of(values, v1);
  if (at >= 0 && s.value_0 >= 0 && s.value_1 >= 0) s.at = at;
  return s;
}

void put(const StateSlot& s, bool on, int* values) noexcept {
  if (s.at >= 0) values[s.at] = on ? s.value_1 : s.value_0;
}

}  // namespace

const char* task_name(Task task) noexcept {
  switch (task) {
    case Task::grasp:
      return "grasp";
    case Task::press:
      return "press";
    case Task::push:
      break;
  }
  return "push";
}

Task resolve_task(const std::string& arg, const std::vector<std::string>& effects) {
  if (arg == "grasp") return Task::grasp;
  if (arg == "press") return Task::press;
  if (arg == "push") return Task::push;
  if (index_of(effects, "grasped") >= 0) return Task::grasp;
  if (index_of(effects, "pressed") >= 0) return Task::press;
  return Task::push;
}

WorldStates WorldStates::of(const a2l::Skill& skill) {
  WorldStates w;
  const a2l::Discretizer& d = skill.discretizer();
  for (int i = 0; i < d.n_variables(); ++i) {
    const a2l::Variable& v = d.variable(i);
    if (v.kind != a2l::VariableKind::high_level) continue;
    if (v.name == "light") w.table_light = slot(i, v.values, "off", "on");
    if (v.name == "gripper") w.table_gripper = slot(i, v.values, "open", "closed");
  }
  const a2l::DSPhaseSet& set = skill.ds_phases();
  for (std::size_t i = 0; i < set.states.size(); ++i) {
    const a2l::DSStateVariable& v = set.states[i];
    if (v.name == "light") w.ds_light = slot(static_cast<int>(i), v.values, "off", "on");
    if (v.name == "gripper") w.ds_gripper = slot(static_cast<int>(i), v.values, "open", "closed");
  }
  return w;
}

void WorldStates::apply(bool light_on, bool gripper_closed,
                        std::array<int, a2l::kMaxVariables>& table,
                        a2l::DSStateValues& ds) const noexcept {
  put(table_light, light_on, table.data());
  put(table_gripper, gripper_closed, table.data());
  put(ds_light, light_on, ds.data());
  put(ds_gripper, gripper_closed, ds.data());
}

EffectDetector EffectDetector::of(Task task, const std::vector<std::string>& effects,
                                  double scale) {
  EffectDetector d;
  d.task = task;
  d.threshold = a2l::kEffectThreshold * scale;
  d.n_classify = effects.size() > 4 ? 8 : 4;
  d.grasped = index_of(effects, "grasped");
  d.pressed = index_of(effects, "pressed");
  d.away = index_of(effects, "away");
  return d;
}

int EffectDetector::detect(const a2l::Scene& scene, const a2l::VirtualScene* virt, bool box_moved,
                           const Eigen::Vector3d& object_start, int presses_start) const noexcept {
  const Eigen::Vector3d obj = scene.object_position();
  if (task == Task::push) {
    return box_moved ? a2l::classify_effect(obj - object_start, n_classify, threshold) : -1;
  }
  if (virt == nullptr) return -1;
  if (task == Task::press) {
    return pressed >= 0 && virt->presses() != presses_start ? pressed : -1;
  }
  if (grasped >= 0 && virt->holding() && obj.z() - object_start.z() >= a2l::kLiftThreshold) {
    return grasped;
  }
  if (away >= 0 && a2l::stayed_away(scene.eef_position(), obj, obj - object_start)) return away;
  return -1;
}

}  // namespace a2l_run
