// The DS phases section of a skill bundle (docs/bundle_format.md, "ds_phases"): parsing and
// validation; every message names the phase's index and the field.
#include <string>

#include "a2l/bundle.hpp"
#include "bundle_json.hpp"

namespace a2l {

namespace {

using namespace bundle_detail;  // NOLINT: the loader's own helpers

bool parse_states(const json& section, DSPhaseSet& set, Errors& e) {
  const json* arr = nullptr;
  if (!get_array(section, "ds_phases.", "states", arr, e)) return false;
  if (arr->size() > static_cast<std::size_t>(kMaxVariables)) {
    return e.parse("ds_phases.states: " + std::to_string(arr->size()) + " states, at most " +
                   std::to_string(kMaxVariables));
  }
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const json& js = (*arr)[i];
    const std::string where = "ds_phases.states[" + std::to_string(i) + "].";
    if (!js.is_object()) return e.parse(where.substr(0, where.size() - 1) + ": must be an object");
    DSStateVariable v;
    const json* values = nullptr;
    if (!get_string(js, where, "name", v.name, e) || !get_array(js, where, "values", values, e)) {
      return false;
    }
    if (v.name.empty()) return e.parse(where + "name: must not be empty");
    if (set.find_state(v.name) >= 0) {
      return e.parse(where + "name: '" + v.name + "' is declared twice");
    }
    if (values->empty() || values->size() > static_cast<std::size_t>(kMaxBins)) {
      return e.parse(where + "values: needs 1 to " + std::to_string(kMaxBins) + " values, got " +
                     std::to_string(values->size()));
    }
    for (std::size_t k = 0; k < values->size(); ++k) {
      std::string s;
      const std::string field = where + "values[" + std::to_string(k) + "]";
      if (!as_string((*values)[k], field, s, e)) return false;
      for (const std::string& prev : v.values) {
        if (prev == s) return e.parse(field + ": '" + s + "' repeats a value");
      }
      v.values.push_back(std::move(s));
    }
    set.states.push_back(std::move(v));
  }
  return true;
}

bool parse_when(const json& jp, const std::string& where, const DSPhaseSet& set, DSPhase& phase,
                Errors& e) {
  const json* when = nullptr;
  if (!get_object(jp, where, "when", when, e)) return false;
  for (auto it = when->begin(); it != when->end(); ++it) {
    const std::string field = where + "when." + it.key();
    const int s = set.find_state(it.key());
    if (s < 0) return e.parse(field + ": not a state of ds_phases.states");
    std::string value;
    if (!as_string(it.value(), field, value, e)) return false;
    const auto& values = set.states[static_cast<std::size_t>(s)].values;
    int index = -1;
    std::string names;
    for (std::size_t k = 0; k < values.size(); ++k) {
      if (values[k] == value) index = static_cast<int>(k);
      names += (k ? ", " : "") + values[k];
    }
    if (index < 0) {
      return e.parse(field + ": '" + value + "' is not a value of the state (" + names + ")");
    }
    phase.when.push_back({s, index});
  }
  return true;
}

}  // namespace

bool bundle_detail::parse_ds_phases(const json& m, const json& arrays, std::uint64_t room,
                                    DSPhaseSet& set, std::vector<DiffeoMaps>& maps,
                                    std::vector<ArrayEntry>& entries, Errors& e) {
  set = DSPhaseSet{};
  maps.clear();
  const json* section = nullptr;
  if (!get_object(m, "", "ds_phases", section, e) || !parse_states(*section, set, e)) {
    return false;
  }
  const json* arr = nullptr;
  if (!get_array(*section, "ds_phases.", "phases", arr, e)) return false;
  if (arr->empty() || arr->size() > static_cast<std::size_t>(kMaxDSPhases)) {
    return e.parse("ds_phases.phases: needs 1 to " + std::to_string(kMaxDSPhases) +
                   " phases, got " + std::to_string(arr->size()));
  }
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const json& jp = (*arr)[i];
    const std::string where = "ds_phases.phases[" + std::to_string(i) + "].";
    if (!jp.is_object()) return e.parse(where.substr(0, where.size() - 1) + ": must be an object");
    DSPhase phase;
    if (!get_string(jp, where, "name", phase.name, e) || !parse_when(jp, where, set, phase, e)) {
      return false;
    }
    const json* action = nullptr;
    if (!get_member(jp, where, "end_action", action, e)) return false;
    if (!action->is_null()) {
      std::string name;
      if (!as_string(*action, where + "end_action", name, e)) return false;
      if (!parse_movement_action(name, phase.end_action)) {
        return e.parse(where + "end_action: unknown action '" + name +
                       "' (open, close, stay, or null)");
      }
    }
    if (!get_number(jp, where, "tolerance", phase.tolerance, e)) return false;
    if (!(phase.tolerance > 0.0)) return e.parse(where + "tolerance: must be > 0");
    const json* ds = nullptr;
    if (!get_object(jp, where, "ds", ds, e)) return false;
    DiffeoMaps mp;
    const std::string prefix = "ds_phase" + std::to_string(i) + "_";
    if (!parse_ds_object(*ds, where + "ds.", arrays, prefix, room, mp, entries, e)) return false;
    if (mp.dim != 3) {
      return e.parse(where + "ds.dim: must be 3 (a phase's DS is 3-D, relative to the object)");
    }
    maps.push_back(std::move(mp));
    set.phases.push_back(std::move(phase));
  }
  return true;
}

bool bundle_detail::read_ds_phases(const std::uint8_t* blob, const std::vector<ArrayEntry>& entries,
                                   std::vector<DiffeoMaps>& maps, DSPhaseSet& set, Errors& e) {
  for (std::size_t i = 0; i < set.phases.size(); ++i) {
    const std::string where = "ds_phases.phases[" + std::to_string(i) + "].ds: ";
    const std::string prefix = "ds_phase" + std::to_string(i) + "_";
    if (!read_ds_maps(blob, entries, prefix, where, maps[i], e)) return false;
    const Result r = DiffeoDS<3>::create(maps[i], set.phases[i].ds);
    if (!r.ok()) return e.parse(where + r.message);
  }
  return true;
}

}  // namespace a2l
