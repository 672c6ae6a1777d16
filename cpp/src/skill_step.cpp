// step(): one step of a skill's policy table (skill.hpp): the context's row (or its fallback
// row), the reach of a fallback step, the approach fallback, smoothing, then the rules of
// skill_rules.hpp (no undo, the revisit rule, the clearance rule, the alignment rule).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "a2l/skill.hpp"
#include "rt_guard.hpp"
#include "skill_rules.hpp"

namespace a2l {

namespace {

using detail::Excluded;
using detail::Reach;

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

Reach reach_of(const Skill& skill, const Context& context, bool fallback) noexcept {
  Reach reach;
  reach.r = context.eef - context.object;
  const double reach_limit = skill.fallback_reach();
  reach.limited = fallback && reach_limit >= 0.0;
  reach.limit = std::max(reach.r.norm(), reach_limit);
  reach.near = std::min(reach.r.norm(), skill.fallback_near());
  return reach;
}

// The context's bins into `bins` and the step's record; the discretizer's status.
Status record_bins(const Discretizer& disc, const Context& context, int* bins,
                   TraceRecord& rec) noexcept {
  const Status s = disc.discretize(context, bins);
  const int nv = disc.n_variables();
  rec.n_variables = nv;
  for (int i = 0; i < nv; ++i)
    rec.bins[static_cast<size_t>(i)] = static_cast<std::int16_t>(bins[i]);
  return s;
}

// Why the step gives no movement before looking at the table (an effect produced, the step
// cap, a context out of the table: `binned` the discretizer's status), or ok.
Status admit(const Skill& skill, const Context& context, int steps, Status binned,
             const int* bins) noexcept {
  if (context.effect_produced) return Status::effect_produced;
  if (steps >= skill.settings().step_cap) return Status::step_cap;
  if (binned != Status::ok || !skill.table().in_range(bins)) return Status::unknown_context;
  return Status::ok;
}

// The context's cell and the row answering for it (the cell's own or its fallback row,
// Skill::fallback_row); false when no row answers.
bool answer_row(const Skill& skill, const int* bins, std::size_t& cell, std::size_t& row) noexcept {
  cell = skill.table().row_index(bins);
  const std::int32_t answer = skill.fallback_row(cell);
  if (answer < 0) return false;
  row = static_cast<std::size_t>(answer);
  return true;
}

// Whether the step smooths (SkillState::smoothing, else the skill's setting).
bool smoothing_on(const Skill& skill, const SkillState& state) noexcept {
  return state.smoothing == Smoothing::on ||
         (state.smoothing == Smoothing::from_skill && skill.settings().smoothing);
}

// The run's previous movement, which a step with the `approach` fallback does not undo unless
// nothing else is allowed (the step is a function of the context, so a movement undone brings
// the end-effector back to the context it left, and the run repeats the pair until the cap);
// -1 without `approach` or before the run's first step.
int previous_movement(const Skill& skill, const SkillState& state) noexcept {
  const bool no_undo = skill.settings().fallback == Fallback::approach;
  return no_undo && state.steps() > 0 && state.trace_size() > 0
             ? state.trace(state.trace_size() - 1).movement
             : -1;
}

// Row `row`'s argmax `am` if the reach allows it, else the most probable movement it allows
// (`am` if it allows none).
int best_within_reach(const Skill& skill, const Reach& reach, std::size_t row, int am) noexcept {
  int chosen = am;
  if (reach.allows(skill, am)) return chosen;
  const double* p = skill.table().posterior_row(row);
  for (int m = 0; m < skill.n_moves(); ++m) {
    if (!reach.allows(skill, m)) continue;
    if (chosen == am || p[m] > p[chosen]) chosen = m;
  }
  return chosen;
}

// The `approach` fallback: the allowed movement ending nearest the fallback cell's centre
// (tx, ty) relative to the object; pass 0 leaves out the `excluded` movements, pass 1 allows
// them, pass 2 any movement.
int approach_move(const Skill& skill, const Reach& reach, const Excluded& excluded, double tx,
                  double ty) noexcept {
  int best = -1;
  double best_d = 0.0;
  for (int pass = 0; pass < 3 && best < 0; ++pass) {
    for (int m = 0; m < skill.n_moves(); ++m) {
      if (pass < 2 && !reach.allows(skill, m)) continue;
      if (pass == 0 && excluded(skill, m)) continue;
      const Eigen::Vector3d e = reach.r + skill.movements().displacement(m);
      const double d2 = (e.x() - tx) * (e.x() - tx) + (e.y() - ty) * (e.y() - ty);
      if (best < 0 || d2 < best_d) {
        best = m;
        best_d = d2;
      }
    }
  }
  return best;
}

// Smoothing's average: row `row`'s posterior and those of the six neighbours half a
// movement away along each axis (the informative ones) into `avg`, their argmax counts into
// `votes` (`am` row `row`'s argmax).
void average_neighbours(const Skill& skill, const Context& context, std::size_t row, int am,
                        double* avg, int* votes) noexcept {
  const PolicyTable& table = skill.table();
  const int nm = skill.n_moves();
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
      if (skill.discretizer().discretize(nb, nbins.data()) != Status::ok ||
          !table.in_range(nbins.data())) {
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
}

// The movements past the reach drop out of the average (-1), unless every one is past it.
void drop_out_of_reach(const Skill& skill, const Reach& reach, double* avg) noexcept {
  if (!reach.limited) return;
  const int nm = skill.n_moves();
  int allowed = 0;
  for (int m = 0; m < nm; ++m) allowed += reach.allows(skill, m) ? 1 : 0;
  for (int m = 0; allowed > 0 && m < nm; ++m) {
    if (!reach.allows(skill, m)) avg[m] = -1.0;
  }
}

// The smoothed choice: the top average, or the second when it is close, the first not sure
// and the neighbours vote for the second more often; its average into `prob`.
int smoothed_move(const Skill& skill, const Context& context, const Reach& reach, std::size_t row,
                  int am, double* avg, int* votes, double& prob) noexcept {
  average_neighbours(skill, context, row, am, avg, votes);
  drop_out_of_reach(skill, reach, avg);
  int first = 0, second = -1;
  top_two(avg, skill.n_moves(), first, second);
  int chosen = first;
  if (second >= 0 && avg[second] > 0.0 && avg[first] <= 0.95 && avg[second] >= 0.75 * avg[first] &&
      votes[second] > votes[first]) {
    chosen = second;
  }
  prob = avg[chosen];
  return chosen;
}

// The chosen movement into the step's output and record.
void emit(const Skill& skill, int chosen, double prob, StepOutput& out) noexcept {
  out.movement = chosen;
  out.probability = prob;
  out.displacement = skill.movements().displacement(chosen);
  out.action = skill.movements().action(chosen);
  out.record.movement = chosen;
  out.record.probability = prob;
}

}  // namespace

Status step(const Skill& skill, SkillState& state, const Context& context,
            StepOutput& out) noexcept {
  [[maybe_unused]] const detail::RealTimeSection rt;
  state.begin_step(out);
  auto finish = [&](Status st) noexcept { return state.finish_step(out, st); };
  if (const Status sized = state.check_sized(skill); sized != Status::ok) return finish(sized);
  int* bins = state.bins_.data();
  const Status binned = record_bins(skill.discretizer(), context, bins, out.record);
  if (const Status admitted = admit(skill, context, state.steps_, binned, bins);
      admitted != Status::ok) {
    return finish(admitted);
  }
  std::size_t cell = 0, row = 0;
  if (!answer_row(skill, bins, cell, row)) return finish(Status::unknown_context);
  const int am = skill.table().argmax(row);
  out.record.fallback = row != cell;
  const Reach reach = reach_of(skill, context, out.record.fallback);
  int chosen = best_within_reach(skill, reach, row, am);
  double tx = 0.0, ty = 0.0;
  const bool approach = out.record.fallback && skill.fallback_target(cell, tx, ty);
  const bool any_spent = detail::mark_spent(skill, state, reach.r, state.spent_.data());
  const Excluded excluded{previous_movement(skill, state),
                          any_spent ? state.spent_.data() : nullptr};
  if (approach) chosen = approach_move(skill, reach, excluded, tx, ty);
  double prob = skill.table().posterior_row(row)[chosen];
  const bool smooth = smoothing_on(skill, state) && !approach;
  if (smooth) {
    chosen = smoothed_move(skill, context, reach, row, am, state.average_.data(),
                           state.votes_.data(), prob);
  }
  if (!approach) {
    const double* score = smooth ? state.average_.data() : skill.table().posterior_row(row);
    detail::avoid_excluded(skill, reach, excluded, score, chosen, prob);
    // which side of the object the end-effector is on, for the clearance and alignment rules
    const bool pushing =
        skill.settings().clearance > 0.0 && detail::on_pushing_side(skill, reach.r, context.effect);
    detail::keep_clearance(skill, pushing, reach, excluded, score, chosen, prob);
    detail::align_push(skill, context, pushing, reach, excluded, score, chosen, prob);
  }
  ++state.steps_;
  state.remember(reach.r, chosen);
  emit(skill, chosen, prob, out);
  return finish(Status::ok);
}

}  // namespace a2l
