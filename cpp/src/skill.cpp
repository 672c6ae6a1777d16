#include "a2l/skill.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "rt_guard.hpp"

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

// The bins of table row `row` into `bins` (C order, strides of `table`).
void bins_of(const PolicyTable& table, std::size_t row, int* bins) noexcept {
  const auto& strides = table.strides();
  for (std::size_t i = 0; i < strides.size(); ++i) {
    bins[i] = static_cast<int>(row / strides[i]);
    row %= strides[i];
  }
}

// The nearest-cell fallback of every row (Skill::fallback_row): a row's own index where it
// is informative; else the nearest informative row with the same effect and high-level
// values, or -1.
Result compile_fallback(const Discretizer& disc, const PolicyTable& table,
                        std::vector<std::int32_t>& out) {
  const std::size_t rows = table.n_rows();
  const int na = table.n_axes();
  std::size_t uniform = 0;
  for (std::size_t r = 0; r < rows; ++r) uniform += table.argmax(r) < 0 ? 1 : 0;
  if (uniform != 0 && rows > kMaxFallbackWork / uniform) {
    return Result::failure(Status::invalid_argument,
                           "execution.fallback: 'nearest' on a table of " + std::to_string(rows) +
                               " rows with " + std::to_string(uniform) +
                               " uniform ones is too large to compile");
  }
  if (rows > static_cast<std::size_t>(INT32_MAX)) {
    return Result::failure(Status::invalid_argument,
                           "execution.fallback: too many rows for 'nearest'");
  }
  out.assign(rows, -1);
  std::vector<int> a(static_cast<std::size_t>(na)), b(static_cast<std::size_t>(na));
  for (std::size_t r = 0; r < rows; ++r) {
    if (table.argmax(r) >= 0) {
      out[r] = static_cast<std::int32_t>(r);
      continue;
    }
    bins_of(table, r, a.data());
    long best = -1;
    for (std::size_t q = 0; q < rows; ++q) {
      if (table.argmax(q) < 0) continue;
      bins_of(table, q, b.data());
      long d = 0;
      for (int i = 0; i < na && d >= 0; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const Variable& v = disc.variable(i);
        int diff = std::abs(a[k] - b[k]);
        if (!is_geometric(v.kind)) {
          if (diff != 0) d = -1;  // another effect or high-level value: not a neighbour
          continue;
        }
        if (v.kind == VariableKind::orientation) diff = std::min(diff, v.n_bins - diff);
        d += diff;
      }
      if (d >= 0 && (best < 0 || d < best)) {
        best = d;
        out[r] = static_cast<std::int32_t>(q);
      }
    }
  }
  return Result::success();
}

// The centre of every fallback row's cell (Skill::fallback_target) into `out` (2 per row),
// or `out` empty unless the discretizer's geometric variables are one distance and one
// orientation (a cell is then a sector of a ring around the object).
void compile_targets(const Discretizer& disc, const PolicyTable& table,
                     const std::vector<std::int32_t>& fallback, std::vector<double>& out) {
  out.clear();
  int id = -1, io = -1, others = 0;
  for (int i = 0; i < disc.n_variables(); ++i) {
    const VariableKind k = disc.variable(i).kind;
    if (k == VariableKind::distance && id < 0) {
      id = i;
    } else if (k == VariableKind::orientation && io < 0) {
      io = i;
    } else if (is_geometric(k)) {
      ++others;
    }
  }
  if (id < 0 || io < 0 || others > 0) return;
  const Variable& vd = disc.variable(id);
  const Variable& vo = disc.variable(io);
  const double wd = (vd.high - vd.low) / vd.n_bins;
  const double wo = 2.0 * std::acos(-1.0) / vo.n_bins;
  const std::size_t rows = table.n_rows();
  out.assign(2 * rows, 0.0);
  std::vector<int> b(static_cast<std::size_t>(table.n_axes()));
  for (std::size_t r = 0; r < rows; ++r) {
    if (fallback[r] < 0) continue;
    bins_of(table, static_cast<std::size_t>(fallback[r]), b.data());
    const double d = vd.low + (b[static_cast<std::size_t>(id)] + 0.5) * wd;
    const double a = -std::acos(-1.0) + b[static_cast<std::size_t>(io)] * wo;  // bin centre
    out[2 * r] = d * std::cos(a);
    out[2 * r + 1] = d * std::sin(a);
  }
}

}  // namespace

const char* fallback_name(Fallback f) noexcept {
  switch (f) {
    case Fallback::nearest:
      return "nearest";
    case Fallback::approach:
      return "approach";
    case Fallback::none:
      break;
  }
  return "none";
}

bool parse_fallback(const std::string& name, Fallback& out) noexcept {
  if (name == "none") {
    out = Fallback::none;
    return true;
  }
  if (name == "nearest") {
    out = Fallback::nearest;
    return true;
  }
  if (name == "approach") {
    out = Fallback::approach;
    return true;
  }
  return false;
}

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
    if (Result r = compile_fallback(discretizer, table, fallback); !r.ok()) return r;
  }
  std::vector<double> targets;
  if (settings.fallback == Fallback::approach) {
    compile_targets(discretizer, table, fallback, targets);
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
