//! \file skill_rules.hpp
//! \brief Private to the skill library: where a step may end (Reach), the movements it may
//! not take (Excluded), and the rules that change the table's choice of movement after it was
//! made: no undo and the revisit rule, the clearance rule, the alignment rule. step()
//! (skill_step.cpp) applies them in that order; none allocates or throws.
#pragma once

#include <Eigen/Core>

#include "a2l/skill.hpp"

namespace a2l::detail {

//! Whether movement `m` undoes movement `last` (their displacements cancel; an action,
//! with no displacement, undoes nothing).
inline bool undoes(const Skill& skill, int m, int last) noexcept {
  if (last < 0) return false;
  const Eigen::Vector3d& back = skill.movements().displacement(last);
  return back.norm() > 0.0 && (skill.movements().displacement(m) + back).norm() < 1e-9;
}

//! Whether movement `m` ends between `near` and `limit` from the object, from `r` = eef -
//! object (a fallback step's restriction, Skill::fallback_reach and Skill::fallback_near).
inline bool within_reach(const Skill& skill, const Eigen::Vector3d& r, double near, double limit,
                         int m) noexcept {
  const double d = (r + skill.movements().displacement(m)).norm();
  return d <= limit + 1e-12 && d >= near - 1e-12;
}

//! Where a step may end. A fallback step (`limited`) ends between min(|r|, near) and
//! max(|r|, reach) from the object (Skill::fallback_near, Skill::fallback_reach); any other
//! step anywhere.
struct Reach {
  Eigen::Vector3d r;  // eef - object
  bool limited;
  double limit, near;

  // Whether movement `m` ends where the step may end.
  bool allows(const Skill& skill, int m) const noexcept {
    return !limited || within_reach(skill, r, near, limit, m);
  }
};

//! The movements a step may not take when another is allowed: the one undoing the previous
//! movement (`last`) and those the revisit rule spent (`spent`, n_moves, or null).
struct Excluded {
  int last;
  const char* spent;

  bool operator()(const Skill& skill, int m) const noexcept {
    return undoes(skill, m, last) || (spent != nullptr && spent[m] != 0);
  }
};

//! The revisit rule (SkillSettings::avoid_revisits): into `spent` (n_moves) the movements this
//! run chose at the points of its path (SkillState's, eef - object) within half a movement of
//! `r` that it has left since (a step that did not move, e.g. a held arm, is no return);
//! whether there is one (`spent` untouched when the rule is off).
bool mark_spent(const Skill& skill, const SkillState& state, const Eigen::Vector3d& r,
                char* spent) noexcept;

//! No undo and the revisit rule: if `chosen` is excluded, the best-scored allowed movement
//! that is not (by `score`, into `chosen` and `prob`); unchanged if there is none.
void avoid_excluded(const Skill& skill, const Reach& reach, const Excluded& excluded,
                    const double* score, int& chosen, double& prob) noexcept;

//! Whether the end-effector, at `r` = eef - object, is within 45 degrees of the side push
//! effect `effect` pushes from (opposite the object's motion); true for an effect that is
//! not a push (the rule then never applies) or a point at the object.
bool on_pushing_side(const Skill& skill, const Eigen::Vector3d& r, int effect) noexcept;

//! The clearance rule (SkillSettings::clearance): away from the pushing side (`pushing`:
//! on_pushing_side()), a `chosen` movement ending nearer the object than the clearance gives
//! way to the best-scored allowed one that does not (by `score`, at least
//! SkillSettings::clearance_ratio of the chosen's; not `excluded`), into `chosen` and `prob`;
//! unchanged if there is none.
void keep_clearance(const Skill& skill, bool pushing, const Reach& reach, const Excluded& excluded,
                    const double* score, int& chosen, double& prob) noexcept;

//! The alignment rule (SkillSettings::align): on the pushing side (`pushing`), a `chosen`
//! movement towards the object along the push direction that would end nearer it than the
//! clearance, started more than the alignment off the push line through the object's centre,
//! gives way to the allowed movement (not `excluded`) that does not approach along the push
//! direction and ends nearest that line, if nearer than the start (into `chosen` and `prob`,
//! by `score`); unchanged if there is none.
void align_push(const Skill& skill, const Context& context, bool pushing, const Reach& reach,
                const Excluded& excluded, const double* score, int& chosen, double& prob) noexcept;

}  // namespace a2l::detail
