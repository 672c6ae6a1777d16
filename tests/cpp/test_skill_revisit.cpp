// The revisit rule (execution.avoid_revisits): when a run comes back within half a movement of
// a point of its path it has left since, the movements it chose there are spent; the step
// takes the best-scored movement that is not.
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include "a2l/bundle.hpp"
#include "a2l/skill.hpp"
#include "bundle_builder.hpp"

namespace test_skill_revisit {

using a2l::Status;
using a2l::testing::BundleParts;
using a2l::testing::sample_parts;

a2l::Skill load(const BundleParts& p) { return a2l::testing::load_skill(p); }

BundleParts with_revisits(BundleParts p) {
  p.manifest["execution"]["avoid_revisits"] = true;
  return p;
}

// `n` points around the object, each at least a movement from the others (several may share a
// context cell).
std::vector<a2l::Context> distinct_points(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> coord(-0.25, 0.25);
  std::vector<a2l::Context> out;
  while (static_cast<int>(out.size()) < n) {
    a2l::Context c;
    c.object = {0.7, 0.0, 0.04};
    c.eef = c.object + Eigen::Vector3d(coord(rng), coord(rng), 0.0);
    c.effect = 1;
    bool close = false;
    for (const a2l::Context& o : out) close = close || (o.eef - c.eef).norm() < 0.05;
    if (!close) out.push_back(c);
  }
  return out;
}

// The row the step answers from at `c` (no fallback: every row is informative).
const double* posterior_at(const a2l::Skill& skill, const a2l::Context& c) {
  int bins[a2l::kMaxVariables];
  EXPECT_EQ(skill.discretizer().discretize(c, bins), Status::ok);
  return skill.table().posterior_row(skill.table().row_index(bins));
}

TEST(Revisit, ARunBackWhereItWasTakesTheBestMovementItHasNotTakenThere) {
  // Random walks over points, written out against the rule: a visit spends its movement at
  // its point once the run has been elsewhere; a later visit takes the best-scored movement
  // not spent there (the plain step, without fallback or smoothing, takes the row's argmax).
  const BundleParts p = sample_parts(5, 0.0);
  const a2l::Skill plain = load(p);
  const a2l::Skill skill = load(with_revisits(p));
  EXPECT_FALSE(plain.settings().avoid_revisits);
  EXPECT_TRUE(skill.settings().avoid_revisits);
  std::mt19937_64 rng(11);
  const std::vector<a2l::Context> points = distinct_points(rng, 4);
  std::uniform_int_distribution<int> pick(0, 3);
  std::uniform_real_distribution<double> jitter(-0.008, 0.008);  // within half a movement
  a2l::SkillState state(skill), plain_state(plain);
  int changed = 0, kept = 0;
  for (int walk = 0; walk < 500; ++walk) {
    state.reset();
    std::vector<int> visited, taken;  // point index and movement per step
    for (int k = 0; k < 10; ++k) {
      const int i = pick(rng);
      a2l::Context c = points[static_cast<size_t>(i)];
      c.eef += Eigen::Vector3d(jitter(rng), jitter(rng), 0.0);
      int left = 0;  // the steps before the last one elsewhere
      for (int j = static_cast<int>(visited.size()) - 1; j >= 0; --j) {
        if (visited[static_cast<size_t>(j)] != i) {
          left = j;
          break;
        }
      }
      std::array<bool, 64> spent{};
      for (int j = 0; j < left; ++j) {
        if (visited[static_cast<size_t>(j)] == i) spent[static_cast<size_t>(taken[j])] = true;
      }
      const double* post = posterior_at(skill, c);
      a2l::StepOutput out, plain_out;
      plain_state.reset();
      ASSERT_EQ(a2l::step(plain, plain_state, c, plain_out), Status::ok);
      int want = plain_out.movement;
      if (spent[static_cast<size_t>(want)]) {
        int alt = -1;
        for (int m = 0; m < skill.n_moves(); ++m) {
          if (!spent[static_cast<size_t>(m)] && (alt < 0 || post[m] > post[alt])) alt = m;
        }
        if (alt >= 0) want = alt;
      }
      ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
      EXPECT_EQ(out.movement, want) << "walk " << walk << " step " << k;
      EXPECT_EQ(out.probability, post[out.movement]);
      (out.movement != plain_out.movement ? changed : kept) += 1;
      visited.push_back(i);
      taken.push_back(out.movement);
    }
    ASSERT_EQ(state.path_size(), 10u);
  }
  EXPECT_GT(changed, 500);
  EXPECT_GT(kept, 500);
}

TEST(Revisit, StayingPutOrANewRunSpendsNothing) {
  const BundleParts p = sample_parts(6, 0.0);
  const a2l::Skill plain = load(p);
  const a2l::Skill skill = load(with_revisits(p));
  std::mt19937_64 rng(5);
  const std::vector<a2l::Context> pts = distinct_points(rng, 2);
  const a2l::Context &a = pts[0], &b = pts[1];
  a2l::SkillState s(skill), s0(plain);
  a2l::StepOutput out, ref;
  ASSERT_EQ(a2l::step(plain, s0, a, ref), Status::ok);
  // held at a: the same answer each time
  for (int k = 0; k < 4; ++k) {
    ASSERT_EQ(a2l::step(skill, s, a, out), Status::ok);
    EXPECT_EQ(out.movement, ref.movement);
  }
  ASSERT_EQ(a2l::step(skill, s, b, out), Status::ok);
  ASSERT_EQ(a2l::step(skill, s, a, out), Status::ok);
  EXPECT_NE(out.movement, ref.movement);  // back at a: its movement is spent
  s.reset();                              // a new run remembers nothing
  EXPECT_EQ(s.path_size(), 0u);
  ASSERT_EQ(a2l::step(skill, s, a, out), Status::ok);
  EXPECT_EQ(out.movement, ref.movement);
  // the path holds at most the step cap's points: past it the step stops anyway
  EXPECT_EQ(s.path_size(), 1u);
}

TEST(Revisit, ANonBooleanSettingIsAParseError) {
  a2l::testing::expect_execution_refused("avoid_revisits", {1, "true", nullptr});
}

}  // namespace test_skill_revisit
