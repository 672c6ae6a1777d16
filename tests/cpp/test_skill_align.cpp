// The alignment rule (execution.align), the clearance rule's counterpart on the pushing side:
// there, a movement towards the object along the push direction that would end nearer it than
// the clearance, started more than `align` off the push line through the object's centre,
// gives way to the movement that does not approach along the push direction and ends nearest
// that line, if nearer than the start.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "a2l/bundle.hpp"
#include "a2l/effects.hpp"
#include "a2l/skill.hpp"
#include "bundle_builder.hpp"

namespace test_skill_align {

using a2l::Status;
using a2l::testing::BundleParts;
using a2l::testing::sample_parts;

constexpr double kClearance = 0.10;
constexpr double kAlign = 0.05;

a2l::Skill load(const BundleParts& p) { return a2l::testing::load_skill(p); }

BundleParts with_rules(BundleParts p, double clearance, double align) {
  p.manifest["execution"]["clearance"] = clearance;
  if (align > 0.0) p.manifest["execution"]["align"] = align;
  return p;
}

Eigen::Vector2d planar(const a2l::Skill& skill, int m) {
  const Eigen::Vector3d& d = skill.movements().displacement(m);
  return {d.x(), d.y()};
}

// What the rule answers for a step whose answer without it is `m0`, at `r` (eef - object)
// for push effect `effect` (an independent statement of the rule, sample_parts' repertoire).
int expected(const a2l::Skill& skill, const Eigen::Vector3d& r3, int effect, int m0) {
  const Eigen::Vector2d u = a2l::effect_direction(effect).normalized();
  const Eigen::Vector2d v(-u.y(), u.x()), r(r3.x(), r3.y());
  const bool pushing_side = -r.dot(u) >= std::cos(0.25 * 3.14159265358979323846) * r.norm();
  const double lateral = std::abs(r.dot(v));
  if (!pushing_side || lateral <= kAlign) return m0;
  if (planar(skill, m0).dot(u) <= 1e-9 || (r + planar(skill, m0)).norm() >= kClearance) return m0;
  int best = m0;
  double best_lateral = lateral;
  for (int m = 0; m < skill.n_moves(); ++m) {
    const Eigen::Vector2d d = planar(skill, m);
    if (d.dot(u) > 1e-9) continue;
    const double l = std::abs((r + d).dot(v));
    const bool nearer = l < best_lateral - 1e-9;
    const bool level =
        best != m0 && l < best_lateral + 1e-9 && d.dot(u) > planar(skill, best).dot(u);
    if (nearer || level) {
      best = m;
      best_lateral = l;
    }
  }
  return best;
}

TEST(Align, AMoveIntoTheObjectOffThePushLineBecomesOneOntoIt) {
  const BundleParts p = sample_parts(5, 0.0);
  const a2l::Skill plain = load(with_rules(p, kClearance, 0.0));
  const a2l::Skill skill = load(with_rules(p, kClearance, kAlign));
  EXPECT_EQ(plain.settings().align, 0.0);
  EXPECT_EQ(skill.settings().align, kAlign);
  std::mt19937_64 rng(11);
  int changed = 0, off_line_kept = 0;
  for (int i = 0; i < 40000; ++i) {
    const a2l::Context c = a2l::testing::random_push_context(rng, 0.2);
    a2l::StepOutput o0, o1;
    if (!a2l::testing::step_both(plain, skill, c, o0, o1)) continue;
    const Eigen::Vector3d r = c.eef - c.object;
    const int want = expected(skill, r, c.effect, o0.movement);
    EXPECT_EQ(o1.movement, want) << "context " << i;
    if (o1.movement == o0.movement) continue;
    ++changed;
    // the new movement does not approach along the push direction and ends nearer the line
    const Eigen::Vector2d u = a2l::effect_direction(c.effect).normalized();
    const Eigen::Vector2d v(-u.y(), u.x()), r2(r.x(), r.y());
    EXPECT_LE(planar(skill, o1.movement).dot(u), 1e-9);
    EXPECT_LT(std::abs((r2 + planar(skill, o1.movement)).dot(v)), std::abs(r2.dot(v)));
    int bins[a2l::kMaxVariables];
    ASSERT_EQ(skill.discretizer().discretize(c, bins), Status::ok);
    EXPECT_EQ(o1.probability,
              skill.table().posterior_row(skill.table().row_index(bins))[o1.movement]);
    EXPECT_EQ(o1.record.movement, o1.movement);
    if (std::abs(r2.dot(v)) > 0.1) ++off_line_kept;  // a second step still to align
  }
  EXPECT_GT(changed, 150);  // 233 of the 40000 contexts
  EXPECT_GT(off_line_kept, 0);
}

TEST(Align, ACornerPushOfTheRightEffectGoesSidewaysFirst) {
  // every row answers -x-y; `right` pushes towards -y from the +y side: 6 cm off the line
  // (x) and 7 cm behind the object, -x-y would hit the box's corner; the rule moves -x.
  BundleParts p = with_rules(sample_parts(5, 0.0), kClearance, kAlign);
  const int diagonal = 7;  // -x-y in sample_parts' repertoire
  for (std::size_t r = 0; r < p.argmax.size(); ++r) {
    for (int m = 0; m < p.n_moves; ++m) p.posterior[r * 8 + static_cast<std::size_t>(m)] = 0.02;
    p.posterior[r * 8 + diagonal] = 0.86;
    p.argmax[r] = diagonal;
  }
  const a2l::Skill skill = load(p);
  a2l::Context c;
  c.object = {0.7, 0.0, 0.04};
  c.effect = 1;  // right
  a2l::StepOutput out;
  const auto answer = [&](const Eigen::Vector3d& r) {
    c.eef = c.object + r;
    a2l::SkillState s(skill);
    EXPECT_EQ(a2l::step(skill, s, c, out), Status::ok);
    return out.movement;
  };
  EXPECT_EQ(answer({0.06, 0.07, 0.0}), 1);  // -x: onto the line
  EXPECT_EQ(out.probability, 0.02);
  EXPECT_EQ(answer({0.03, 0.07, 0.0}), diagonal);   // within the alignment: kept
  EXPECT_EQ(answer({0.06, 0.18, 0.0}), diagonal);   // ends farther than the clearance
  EXPECT_EQ(answer({0.06, -0.08, 0.0}), diagonal);  // not the pushing side
  c.effect = 0;                                     // left: pushes from -y, -x-y moves away
  EXPECT_EQ(answer({0.06, -0.07, 0.0}), diagonal);
}

TEST(Align, OffWithoutClearanceOrAtZero) {
  const BundleParts p = sample_parts(6, 0.1, true);
  // without a clearance the rule never acts
  a2l::testing::expect_same_answers(load(p), load(with_rules(p, 0.0, kAlign)));
  // written as 0: the same as absent
  BundleParts zero = with_rules(p, kClearance, 0.0);
  zero.manifest["execution"]["align"] = 0.0;
  a2l::testing::expect_same_answers(load(with_rules(p, kClearance, 0.0)), load(zero));
}

TEST(Align, ANegativeOrNonNumericAlignmentIsAParseError) {
  a2l::testing::expect_execution_refused("align", {-0.01, "0.05", nullptr});
}

}  // namespace test_skill_align
