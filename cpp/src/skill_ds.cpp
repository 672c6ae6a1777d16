// step_ds(): one step of a skill's DS phases (skill.hpp, ds_phases.hpp).
#include <algorithm>
#include <cmath>

#include "a2l/skill.hpp"
#include "rt_guard.hpp"

namespace a2l {

Status step_ds(const Skill& skill, SkillState& state, const Eigen::Vector3d& eef,
               const Eigen::Vector3d& object, const DSStateValues& states,
               StepOutput& out) noexcept {
  [[maybe_unused]] const detail::RealTimeSection rt;
  state.begin_step(out);
  TraceRecord& rec = out.record;
  auto finish = [&](Status st) noexcept { return state.finish_step(out, st); };
  const DSPhaseSet& set = skill.ds_phases();
  const Status sized = state.check_sized(skill);
  if (sized == Status::not_initialized || set.empty()) return finish(Status::not_initialized);
  if (sized != Status::ok) return finish(sized);
  if (!eef.allFinite() || !object.allFinite()) return finish(Status::unknown_context);
  const int p = set.select(states);
  if (p < 0) return finish(Status::unknown_context);
  rec.phase = p;
  if (state.steps_ >= skill.settings().step_cap) return finish(Status::step_cap);

  const DSPhase& phase = set.phases[static_cast<std::size_t>(p)];
  const Eigen::Vector3d x = eef - object;
  const double to_target = (x - phase.ds.target()).norm();
  if (!std::isfinite(to_target)) return finish(Status::unknown_context);
  if (to_target <= phase.tolerance) {
    const std::uint64_t bit = std::uint64_t{1} << p;
    if (phase.end_action == MovementAction::none || (state.ds_emitted_ & bit) != 0) {
      return finish(Status::converged);
    }
    state.ds_emitted_ |= bit;
    ++state.steps_;
    out.action = phase.end_action;
    out.movement = skill.movements().index_of(phase.end_action);
    out.probability = 1.0;
    rec.movement = out.movement;
    rec.probability = 1.0;
    return finish(Status::ok);
  }
  Eigen::Vector3d v;
  if (phase.ds.velocity(x, v) != Status::ok) return finish(Status::unknown_context);
  const double speed = v.norm();
  if (!std::isfinite(speed)) return finish(Status::unknown_context);
  if (!(speed > 1e-12)) return finish(Status::converged);  // at the attractor numerically
  ++state.steps_;
  out.displacement = v * (std::min(skill.movements().step(), to_target) / speed);
  out.probability = 1.0;
  rec.probability = 1.0;
  return finish(Status::ok);
}

}  // namespace a2l
