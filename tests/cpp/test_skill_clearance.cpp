// The clearance rule (execution.clearance): away from the side the wanted push effect pushes
// from, a movement that would end nearer the object than the clearance gives way to the
// best-scored one that does not, if that one scores at least the bundle's clearance_ratio of
// it (kClearanceRatio when the bundle sets none).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "a2l/bundle.hpp"
#include "a2l/effects.hpp"
#include "a2l/skill.hpp"
#include "bundle_builder.hpp"

namespace test_skill_clearance {

using a2l::Status;
using a2l::testing::BundleParts;
using a2l::testing::sample_parts;

constexpr double kClearance = 0.10;

a2l::Skill load(const BundleParts& p) { return a2l::testing::load_skill(p); }

BundleParts with_clearance(BundleParts p, double c) {
  p.manifest["execution"]["clearance"] = c;
  return p;
}

double end_distance(const a2l::Skill& skill, const Eigen::Vector3d& r, int m) {
  const Eigen::Vector3d e = r + skill.movements().displacement(m);
  return std::hypot(e.x(), e.y());
}

// Whether `r` (eef - object) is within 45 degrees of the side effect `effect` pushes from.
bool pushing_side(const Eigen::Vector3d& r, int effect) {
  const Eigen::Vector2d u = a2l::effect_direction(effect).normalized();
  const Eigen::Vector2d p(r.x(), r.y());
  return -p.dot(u) >= std::cos(0.25 * 3.14159265358979323846) * p.norm();
}

// Without smoothing or fallback the step without the rule takes the row's argmax; with it,
// the answer changes exactly where the rule says, to the movement it says; `ratio` the
// bundle's clearance_ratio (<= 0: none written).
void check_rule(double ratio) {
  const BundleParts p = sample_parts(5, 0.0);
  const a2l::Skill plain = load(p);
  BundleParts ruled = with_clearance(p, kClearance);
  if (ratio > 0.0) ruled.manifest["execution"]["clearance_ratio"] = ratio;
  const a2l::Skill skill = load(ruled);
  const double bar = ratio > 0.0 ? ratio : a2l::kClearanceRatio;
  EXPECT_EQ(plain.settings().clearance, 0.0);
  EXPECT_EQ(skill.settings().clearance, kClearance);
  EXPECT_EQ(skill.settings().clearance_ratio, bar);
  std::mt19937_64 rng(7);
  int changed = 0, kept_near = 0, pushing = 0;
  for (int i = 0; i < 20000; ++i) {
    const a2l::Context c = a2l::testing::random_push_context(rng, 0.25, -0.02, 0.06);
    a2l::StepOutput o0, o1;
    if (!a2l::testing::step_both(plain, skill, c, o0, o1)) continue;
    const Eigen::Vector3d r = c.eef - c.object;
    int bins[a2l::kMaxVariables];
    ASSERT_EQ(skill.discretizer().discretize(c, bins), Status::ok);
    const double* post = skill.table().posterior_row(skill.table().row_index(bins));
    // what the rule should choose
    int want = o0.movement;
    const bool near = end_distance(skill, r, o0.movement) < kClearance;
    if (near && !pushing_side(r, c.effect)) {
      int alt = -1;
      for (int m = 0; m < skill.n_moves(); ++m) {
        if (m == o0.movement || post[m] <= 0.0) continue;
        if (post[m] < bar * post[o0.movement]) continue;
        if (end_distance(skill, r, m) < kClearance) continue;
        if (alt < 0 || post[m] > post[alt]) alt = m;
      }
      if (alt >= 0) want = alt;
      kept_near += alt < 0 ? 1 : 0;
    }
    if (near && pushing_side(r, c.effect)) ++pushing;
    EXPECT_EQ(o1.movement, want) << "context " << i;
    if (o1.movement != o0.movement) {
      ++changed;
      EXPECT_GE(end_distance(skill, r, o1.movement), kClearance);
      EXPECT_EQ(o1.probability, post[o1.movement]);
      EXPECT_EQ(o1.record.movement, o1.movement);
    }
  }
  // every branch was taken: the rule changed answers, found no alternative, and left the
  // pushing side alone
  EXPECT_GT(changed, 200);
  EXPECT_GT(kept_near, 200);
  EXPECT_GT(pushing, 200);
}

TEST(Clearance, ANearEqualMovementThatKeepsClearGoesFirstAwayFromThePushingSide) {
  check_rule(0.0);   // the default bar
  check_rule(0.25);  // a lower one
}

TEST(Clearance, ALowerBarYieldsMoreOften) {
  // the same contexts: every answer the 0.5 bar changes, 0.25 changes too, and more
  const BundleParts p = sample_parts(5, 0.0);
  BundleParts half = with_clearance(p, kClearance), quarter = half;
  quarter.manifest["execution"]["clearance_ratio"] = 0.25;
  const a2l::Skill plain = load(p), a = load(half), b = load(quarter);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> coord(-0.25, 0.25);
  int changed_a = 0, changed_b = 0;
  for (int i = 0; i < 5000; ++i) {
    a2l::Context c;
    c.object = {0.7, 0.0, 0.04};
    c.eef = c.object + Eigen::Vector3d(coord(rng), coord(rng), 0.0);
    c.effect = i % 4;
    a2l::SkillState s0(plain), sa(a), sb(b);
    a2l::StepOutput o0, oa, ob;
    if (a2l::step(plain, s0, c, o0) != Status::ok) continue;
    ASSERT_EQ(a2l::step(a, sa, c, oa), Status::ok);
    ASSERT_EQ(a2l::step(b, sb, c, ob), Status::ok);
    changed_a += oa.movement != o0.movement ? 1 : 0;
    changed_b += ob.movement != o0.movement ? 1 : 0;
    if (oa.movement != o0.movement) EXPECT_NE(ob.movement, o0.movement) << "context " << i;
  }
  EXPECT_GT(changed_b, changed_a);
}

TEST(Clearance, OffByDefaultAndTheSameAnswersAtZero) {
  const BundleParts p = sample_parts(6, 0.1, true);
  a2l::testing::expect_same_answers(load(p), load(with_clearance(p, 0.0)));
}

TEST(Clearance, PushDirectionsComeFromTheEffectNames) {
  const a2l::Skill skill = load(sample_parts());
  // sample_parts' effect values: left (+y), right (-y), close (-x), far (+x)
  EXPECT_TRUE(skill.push_direction(0).isApprox(Eigen::Vector2d(0, 1)));
  EXPECT_TRUE(skill.push_direction(1).isApprox(Eigen::Vector2d(0, -1)));
  EXPECT_TRUE(skill.push_direction(2).isApprox(Eigen::Vector2d(-1, 0)));
  EXPECT_TRUE(skill.push_direction(3).isApprox(Eigen::Vector2d(1, 0)));
  EXPECT_EQ(skill.push_direction(4), Eigen::Vector2d::Zero());
  EXPECT_EQ(skill.push_direction(-1), Eigen::Vector2d::Zero());
}

TEST(Clearance, ARatioOutsideZeroToOneIsAParseError) {
  a2l::testing::expect_execution_refused("clearance_ratio", {0.0, 1.5, -0.2, "0.5"});
}

TEST(Clearance, ANegativeOrNonNumericClearanceIsAParseError) {
  a2l::testing::expect_execution_refused("clearance", {-0.01, "0.1", nullptr});
}

}  // namespace test_skill_clearance
