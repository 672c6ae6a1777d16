#include "a2l/skill.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "rt_guard.hpp"
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
  if (Result r = check_ds_phases(ds_phases); !r.ok()) return r;
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
  out.fallback_reach_ = -1.0;
  out.fallback_near_ = -1.0;
  for (int i = 0; i < discretizer.n_variables(); ++i) {
    const Variable& v = discretizer.variable(i);
    if (v.kind == VariableKind::distance) {
      out.fallback_reach_ = v.high;
      out.fallback_near_ = v.low + (v.high - v.low) / v.n_bins;
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

namespace {

// The top two movements of `p` (lowest index on ties).
void top_two(const double* p, int n, int& first, int& second) noexcept {
  first = 0;
  second = -1;
  for (int m = 1; m < n; ++m) {
    if (p[m] > p[first]) {
      second = first;
      first = m;
    } else if (second < 0 || p[m] > p[second]) {
      second = m;
    }
  }
}

// Whether movement `m` undoes movement `last` (their displacements cancel; an action,
// with no displacement, undoes nothing).
bool undoes(const Skill& skill, int m, int last) noexcept {
  if (last < 0) return false;
  const Eigen::Vector3d& back = skill.movements().displacement(last);
  return back.norm() > 0.0 && (skill.movements().displacement(m) + back).norm() < 1e-9;
}

// Whether movement `m` ends between `near` and `limit` from the object, from `r` = eef -
// object (a fallback step's restriction, Skill::fallback_reach and Skill::fallback_near).
bool within_reach(const Skill& skill, const Eigen::Vector3d& r, double near, double limit,
                  int m) noexcept {
  const double d = (r + skill.movements().displacement(m)).norm();
  return d <= limit + 1e-12 && d >= near - 1e-12;
}

}  // namespace

Status step(const Skill& skill, SkillState& state, const Context& context,
            StepOutput& out) noexcept {
  [[maybe_unused]] const detail::RealTimeSection rt;
  state.begin_step(out);
  TraceRecord& rec = out.record;
  auto finish = [&](Status st) noexcept { return state.finish_step(out, st); };
  if (const Status sized = state.check_sized(skill); sized != Status::ok) return finish(sized);
  const int nv = skill.n_variables();
  const Discretizer& disc = skill.discretizer();
  const PolicyTable& table = skill.table();
  int* bins = state.bins_.data();
  Status s = disc.discretize(context, bins);
  rec.n_variables = nv;
  for (int i = 0; i < nv; ++i)
    rec.bins[static_cast<size_t>(i)] = static_cast<std::int16_t>(bins[i]);

  if (context.effect_produced) return finish(Status::effect_produced);
  if (state.steps_ >= skill.settings().step_cap) return finish(Status::step_cap);
  if (s != Status::ok || !table.in_range(bins)) return finish(Status::unknown_context);

  const std::size_t cell = table.row_index(bins);
  const std::int32_t answer = skill.fallback_row(cell);
  if (answer < 0) return finish(Status::unknown_context);
  const auto row = static_cast<std::size_t>(answer);
  const int am = table.argmax(row);
  rec.fallback = row != cell;

  const bool smooth = state.smoothing == Smoothing::on ||
                      (state.smoothing == Smoothing::from_skill && skill.settings().smoothing);
  // A fallback step ends between min(|r|, near) and max(|r|, reach) from the object
  // (Skill::fallback_near, Skill::fallback_reach).
  const Eigen::Vector3d r = context.eef - context.object;
  const double reach = skill.fallback_reach();
  const bool limited = rec.fallback && reach >= 0.0;
  const double limit = std::max(r.norm(), reach);
  const double near = std::min(r.norm(), skill.fallback_near());
  int chosen = am;
  if (limited && !within_reach(skill, r, near, limit, am)) {
    const double* p = table.posterior_row(row);
    for (int m = 0; m < skill.n_moves(); ++m) {
      if (!within_reach(skill, r, near, limit, m)) continue;
      if (chosen == am || p[m] > p[chosen]) chosen = m;
    }
  }
  double tx = 0.0, ty = 0.0;
  const bool approach = rec.fallback && skill.fallback_target(cell, tx, ty);
  // The run's previous movement. With `approach` no step undoes it unless nothing else is
  // allowed: the step is a function of the context, so a movement undone brings the
  // end-effector back to the context it left, and the run repeats the pair until the cap.
  const bool no_undo = skill.settings().fallback == Fallback::approach;
  const int last = no_undo && state.steps_ > 0 && state.trace_size_ > 0
                       ? state.trace(state.trace_size_ - 1).movement
                       : -1;
  if (approach) {  // head for the fallback cell: the allowed movement ending nearest it
    int best = -1;
    double best_d = 0.0;
    for (int pass = 0; pass < 3 && best < 0; ++pass) {  // 1: undoing allowed; 2: any
      for (int m = 0; m < skill.n_moves(); ++m) {
        if (pass < 2 && limited && !within_reach(skill, r, near, limit, m)) continue;
        if (pass == 0 && undoes(skill, m, last)) continue;
        const Eigen::Vector3d e = r + skill.movements().displacement(m);
        const double d2 = (e.x() - tx) * (e.x() - tx) + (e.y() - ty) * (e.y() - ty);
        if (best < 0 || d2 < best_d) {
          best = m;
          best_d = d2;
        }
      }
    }
    chosen = best;
  }
  double prob = table.posterior_row(row)[chosen];
  if (smooth && !approach) {
    const int nm = skill.n_moves();
    double* avg = state.average_.data();
    int* votes = state.votes_.data();
    for (int m = 0; m < nm; ++m) {
      avg[m] = table.posterior_row(row)[m];
      votes[m] = 0;
    }
    votes[am] = 1;
    int informative = 1;
    const double h = 0.5 * skill.movements().step();
    Context nb = context;
    std::array<int, kMaxVariables> nbins{};
    for (int axis = 0; axis < 3; ++axis) {
      for (int sign = -1; sign <= 1; sign += 2) {
        nb.eef = context.eef;
        nb.eef[axis] += sign * h;
        if (disc.discretize(nb, nbins.data()) != Status::ok || !table.in_range(nbins.data())) {
          continue;
        }
        const std::size_t r = table.row_index(nbins.data());
        const int a = table.argmax(r);
        if (a < 0) continue;  // uniform: no information
        const double* p = table.posterior_row(r);
        for (int m = 0; m < nm; ++m) avg[m] += p[m];
        ++votes[a];
        ++informative;
      }
    }
    for (int m = 0; m < nm; ++m) avg[m] /= informative;
    if (limited) {  // the movements past the reach drop out, unless every one is past it
      int allowed = 0;
      for (int m = 0; m < nm; ++m) allowed += within_reach(skill, r, near, limit, m) ? 1 : 0;
      for (int m = 0; allowed > 0 && m < nm; ++m) {
        if (!within_reach(skill, r, near, limit, m)) avg[m] = -1.0;
      }
    }
    int first = 0, second = -1;
    top_two(avg, nm, first, second);
    chosen = first;
    if (second >= 0 && avg[second] > 0.0 && avg[first] <= 0.95 &&
        avg[second] >= 0.75 * avg[first] && votes[second] > votes[first]) {
      chosen = second;
    }
    prob = avg[chosen];
  }
  if (!approach && undoes(skill, chosen, last)) {  // the next best that does not undo it
    const double* score = smooth ? state.average_.data() : table.posterior_row(row);
    int alt = -1;
    for (int m = 0; m < skill.n_moves(); ++m) {
      if (m == chosen || undoes(skill, m, last)) continue;
      if (limited && !within_reach(skill, r, near, limit, m)) continue;
      if (alt < 0 || score[m] > score[alt]) alt = m;
    }
    if (alt >= 0) {
      chosen = alt;
      prob = score[alt];
    }
  }

  ++state.steps_;
  out.movement = chosen;
  out.probability = prob;
  out.displacement = skill.movements().displacement(chosen);
  out.action = skill.movements().action(chosen);
  rec.movement = chosen;
  rec.probability = prob;
  return finish(Status::ok);
}

}  // namespace a2l
