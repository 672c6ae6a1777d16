// The skill sections of a bundle's manifest (docs/bundle_format.md): robot, variables,
// movements (directions, labels, actions) and execution settings.
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "a2l/bundle.hpp"
#include "bundle_json.hpp"

namespace a2l {

using namespace bundle_detail;  // NOLINT: the loader's own helpers

bool bundle_detail::parse_robot(const json& m, RobotInfo& robot, Errors& e) {
  const json* r = nullptr;
  if (!get_member(m, "", "robot", r, e)) return false;
  robot = RobotInfo{};
  if (r->is_null()) return true;
  if (!r->is_object())
    return e.parse(std::string("robot: must be an object or null, got ") + type_name(*r));
  robot.present = true;
  return get_string(*r, "robot.", "name", robot.name, e) &&
         get_string(*r, "robot.", "urdf_sha256", robot.urdf_sha256, e) &&
         get_string(*r, "robot.", "base_link", robot.base_link, e) &&
         get_string(*r, "robot.", "tip_link", robot.tip_link, e);
}

namespace {

// The optional "edges" of variable `jv` (`where` = "variables[i].") into v.edges: a distance
// only, 1 to kMaxBins - 1 finite numbers, > 0, strictly increasing, n_bins = edges + 1.
bool parse_edges(const json& jv, const std::string& where, Variable& v, Errors& e) {
  const auto it = jv.find("edges");
  if (it == jv.end()) return true;
  if (v.kind != VariableKind::distance) {
    return e.parse(where + "edges: '" + v.name + "' is of kind " + variable_kind_name(v.kind) +
                   ", only a distance variable may have edges");
  }
  if (!it->is_array()) {
    return e.parse(where + "edges: must be an array of numbers, got " + type_name(*it));
  }
  if (it->empty() || it->size() > static_cast<size_t>(kMaxBins - 1)) {
    return e.parse(where + "edges: needs 1 to " + std::to_string(kMaxBins - 1) + " edges, got " +
                   std::to_string(it->size()));
  }
  for (size_t k = 0; k < it->size(); ++k) {
    const json& x = (*it)[k];
    const std::string field = where + "edges[" + std::to_string(k) + "]";
    if (!x.is_number()) return e.parse(field + ": must be a number, got " + type_name(x));
    const double d = x.get<double>();
    std::ostringstream ss;
    ss << field << ": " << d;
    if (!std::isfinite(d) || !(d > 0.0)) return e.parse(ss.str() + " (must be finite and > 0)");
    if (k > 0 && !(d > v.edges.back())) {
      ss << " is not above edges[" << k - 1 << "] = " << v.edges.back()
         << " (edges must be strictly increasing)";
      return e.parse(ss.str());
    }
    v.edges.push_back(d);
  }
  if (static_cast<size_t>(v.n_bins) != v.edges.size() + 1) {
    return e.parse(where + "n_bins: " + std::to_string(v.n_bins) + ", but " +
                   std::to_string(v.edges.size()) + " edges make " +
                   std::to_string(v.edges.size() + 1) + " bins ('" + v.name + "')");
  }
  return true;
}

}  // namespace

bool bundle_detail::parse_variables(const json& m, std::vector<Variable>& vars, Errors& e) {
  const json* arr = nullptr;
  if (!get_array(m, "", "variables", arr, e)) return false;
  if (arr->size() > static_cast<size_t>(kMaxVariables)) {
    return e.parse("variables: " + std::to_string(arr->size()) + " variables, at most " +
                   std::to_string(kMaxVariables) + " are supported");
  }
  for (size_t i = 0; i < arr->size(); ++i) {
    const json& jv = (*arr)[i];
    const std::string where = "variables[" + std::to_string(i) + "].";
    if (!jv.is_object()) return e.parse(where.substr(0, where.size() - 1) + ": must be an object");
    Variable v;
    std::string kind;
    if (!get_string(jv, where, "name", v.name, e) || !get_string(jv, where, "kind", kind, e)) {
      return false;
    }
    if (!parse_variable_kind(kind, v.kind)) {
      return e.parse(
          where + "kind: unknown kind '" + kind +
          "' (effect, distance, orientation, inclination, high_level, offset_x, offset_y)");
    }
    if (v.kind == VariableKind::effect || v.kind == VariableKind::high_level) {
      const json* values = nullptr;
      if (!get_array(jv, where, "values", values, e)) return false;
      if (values->empty() || values->size() > static_cast<size_t>(kMaxBins)) {
        return e.parse(where + "values: needs 1 to " + std::to_string(kMaxBins) + " values, got " +
                       std::to_string(values->size()));
      }
      for (size_t k = 0; k < values->size(); ++k) {
        std::string s;
        if (!as_string((*values)[k], where + "values[" + std::to_string(k) + "]", s, e)) {
          return false;
        }
        v.values.push_back(std::move(s));
      }
      v.n_bins = static_cast<int>(v.values.size());
    } else {
      std::int64_t n = 0;
      if (!get_int(jv, where, "n_bins", 1, kMaxBins, n, e)) return false;
      v.n_bins = static_cast<int>(n);
    }
    if (has_range(v.kind)) {
      if (!get_number(jv, where, "low", v.low, e) || !get_number(jv, where, "high", v.high, e)) {
        return false;
      }
      if (!(v.low < v.high)) return e.parse(where + "low/high: requires low < high");
    }
    if (!parse_edges(jv, where, v, e)) return false;
    vars.push_back(std::move(v));
  }
  return true;
}

bool bundle_detail::parse_movements(const json& m, double& step, std::vector<Eigen::Vector3i>& dirs,
                                    std::vector<std::string>& labels,
                                    std::vector<MovementAction>& actions, Errors& e) {
  const json* mv = nullptr;
  if (!get_object(m, "", "movements", mv, e)) return false;
  if (!get_number(*mv, "movements.", "step", step, e)) return false;
  if (!(step > 0.0)) return e.parse("movements.step: must be > 0");
  const json* d = nullptr;
  if (!get_array(*mv, "movements.", "directions", d, e)) return false;
  if (d->empty() || d->size() > static_cast<size_t>(kMaxMoves)) {
    return e.parse("movements.directions: needs 1 to " + std::to_string(kMaxMoves) +
                   " movements, got " + std::to_string(d->size()));
  }
  for (size_t i = 0; i < d->size(); ++i) {
    const json& row = (*d)[i];
    const std::string field = "movements.directions[" + std::to_string(i) + "]";
    if (!row.is_array() || row.size() != 3) return e.parse(field + ": must be an array of 3 signs");
    Eigen::Vector3i v;
    for (int k = 0; k < 3; ++k) {
      std::int64_t x = 0;
      if (!as_int(row[static_cast<size_t>(k)], field + "[" + std::to_string(k) + "]", -1, 1, x,
                  e)) {
        return false;
      }
      v[k] = static_cast<int>(x);
    }
    if (v.isZero()) return e.parse(field + ": all zero (not a movement)");
    dirs.push_back(v);
  }
  const json* l = nullptr;
  if (!get_array(*mv, "movements.", "labels", l, e)) return false;
  if (l->size() != d->size()) {
    return e.parse("movements.labels: " + std::to_string(l->size()) + " labels for " +
                   std::to_string(d->size()) + " directions");
  }
  for (size_t i = 0; i < l->size(); ++i) {
    std::string s;
    if (!as_string((*l)[i], "movements.labels[" + std::to_string(i) + "]", s, e)) return false;
    labels.push_back(std::move(s));
  }
  const json* a = nullptr;
  if (!get_array(*mv, "movements.", "actions", a, e)) return false;
  if (a->size() + d->size() > static_cast<size_t>(kMaxMoves)) {
    return e.parse("movements.actions: " + std::to_string(a->size()) + " actions and " +
                   std::to_string(d->size()) + " directions, at most " + std::to_string(kMaxMoves) +
                   " movements");
  }
  for (size_t i = 0; i < a->size(); ++i) {
    const std::string field = "movements.actions[" + std::to_string(i) + "]";
    std::string s;
    if (!as_string((*a)[i], field, s, e)) return false;
    MovementAction act = MovementAction::none;
    if (!parse_movement_action(s, act)) {
      return e.parse(field + ": unknown action '" + s + "' (open, close, stay)");
    }
    for (size_t k = 0; k < actions.size(); ++k) {
      if (actions[k] == act) {
        return e.parse(field + ": '" + s + "' repeats movements.actions[" + std::to_string(k) +
                       "]");
      }
    }
    actions.push_back(act);
  }
  return true;
}

bool bundle_detail::parse_execution(const json& m, SkillSettings& s, Errors& e) {
  const json* x = nullptr;
  if (!get_object(m, "", "execution", x, e)) return false;
  std::int64_t cap = 0;
  if (!get_int(*x, "execution.", "step_cap", 1, 1000000, cap, e)) return false;
  s.step_cap = static_cast<int>(cap);
  if (!get_bool(*x, "execution.", "smoothing", s.smoothing, e)) return false;
  if (!get_number(*x, "execution.", "uniform_tolerance", s.uniform_tolerance, e)) return false;
  if (s.uniform_tolerance < 0.0) return e.parse("execution.uniform_tolerance: must be >= 0");
  s.clearance = 0.0;  // optional key: bundles written before it have no clearance rule
  if (x->contains("clearance")) {
    if (!get_number(*x, "execution.", "clearance", s.clearance, e)) return false;
    if (s.clearance < 0.0) return e.parse("execution.clearance: must be >= 0 (m)");
  }
  s.clearance_ratio = kClearanceRatio;  // optional key: bundles written before it have 0.5
  if (x->contains("clearance_ratio")) {
    if (!get_number(*x, "execution.", "clearance_ratio", s.clearance_ratio, e)) return false;
    if (!(s.clearance_ratio > 0.0 && s.clearance_ratio <= 1.0)) {
      return e.parse("execution.clearance_ratio: must be in (0, 1]");
    }
  }
  s.align = 0.0;  // optional key: bundles written before it have no alignment rule
  if (x->contains("align")) {
    if (!get_number(*x, "execution.", "align", s.align, e)) return false;
    if (s.align < 0.0) return e.parse("execution.align: must be >= 0 (m)");
  }
  s.avoid_revisits = false;  // optional key: bundles written before it have no revisit rule
  if (x->contains("avoid_revisits")) {
    if (!get_bool(*x, "execution.", "avoid_revisits", s.avoid_revisits, e)) return false;
  }
  s.fallback = Fallback::none;  // optional key: bundles written before it have none
  if (x->contains("fallback")) {
    std::string name;
    if (!get_string(*x, "execution.", "fallback", name, e)) return false;
    if (!parse_fallback(name, s.fallback)) {
      return e.parse("execution.fallback: '" + name + "' is not 'none', 'nearest' or 'approach'");
    }
  }
  return true;
}

}  // namespace a2l
