// Skill runtime: bundle loading, discretizer bin math, table lookups, step() statuses,
// trace ring buffer, neighbour smoothing.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "a2l/bundle.hpp"
#include "a2l/skill.hpp"
#include "bundle_builder.hpp"

namespace test_skill {

using a2l::Status;
using a2l::testing::build;
using a2l::testing::BundleParts;
using a2l::testing::json;
using a2l::testing::sample_parts;
constexpr double kPi = 3.14159265358979323846;

a2l::Skill load(const std::vector<std::uint8_t>& bytes) {
  a2l::Skill s;
  const a2l::Result r = a2l::load_bundle_from_memory(bytes.data(), bytes.size(), s, "test");
  EXPECT_TRUE(r.ok()) << r.message;
  return s;
}

TEST(Discretizer, DistanceSaturatesAtBothEnds) {
  using D = a2l::Discretizer;
  EXPECT_EQ(D::distance_bin(0.0, 0.05, 0.20, 3), 0);
  EXPECT_EQ(D::distance_bin(0.0999, 0.05, 0.20, 3), 0);
  EXPECT_EQ(D::distance_bin(0.1001, 0.05, 0.20, 3), 1);
  EXPECT_EQ(D::distance_bin(0.1501, 0.05, 0.20, 3), 2);
  EXPECT_EQ(D::distance_bin(5.0, 0.05, 0.20, 3), 2);
  EXPECT_EQ(D::distance_bin(std::numeric_limits<double>::infinity(), 0.05, 0.20, 3), -1);
  EXPECT_EQ(D::distance_bin(std::nan(""), 0.05, 0.20, 3), -1);
}

TEST(Discretizer, OrientationBinKIsCentredOnMinusPiPlusKw) {
  for (int n : {4, 8, 16, 24, 32}) {
    const double w = 2 * kPi / n;
    for (int k = 0; k < n; ++k) {
      const double centre = -kPi + k * w;
      EXPECT_EQ(a2l::Discretizer::orientation_bin(centre, n), k) << n << " " << k;
      EXPECT_EQ(a2l::Discretizer::orientation_bin(centre + 0.49 * w, n), k);
      EXPECT_EQ(a2l::Discretizer::orientation_bin(centre - 0.49 * w, n), k);
    }
    EXPECT_EQ(a2l::Discretizer::orientation_bin(kPi, n), 0);  // pi and -pi are one direction
  }
  EXPECT_EQ(a2l::Discretizer::orientation_bin(std::nan(""), 16), -1);
}

TEST(Discretizer, InclinationFromTheVertical) {
  EXPECT_EQ(a2l::Discretizer::inclination_bin(0.0, 8), 0);
  EXPECT_EQ(a2l::Discretizer::inclination_bin(kPi / 2, 8), 4);
  EXPECT_EQ(a2l::Discretizer::inclination_bin(kPi, 8), 7);
  EXPECT_EQ(a2l::Discretizer::inclination_bin(kPi / 8 - 1e-9, 8), 0);
}

TEST(Discretizer, ContextBinsAndUnknownContexts) {
  const a2l::Skill skill = load(build(sample_parts()));
  const a2l::Discretizer& d = skill.discretizer();
  ASSERT_EQ(d.n_variables(), 5);
  EXPECT_EQ(d.effect_axis(), 0);
  EXPECT_EQ(d.find("light"), 4);
  EXPECT_EQ(d.find("nothing"), -1);
  a2l::Context c;
  c.object = {0.7, 0.0, 0.04};
  c.eef = {0.7, 0.12, 0.04};  // +y of the object, same height: theta = pi/2, phi = pi/2
  c.effect = 2;
  c.high_level[4] = 1;
  int bins[a2l::kMaxVariables];
  ASSERT_EQ(d.discretize(c, bins), Status::ok);
  EXPECT_EQ(bins[0], 2);
  EXPECT_EQ(bins[1], 1);  // 0.12 in [0.10, 0.15)
  EXPECT_EQ(bins[2], 6);  // 8 bins: k = (pi/2 + pi) / (pi/4) = 6
  EXPECT_EQ(bins[3], 2);  // 4 bins: floor(0.5 * 4) = 2
  EXPECT_EQ(bins[4], 1);

  a2l::Context bad = c;
  bad.effect = 4;
  EXPECT_EQ(d.discretize(bad, bins), Status::unknown_context);
  EXPECT_EQ(bins[0], -1);
  bad = c;
  bad.high_level[4] = 2;
  EXPECT_EQ(d.discretize(bad, bins), Status::unknown_context);
  bad = c;
  bad.high_level[4] = -1;
  EXPECT_EQ(d.discretize(bad, bins), Status::unknown_context);
  bad = c;
  bad.eef.x() = std::nan("");
  EXPECT_EQ(d.discretize(bad, bins), Status::unknown_context);
  EXPECT_EQ(bins[1], -1);
  bad = c;
  bad.object.z() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(d.discretize(bad, bins), Status::unknown_context);
}

TEST(Discretizer, CreateRejectsBadVariables) {
  a2l::Discretizer d;
  a2l::Variable v{"distance", a2l::VariableKind::distance, 3, 0.2, 0.05, {}};
  a2l::Result r = a2l::Discretizer::create({v}, d);
  EXPECT_EQ(r.status, Status::invalid_argument);
  EXPECT_NE(r.message.find("low"), std::string::npos) << r.message;
  a2l::Variable e{"e", a2l::VariableKind::effect, 0, 0, 0, {"a", "a"}};
  r = a2l::Discretizer::create({e}, d);
  EXPECT_NE(r.message.find("duplicate value"), std::string::npos) << r.message;
  a2l::Variable o{"o", a2l::VariableKind::orientation, 8, 0, 0, {}};
  r = a2l::Discretizer::create({o, o}, d);
  EXPECT_NE(r.message.find("duplicate name"), std::string::npos) << r.message;
}

TEST(PolicyTable, LookupEqualsTheStoredArraysOnEveryCombination) {
  const BundleParts p = sample_parts(7);
  const a2l::Skill skill = load(build(p));
  const a2l::PolicyTable& t = skill.table();
  ASSERT_EQ(t.n_rows(), 4u * 3 * 8 * 4 * 2);
  EXPECT_EQ(t.strides(), (std::vector<std::size_t>{192, 64, 8, 2, 1}));
  std::size_t row = 0;
  int bins[5];
  for (bins[0] = 0; bins[0] < 4; ++bins[0])
    for (bins[1] = 0; bins[1] < 3; ++bins[1])
      for (bins[2] = 0; bins[2] < 8; ++bins[2])
        for (bins[3] = 0; bins[3] < 4; ++bins[3])
          for (bins[4] = 0; bins[4] < 2; ++bins[4], ++row) {
            ASSERT_EQ(t.row_index(bins), row);
            ASSERT_EQ(t.lookup(bins), p.argmax[row]);
            for (int m = 0; m < 8; ++m) {
              ASSERT_EQ(t.posterior_row(row)[m], p.posterior[row * 8 + static_cast<size_t>(m)]);
            }
          }
  int out_of_range[5] = {0, 3, 0, 0, 0};
  EXPECT_EQ(t.lookup(out_of_range), -1);
}

// A context whose row has an argmax, found by scanning eef positions.
a2l::Context known_context(const a2l::Skill& skill, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  a2l::Context c;
  c.object = {0.7, 0.0, 0.04};
  for (int i = 0; i < 10000; ++i) {
    c.eef = c.object + Eigen::Vector3d(u(rng), u(rng), u(rng));
    int bins[a2l::kMaxVariables];
    if (skill.discretizer().discretize(c, bins) == Status::ok && skill.table().lookup(bins) >= 0) {
      return c;
    }
  }
  ADD_FAILURE() << "no known context found";
  return c;
}

TEST(Step, ReturnsTheTableArgmaxAndItsProbability) {
  const a2l::Skill skill = load(build(sample_parts(3)));
  a2l::SkillState state(skill);
  std::mt19937_64 rng(1);
  for (int i = 0; i < 200; ++i) {
    state.reset();
    const a2l::Context c = known_context(skill, rng);
    int bins[a2l::kMaxVariables];
    ASSERT_EQ(skill.discretizer().discretize(c, bins), Status::ok);
    const std::size_t row = skill.table().row_index(bins);
    a2l::StepOutput out;
    ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
    EXPECT_EQ(out.movement, skill.table().argmax(row));
    EXPECT_EQ(out.probability, skill.table().posterior_row(row)[out.movement]);
    EXPECT_TRUE(out.displacement.isApprox(skill.movements().displacement(out.movement)));
    EXPECT_NEAR(out.displacement.norm(), 0.05, 1e-12);
    EXPECT_EQ(out.record.movement, out.movement);
    EXPECT_EQ(out.record.status, Status::ok);
    for (int k = 0; k < 5; ++k) EXPECT_EQ(out.record.bins[static_cast<size_t>(k)], bins[k]);
  }
}

TEST(Step, StopConditions) {
  const a2l::Skill skill = load(build(sample_parts(3)));
  a2l::SkillState state(skill);
  std::mt19937_64 rng(2);
  const a2l::Context c = known_context(skill, rng);
  a2l::StepOutput out;
  for (int i = 0; i < skill.settings().step_cap; ++i) {
    ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok) << i;
  }
  EXPECT_EQ(state.steps(), 12);
  EXPECT_EQ(a2l::step(skill, state, c, out), Status::step_cap);
  EXPECT_EQ(out.movement, -1);
  state.reset();
  a2l::Context produced = c;
  produced.effect_produced = true;
  EXPECT_EQ(a2l::step(skill, state, produced, out), Status::effect_produced);
  a2l::Context nan = c;
  nan.eef.y() = std::nan("");
  EXPECT_EQ(a2l::step(skill, state, nan, out), Status::unknown_context);
  EXPECT_EQ(out.movement, -1);
  EXPECT_EQ(out.probability, 0.0);
  a2l::Context unknown_hl = c;
  unknown_hl.high_level[4] = 7;
  EXPECT_EQ(a2l::step(skill, state, unknown_hl, out), Status::unknown_context);
  EXPECT_EQ(out.record.bins[4], -1);
  a2l::Context bad_effect = c;
  bad_effect.effect = -3;
  EXPECT_EQ(a2l::step(skill, state, bad_effect, out), Status::unknown_context);
  EXPECT_EQ(state.steps(), 0);  // stops do not count as movements
}

TEST(Step, UniformRowIsAnUnknownContextNotAGuess) {
  BundleParts p = sample_parts(5, 1.0);  // every row uniform
  const a2l::Skill skill = load(build(p));
  a2l::SkillState state(skill);
  a2l::Context c;
  c.object = {0.7, 0.0, 0.04};
  c.eef = {0.8, 0.0, 0.04};
  a2l::StepOutput out;
  EXPECT_EQ(a2l::step(skill, state, c, out), Status::unknown_context);
  EXPECT_EQ(out.movement, -1);
}

TEST(Step, UnloadedSkillOrStateOfAnotherSkill) {
  const a2l::Skill empty;
  a2l::SkillState none;
  a2l::StepOutput out;
  EXPECT_EQ(a2l::step(empty, none, a2l::Context(), out), Status::not_initialized);
  const a2l::Skill skill = load(build(sample_parts()));
  EXPECT_EQ(a2l::step(skill, none, a2l::Context(), out), Status::not_initialized);
  BundleParts small = sample_parts();
  small.manifest["variables"].erase(4);
  small.shape.pop_back();
  small.posterior.resize(small.posterior.size() / 2);
  small.argmax.resize(small.argmax.size() / 2);
  const a2l::Skill other = load(build(small));
  a2l::SkillState other_state(other);
  EXPECT_EQ(a2l::step(skill, other_state, a2l::Context(), out), Status::size_mismatch);
}

TEST(Step, TraceRingBufferKeepsTheNewestRecords) {
  const a2l::Skill skill = load(build(sample_parts(3)));
  a2l::SkillState state(skill, 4);
  std::mt19937_64 rng(3);
  const a2l::Context c = known_context(skill, rng);
  a2l::StepOutput out;
  for (int i = 0; i < 10; ++i) a2l::step(skill, state, c, out);  // 12 cap: all ok
  ASSERT_EQ(state.trace_capacity(), 4u);
  ASSERT_EQ(state.trace_size(), 4u);
  EXPECT_EQ(state.trace_dropped(), 6u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(state.trace(i).step, static_cast<long>(6 + i));
  state.clear_trace();
  EXPECT_EQ(state.trace_size(), 0u);
}

// Only a distance variable (3 bins over [0.05, 0.20]) and 2 movements: the centre point at
// d = 0.099 on the diagonal of the table plane is in bin 0; its neighbours at +x, +y, +z, -z
// are in bin 1, at -x, -y in bin 0.
a2l::Skill smoothing_skill(const std::vector<double>& bin0, const std::vector<double>& bin1) {
  BundleParts p;
  p.manifest = {
      {"schema_version", a2l::kBundleSchemaVersion},
      {"kind", "skill"},
      {"name", "s"},
      {"created_by", "t"},
      {"robot", nullptr},
      {"target", "move"},
      {"variables", json::array({{{"name", "distance"},
                                  {"kind", "distance"},
                                  {"n_bins", 3},
                                  {"low", 0.05},
                                  {"high", 0.20}}})},
      {"movements",
       {{"step", 0.05},
        {"directions", {{1, 0, 0}, {-1, 0, 0}}},
        {"labels", {"+x", "-x"}},
        {"actions", json::array()}}},
      {"execution", {{"step_cap", 12}, {"smoothing", true}, {"uniform_tolerance", 1e-9}}}};
  p.shape = {3};
  p.n_moves = 2;
  p.posterior = {bin0[0], bin0[1], bin1[0], bin1[1], 0.5, 0.5};
  p.argmax = {bin0[0] >= bin0[1] ? 0 : 1, bin1[0] >= bin1[1] ? 0 : 1, -1};
  return load(build(p));
}

a2l::Context diagonal_context() {
  a2l::Context c;
  c.object = {0.0, 0.0, 0.0};
  const double s = 0.099 / std::sqrt(2.0);
  c.eef = {s, s, 0.0};
  return c;
}

TEST(Step, SmoothingTakesAClearTopMovement) {
  // avg = (3 * bin0 + 4 * bin1) / 7 = (0.407, 0.593): second < 0.75 * first -> the top one.
  const a2l::Skill skill = smoothing_skill({0.55, 0.45}, {0.3, 0.7});
  a2l::SkillState state(skill);
  a2l::StepOutput out;
  ASSERT_EQ(a2l::step(skill, state, diagonal_context(), out), Status::ok);
  EXPECT_EQ(out.movement, 1);
  EXPECT_NEAR(out.probability, (3 * 0.45 + 4 * 0.7) / 7, 1e-12);
  state.smoothing = a2l::Smoothing::off;  // the centre row alone says movement 0
  ASSERT_EQ(a2l::step(skill, state, diagonal_context(), out), Status::ok);
  EXPECT_EQ(out.movement, 0);
  EXPECT_EQ(out.probability, 0.55);
}

TEST(Step, SmoothingTakesTheMoreFrequentOfTwoCloseMovements) {
  // avg = (0.557, 0.443): second >= 0.75 * first, movement 1 is the argmax at 4 of 7 points.
  const a2l::Skill skill = smoothing_skill({0.7, 0.3}, {0.45, 0.55});
  a2l::SkillState state(skill);
  a2l::StepOutput out;
  ASSERT_EQ(a2l::step(skill, state, diagonal_context(), out), Status::ok);
  EXPECT_EQ(out.movement, 1);
  EXPECT_NEAR(out.probability, (3 * 0.3 + 4 * 0.55) / 7, 1e-12);
}

TEST(Step, SmoothingLeavesUniformNeighboursOut) {
  // Centre far out (bin 2 is uniform): still an unknown context.
  const a2l::Skill skill = smoothing_skill({0.7, 0.3}, {0.45, 0.55});
  a2l::SkillState state(skill);
  a2l::Context c;
  c.eef = {0.3, 0.0, 0.0};
  a2l::StepOutput out;
  EXPECT_EQ(a2l::step(skill, state, c, out), Status::unknown_context);
}

}  // namespace test_skill
