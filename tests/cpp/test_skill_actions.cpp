// Movement actions (open, close, stay) in the repertoire: the repertoire's layout, the bundle's
// `movements.actions` and its checks, step() returning an action, and the acceptance test of
// the demonstrated skills: a high-level state (the light) toggled mid-action switches the behaviour
// in the very next C++ step.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "a2l/bundle.hpp"
#include "a2l/movement_repertoire.hpp"
#include "a2l/skill.hpp"
#include "bundle_builder.hpp"

namespace test_skill_actions {

using a2l::MovementAction;
using a2l::Status;
using a2l::testing::BundleParts;
using a2l::testing::json;

// Movements of the grasp-with-light skill: 6 axis directions, then open, close, stay.
enum Move : int { kPx, kMx, kPy, kMy, kPz, kMz, kOpen, kClose, kStay, kMoves };

// A grasp skill whose table depends on the light: effect(1) x distance(3 bins over
// [0.05, 0.20] m) x light(off, on). Light off: approach (-x, the eef starts on the +x side)
// until the near bin, then close. Light on (a hot stove): move away (+x) until the far bin,
// then stay. Each row puts 0.9 on its movement.
BundleParts grasp_light_parts() {
  BundleParts p;
  p.manifest = {
      {"schema_version", a2l::kBundleSchemaVersion},
      {"kind", "skill"},
      {"name", "grasp_light"},
      {"created_by", "a2l tests"},
      {"robot", nullptr},
      {"target", "move"},
      {"variables",
       json::array({{{"name", "effect"}, {"kind", "effect"}, {"values", {"grasped"}}},
                    {{"name", "distance"},
                     {"kind", "distance"},
                     {"n_bins", 3},
                     {"low", 0.05},
                     {"high", 0.20}},
                    {{"name", "light"}, {"kind", "high_level"}, {"values", {"off", "on"}}}})},
      {"movements",
       {{"step", 0.05},
        {"directions", {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}},
        {"labels", {"+x", "-x", "+y", "-y", "+z", "-z"}},
        {"actions", {"open", "close", "stay"}}}},
      {"execution", {{"step_cap", 12}, {"smoothing", false}, {"uniform_tolerance", 1e-9}}}};
  p.shape = {1, 3, 2};
  p.n_moves = kMoves;
  const int chosen[3][2] = {{kClose, kPx}, {kMx, kPx}, {kMx, kStay}};  // [distance][light]
  for (int d = 0; d < 3; ++d) {
    for (int light = 0; light < 2; ++light) {
      for (int m = 0; m < kMoves; ++m) {
        p.posterior.push_back(m == chosen[d][light] ? 0.9 : 0.1 / (kMoves - 1));
      }
      p.argmax.push_back(chosen[d][light]);
    }
  }
  return p;
}

a2l::Result load(const BundleParts& p, a2l::Skill& skill) {
  const auto bytes = a2l::testing::build(p);
  return a2l::load_bundle_from_memory(bytes.data(), bytes.size(), skill, "actions.a2lb");
}

void expect_parse_error(const std::function<void(json&)>& edit, const std::string& needle) {
  BundleParts p = grasp_light_parts();
  edit(p.manifest);
  a2l::Skill skill;
  const a2l::Result r = load(p, skill);
  EXPECT_EQ(r.status, Status::parse_error) << r.message;
  EXPECT_NE(r.message.find(needle), std::string::npos)
      << "message '" << r.message << "' does not name '" << needle << "'";
}

TEST(MovementActions, RepertoireHoldsDirectionsThenActions) {
  a2l::MovementRepertoire r;
  ASSERT_TRUE(a2l::MovementRepertoire::create(0.05, {{1, 0, 0}, {0, -1, 0}}, {"+x", "-y"}, r,
                                              {MovementAction::close, MovementAction::stay})
                  .ok());
  EXPECT_EQ(r.size(), 4);
  EXPECT_EQ(r.n_directions(), 2);
  EXPECT_EQ(r.n_actions(), 2);
  EXPECT_EQ(r.labels(), (std::vector<std::string>{"+x", "-y", "close", "stay"}));
  EXPECT_FALSE(r.is_action(1));
  EXPECT_TRUE(r.is_action(2));
  EXPECT_EQ(r.action(0), MovementAction::none);
  EXPECT_EQ(r.action(2), MovementAction::close);
  EXPECT_EQ(r.action(3), MovementAction::stay);
  EXPECT_EQ(r.index_of(MovementAction::stay), 3);
  EXPECT_EQ(r.index_of(MovementAction::open), -1);
  EXPECT_TRUE(r.displacement(2).isZero());
  EXPECT_TRUE(r.displacement(3).isZero());
  EXPECT_NEAR(r.displacement(1).y(), -0.05, 1e-15);

  MovementAction a = MovementAction::none;
  EXPECT_TRUE(a2l::parse_movement_action("open", a));
  EXPECT_EQ(a, MovementAction::open);
  EXPECT_FALSE(a2l::parse_movement_action("none", a));
  EXPECT_FALSE(a2l::parse_movement_action("grip", a));

  a2l::MovementRepertoire bad;
  const a2l::Result twice = a2l::MovementRepertoire::create(
      0.05, {{1, 0, 0}}, {}, bad, {MovementAction::open, MovementAction::open});
  EXPECT_EQ(twice.status, Status::invalid_argument);
  EXPECT_NE(twice.message.find("movements.actions[1]"), std::string::npos) << twice.message;
  const a2l::Result none =
      a2l::MovementRepertoire::create(0.05, {{1, 0, 0}}, {}, bad, {MovementAction::none});
  EXPECT_EQ(none.status, Status::invalid_argument);
  EXPECT_NE(none.message.find("movements.actions[0]"), std::string::npos) << none.message;
}

TEST(MovementActions, BundleActionsAreLoadedAndChecked) {
  a2l::Skill skill;
  const a2l::Result r = load(grasp_light_parts(), skill);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(skill.n_moves(), kMoves);
  EXPECT_EQ(skill.movements().n_directions(), 6);
  EXPECT_EQ(skill.movements().action(kClose), MovementAction::close);
  EXPECT_EQ(skill.movements().label(kStay), "stay");

  expect_parse_error([](json& m) { m["movements"].erase("actions"); },
                     "movements.actions: missing");
  expect_parse_error([](json& m) { m["movements"]["actions"] = "open"; },
                     "movements.actions: must be an array");
  expect_parse_error([](json& m) { m["movements"]["actions"][1] = "grip"; },
                     "movements.actions[1]: unknown action 'grip'");
  expect_parse_error([](json& m) { m["movements"]["actions"][2] = "open"; },
                     "movements.actions[2]: 'open' repeats movements.actions[0]");
  expect_parse_error([](json& m) { m["movements"]["actions"][0] = 3; },
                     "movements.actions[0]: must be a string");
  // The table's last axis counts the actions: one action fewer no longer fits it.
  expect_parse_error([](json& m) { m["movements"]["actions"].erase(2); }, "arrays.posterior.shape");
}

TEST(MovementActions, StepReturnsTheActionWithNoDisplacement) {
  a2l::Skill skill;
  ASSERT_TRUE(load(grasp_light_parts(), skill).ok());
  a2l::SkillState state(skill);
  a2l::Context c;
  c.object = {0.6, -0.2, 0.1};
  c.eef = c.object + Eigen::Vector3d(0.03, 0.0, 0.0);  // near bin, light off: close
  a2l::StepOutput out;
  ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
  EXPECT_EQ(out.movement, kClose);
  EXPECT_EQ(out.action, MovementAction::close);
  EXPECT_TRUE(out.displacement.isZero());
  EXPECT_NEAR(out.probability, 0.9, 1e-12);
  EXPECT_EQ(state.steps(), 1);  // an action is a movement of the run
  c.effect_produced = true;     // a stop carries no action
  EXPECT_EQ(a2l::step(skill, state, c, out), Status::effect_produced);
  EXPECT_EQ(out.action, MovementAction::none);
}

// Acceptance test of the demonstrated skills: "a light toggle mid-action switches the behaviour in
// the C++ step". The same eef/object context gives the light-off movement, then, after the light
// turned on, the light-on movement, in consecutive step() calls of one run; and the light-on
// behaviour ends with the demonstrated action (stay) where light-off would approach.
TEST(MovementActions, LightToggleMidActionSwitchesTheBehaviourInTheCppStep) {
  a2l::Skill skill;
  ASSERT_TRUE(load(grasp_light_parts(), skill).ok());
  const int light = skill.discretizer().find("light");
  ASSERT_EQ(light, 2);
  a2l::SkillState state(skill);
  a2l::Context c;
  c.object = {0.6, -0.2, 0.1};
  c.eef = c.object + Eigen::Vector3d(0.12, 0.0, 0.0);  // middle distance bin
  c.high_level[static_cast<size_t>(light)] = 0;        // off
  a2l::StepOutput out;

  // Light off: approach.
  ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
  EXPECT_EQ(out.movement, kMx);
  EXPECT_EQ(out.action, MovementAction::none);
  EXPECT_NEAR(out.displacement.x(), -0.05, 1e-15);
  // The light turns on mid-action: the same context now moves away, in the next step.
  c.high_level[static_cast<size_t>(light)] = 1;
  ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
  EXPECT_EQ(out.movement, kPx);
  EXPECT_NEAR(out.displacement.x(), 0.05, 1e-15);
  EXPECT_EQ(state.steps(), 2);  // one run, no reset between the two steps
  // Far from the object with the light on: wait (stay); with the light off: approach again.
  c.eef = c.object + Eigen::Vector3d(0.22, 0.0, 0.0);
  ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
  EXPECT_EQ(out.action, MovementAction::stay);
  EXPECT_TRUE(out.displacement.isZero());
  c.high_level[static_cast<size_t>(light)] = 0;
  ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
  EXPECT_EQ(out.movement, kMx);
  // The trace recorded the switch: the light's bin and the movement of each step.
  ASSERT_EQ(state.trace_size(), 4u);
  EXPECT_EQ(state.trace(0).bins[2], 0);
  EXPECT_EQ(state.trace(1).bins[2], 1);
  EXPECT_EQ(state.trace(0).movement, kMx);
  EXPECT_EQ(state.trace(1).movement, kPx);
  EXPECT_EQ(state.trace(2).movement, kStay);
}

}  // namespace test_skill_actions
