// The rules that change a step's choice of movement (skill_rules.hpp): no undo and the
// revisit rule, the clearance rule, the alignment rule.
#include "skill_rules.hpp"

#include <cmath>

namespace a2l::detail {

namespace {

// How far from the object, in the table plane, movement `m` ends from `r` = eef - object
// (what the clearance and alignment rules compare with the clearance).
double end_distance(const Skill& skill, const Eigen::Vector3d& r, int m) noexcept {
  const Eigen::Vector3d e = r + skill.movements().displacement(m);
  return std::hypot(e.x(), e.y());
}

}  // namespace

bool mark_spent(const Skill& skill, const SkillState& state, const Eigen::Vector3d& r,
                char* spent) noexcept {
  if (!skill.settings().avoid_revisits) return false;
  const int nm = skill.n_moves();
  for (int m = 0; m < nm; ++m) spent[m] = 0;
  const double radius = 0.5 * skill.movements().step();
  auto near = [&](std::size_t j) noexcept { return (state.path_point(j) - r).norm() < radius; };
  std::size_t left = 0;  // the points before the last one away from r
  for (std::size_t j = state.path_size(); j-- > 0;) {
    if (!near(j)) {
      left = j;
      break;
    }
  }
  bool any = false;
  for (std::size_t j = 0; j < left; ++j) {
    const int m = state.path_movement(j);
    if (m < 0 || m >= nm || !near(j)) continue;
    spent[m] = 1;
    any = true;
  }
  return any;
}

void avoid_excluded(const Skill& skill, const Reach& reach, const Excluded& excluded,
                    const double* score, int& chosen, double& prob) noexcept {
  if (!excluded(skill, chosen)) return;
  int alt = -1;
  for (int m = 0; m < skill.n_moves(); ++m) {
    if (m == chosen || excluded(skill, m)) continue;
    if (!reach.allows(skill, m)) continue;
    if (alt < 0 || score[m] > score[alt]) alt = m;
  }
  if (alt >= 0) {
    chosen = alt;
    prob = score[alt];
  }
}

bool on_pushing_side(const Skill& skill, const Eigen::Vector3d& r, int effect) noexcept {
  const Eigen::Vector2d u = skill.push_direction(effect);
  const Eigen::Vector2d planar(r.x(), r.y());
  const double n = planar.norm() * u.norm();
  if (n <= 0.0) return true;
  constexpr double kCos45 = 0.70710678118654752440;  // the side's half-angle, 45 degrees
  return -planar.dot(u) >= kCos45 * n;
}

void keep_clearance(const Skill& skill, bool pushing, const Reach& reach, const Excluded& excluded,
                    const double* score, int& chosen, double& prob) noexcept {
  const double c = skill.settings().clearance;
  if (c <= 0.0 || pushing) return;
  if (end_distance(skill, reach.r, chosen) >= c) return;
  const double bar = skill.settings().clearance_ratio * score[chosen];
  int alt = -1;
  for (int m = 0; m < skill.n_moves(); ++m) {
    if (m == chosen || score[m] < bar || score[m] <= 0.0 || excluded(skill, m)) continue;
    if (!reach.allows(skill, m) || end_distance(skill, reach.r, m) < c) continue;
    if (alt < 0 || score[m] > score[alt]) alt = m;
  }
  if (alt >= 0) {
    chosen = alt;
    prob = score[alt];
  }
}

void align_push(const Skill& skill, const Context& context, bool pushing, const Reach& reach,
                const Excluded& excluded, const double* score, int& chosen, double& prob) noexcept {
  const double a = skill.settings().align;
  const double c = skill.settings().clearance;
  if (a <= 0.0 || c <= 0.0 || !pushing) return;
  const Eigen::Vector2d u = skill.push_direction(context.effect);
  if (u.norm() <= 0.0) return;
  const Eigen::Vector2d v(-u.y(), u.x());  // across the push line
  const Eigen::Vector2d r(reach.r.x(), reach.r.y());
  const double lateral = std::abs(r.dot(v));
  auto planar = [&](int m) noexcept {
    const Eigen::Vector3d& d = skill.movements().displacement(m);
    return Eigen::Vector2d(d.x(), d.y());
  };
  constexpr double kEps = 1e-9;
  if (lateral <= a || planar(chosen).dot(u) <= kEps || end_distance(skill, reach.r, chosen) >= c) {
    return;
  }
  int alt = -1;
  double alt_lateral = lateral;
  for (int m = 0; m < skill.n_moves(); ++m) {
    const Eigen::Vector2d d = planar(m);
    if (d.dot(u) > kEps || d.norm() <= kEps || excluded(skill, m) || !reach.allows(skill, m)) {
      continue;
    }
    const double l = std::abs((r + d).dot(v));
    if (l < alt_lateral - kEps ||
        (alt >= 0 && l < alt_lateral + kEps && d.dot(u) > planar(alt).dot(u))) {
      alt = m;
      alt_lateral = l;
    }
  }
  if (alt >= 0) {
    chosen = alt;
    prob = score[alt];
  }
}

}  // namespace a2l::detail
