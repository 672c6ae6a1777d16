// Skill::create (a skill's checks and what it compiles) and SkillState (a run's preallocated
// state and trace ring buffer); the step is in skill_step.cpp, the DS step in skill_ds.cpp.
#include "a2l/skill.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "a2l/effects.hpp"
#include "skill_fallback.hpp"

namespace a2l {

namespace {

// The phases' checks of Skill::create (see there).
Result check_ds_phases(const DSPhaseSet& set) {
  if (set.states.size() > static_cast<std::size_t>(kMaxVariables)) {
    return Result::failure(Status::invalid_argument,
                           "ds_phases.states: at most " + std::to_string(kMaxVariables) +
                               " states, got " + std::to_string(set.states.size()));
  }
  if (set.phases.size() > static_cast<std::size_t>(kMaxDSPhases)) {
    return Result::failure(Status::invalid_argument,
                           "ds_phases.phases: at most " + std::to_string(kMaxDSPhases) +
                               " phases, got " + std::to_string(set.phases.size()));
  }
  for (std::size_t p = 0; p < set.phases.size(); ++p) {
    const DSPhase& ph = set.phases[p];
    const std::string where = "ds_phases.phases[" + std::to_string(p) + "]";
    if (!std::isfinite(ph.tolerance) || !(ph.tolerance > 0.0)) {
      return Result::failure(Status::invalid_argument,
                             where + ".tolerance: must be finite and > 0");
    }
    for (const DSCondition& c : ph.when) {
      if (c.state < 0 || static_cast<std::size_t>(c.state) >= set.states.size() || c.value < 0 ||
          static_cast<std::size_t>(c.value) >=
              set.states[static_cast<std::size_t>(c.state)].values.size()) {
        return Result::failure(Status::invalid_argument,
                               where + ".when: a condition names an undeclared state or value");
      }
    }
  }
  return Result::success();
}

}  // namespace

Result Skill::create(std::string name, Discretizer discretizer, PolicyTable table,
                     MovementRepertoire movements, SkillSettings settings, RobotInfo robot,
                     Skill& out, DSPhaseSet ds_phases) {
  if (table.n_axes() != discretizer.n_variables()) {
    return Result::failure(Status::size_mismatch,
                           "skill: the table has " + std::to_string(table.n_axes()) +
                               " evidence axes for " + std::to_string(discretizer.n_variables()) +
                               " variables");
  }
  for (int i = 0; i < table.n_axes(); ++i) {
    const Variable& v = discretizer.variable(i);
    if (table.shape()[static_cast<size_t>(i)] != v.n_bins) {
      return Result::failure(Status::size_mismatch,
                             "skill: table axis " + std::to_string(i) + " has " +
                                 std::to_string(table.shape()[static_cast<size_t>(i)]) +
                                 " bins, variable '" + v.name + "' has " +
                                 std::to_string(v.n_bins));
    }
  }
  if (table.n_moves() != movements.size()) {
    return Result::failure(Status::size_mismatch,
                           "skill: the table has " + std::to_string(table.n_moves()) +
                               " movements, the repertoire " + std::to_string(movements.size()));
  }
  if (settings.step_cap < 1) {
    return Result::failure(Status::invalid_argument, "execution.step_cap: must be >= 1, got " +
                                                         std::to_string(settings.step_cap));
  }
  if (!std::isfinite(settings.uniform_tolerance) || settings.uniform_tolerance < 0.0) {
    return Result::failure(Status::invalid_argument,
                           "execution.uniform_tolerance: must be finite and >= 0");
  }
  if (!std::isfinite(settings.clearance) || settings.clearance < 0.0) {
    return Result::failure(Status::invalid_argument,
                           "execution.clearance: must be finite and >= 0");
  }
  if (!(settings.clearance_ratio > 0.0 && settings.clearance_ratio <= 1.0)) {
    return Result::failure(Status::invalid_argument,
                           "execution.clearance_ratio: must be in (0, 1]");
  }
  if (!std::isfinite(settings.align) || settings.align < 0.0) {
    return Result::failure(Status::invalid_argument, "execution.align: must be finite and >= 0");
  }
  if (Result r = check_ds_phases(ds_phases); !r.ok()) return r;
  std::vector<Eigen::Vector2d> push_directions;
  if (discretizer.effect_axis() >= 0) {
    for (const std::string& value : discretizer.variable(discretizer.effect_axis()).values) {
      const Eigen::Vector2d u = effect_direction(effect_index(value));
      push_directions.push_back(u.norm() > 0.0 ? Eigen::Vector2d(u.normalized()) : u);
    }
  }
  std::vector<std::int32_t> fallback;
  if (settings.fallback != Fallback::none) {
    if (Result r = detail::compile_fallback(discretizer, table, fallback); !r.ok()) return r;
  }
  std::vector<double> targets;
  if (settings.fallback == Fallback::approach) {
    detail::compile_targets(discretizer, table, fallback, targets);
  }
  out.fallback_ = std::move(fallback);
  out.targets_ = std::move(targets);
  out.push_directions_ = std::move(push_directions);
  out.fallback_reach_ = -1.0;
  out.fallback_near_ = -1.0;
  for (int i = 0; i < discretizer.n_variables(); ++i) {
    const Variable& v = discretizer.variable(i);
    if (v.kind == VariableKind::distance) {
      out.fallback_reach_ = range_upper_end(v);
      out.fallback_near_ = first_bin_edge(v);
      break;
    }
  }
  out.name_ = std::move(name);
  out.discretizer_ = std::move(discretizer);
  out.table_ = std::move(table);
  out.movements_ = std::move(movements);
  out.settings_ = settings;
  out.robot_ = std::move(robot);
  out.ds_phases_ = std::move(ds_phases);
  return Result::success();
}

SkillState::SkillState(const Skill& skill, std::size_t trace_capacity)
    : n_variables_(skill.loaded() ? skill.n_variables() : -1),
      n_moves_(skill.n_moves()),
      average_(static_cast<size_t>(std::max(skill.n_moves(), 1)), 0.0),
      votes_(static_cast<size_t>(std::max(skill.n_moves(), 1)), 0),
      spent_(static_cast<size_t>(std::max(skill.n_moves(), 1)), 0),
      path_(std::min(static_cast<std::size_t>(std::max(skill.settings().step_cap, 1)), kMaxPath)),
      path_moves_(path_.size(), -1),
      trace_(std::max<std::size_t>(trace_capacity, 1)) {}

void SkillState::push(const TraceRecord& r) noexcept {
  if (trace_.empty()) return;
  const std::size_t cap = trace_.size();
  if (trace_size_ < cap) {
    trace_[(trace_head_ + trace_size_) % cap] = r;
    ++trace_size_;
  } else {
    trace_[trace_head_] = r;
    trace_head_ = (trace_head_ + 1) % cap;
    ++dropped_;
  }
}

void SkillState::begin_step(StepOutput& out) const noexcept {
  out.movement = -1;
  out.probability = 0.0;
  out.displacement.setZero();
  out.action = MovementAction::none;
  TraceRecord& rec = out.record;
  rec.step = calls_;
  rec.movement = -1;
  rec.probability = 0.0;
  rec.n_variables = 0;
  rec.phase = -1;
  rec.fallback = false;
}

Status SkillState::finish_step(StepOutput& out, Status s) noexcept {
  out.status = s;
  out.record.status = s;
  if (n_variables_ >= 0) {
    push(out.record);
    ++calls_;
  }
  return s;
}

Status SkillState::check_sized(const Skill& skill) const noexcept {
  if (!skill.loaded() || n_variables_ < 0) return Status::not_initialized;
  if (n_variables_ != skill.n_variables() || n_moves_ != skill.n_moves()) {
    return Status::size_mismatch;
  }
  return Status::ok;
}

}  // namespace a2l
