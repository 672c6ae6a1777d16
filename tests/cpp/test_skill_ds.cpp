// DS phases (docs/bundle_format.md, "ds_phases"): the loader reads them and refuses bad ones
// naming the phase's index and the field; step_ds() follows the phase selected by the
// high-level states (step-length displacements along the DS velocity, capped at the target,
// the end action once within tolerance, then converged), switches phase when a state changes
// mid-run, stops on unknown contexts, and allocates and throws nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <type_traits>

#include "a2l/bundle.hpp"
#include "a2l/skill.hpp"
#include "alloc_counter.hpp"
#include "bundle_builder.hpp"

namespace test_skill_ds {

using a2l::MovementAction;
using a2l::Status;
using a2l::testing::Array;
using a2l::testing::array_of;
using a2l::testing::json;

static_assert(noexcept(a2l::step_ds(
                  std::declval<const a2l::Skill&>(), std::declval<a2l::SkillState&>(),
                  std::declval<const Eigen::Vector3d&>(), std::declval<const Eigen::Vector3d&>(),
                  std::declval<const a2l::DSStateValues&>(), std::declval<a2l::StepOutput&>())),
              "step_ds() must be noexcept");

constexpr int kLight = 0, kGripper = 1;  // DS state variables
constexpr int kClose = 9;                // the push skill's 8 directions, then open, close, stay

struct Phase {
  json entry;
  std::vector<double> centers, vectors, rhos;
};

// approach: light off, gripper open -> (0, 0, 0.02) above the object, then close; three maps
// bend the path far from the target (their weight there underflows). lift: gripper closed ->
// 0.15 m up. retreat: light on -> 0.15 m away along +x, no end action.
std::vector<Phase> sample_phases() {
  std::vector<Phase> ph(3);
  ph[0].entry = {{"name", "approach"},
                 {"when", {{"light", "off"}, {"gripper", "open"}}},
                 {"end_action", "close"},
                 {"tolerance", 0.01},
                 {"ds",
                  {{"dim", 3},
                   {"n_maps", 3},
                   {"speed", 1.0},
                   {"direction", "to_demo"},
                   {"target", {0.0, 0.0, 0.02}}}}};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 3; ++i) {
    const double c[3] = {0.14, 0.04, 0.10};
    for (int j = 0; j < 3; ++j) {
      ph[0].centers.push_back(c[j] + 0.02 * u(rng));
      ph[0].vectors.push_back(0.015 * u(rng));
    }
    ph[0].rhos.push_back(30.0);  // rho ||v|| <= 30 * 0.026 < sqrt(e/2)
  }
  ph[1].entry = {{"name", "lift"},
                 {"when", {{"gripper", "closed"}}},
                 {"end_action", nullptr},
                 {"tolerance", 0.01},
                 {"ds",
                  {{"dim", 3},
                   {"n_maps", 0},
                   {"speed", 1.0},
                   {"direction", "to_demo"},
                   {"target", {0.0, 0.0, 0.15}}}}};
  ph[2].entry = {{"name", "retreat"},
                 {"when", {{"light", "on"}}},
                 {"end_action", nullptr},
                 {"tolerance", 0.01},
                 {"ds",
                  {{"dim", 3},
                   {"n_maps", 0},
                   {"speed", 2.0},
                   {"direction", "to_line"},
                   {"target", {0.15, 0.0, 0.0}}}}};
  return ph;
}

// The push skill of bundle_builder (no uniform row) with the actions open, close, stay and the
// phases; `edit` changes the manifest, `patch` the arrays entry.
std::vector<std::uint8_t> phase_bundle(const std::function<void(json&)>& edit = nullptr,
                                       const std::vector<Phase>& phases = sample_phases(),
                                       const json& patch = json()) {
  a2l::testing::BundleParts p = a2l::testing::sample_parts(7, 0.0);
  p.manifest["movements"]["actions"] = {"open", "close", "stay"};
  std::vector<double> post;
  for (std::size_t r = 0; r < p.argmax.size(); ++r) {
    for (int m = 0; m < 8; ++m) post.push_back(p.posterior[r * 8 + static_cast<std::size_t>(m)]);
    for (int m = 0; m < 3; ++m) post.push_back(0.0);
  }
  json m = p.manifest;
  m["ds_phases"] = {{"states",
                     {{{"name", "light"}, {"values", {"off", "on"}}},
                      {{"name", "gripper"}, {"values", {"open", "closed"}}}}},
                    {"phases", json::array()}};
  std::vector<std::int64_t> pshape = p.shape;
  pshape.push_back(11);
  std::vector<Array> arrays = {array_of("posterior", "float64", pshape, post),
                               array_of("argmax", "int32", p.shape, p.argmax)};
  for (std::size_t i = 0; i < phases.size(); ++i) {
    m["ds_phases"]["phases"].push_back(phases[i].entry);
    const auto k = static_cast<std::int64_t>(phases[i].rhos.size());
    const std::string pre = "ds_phase" + std::to_string(i) + "_";
    arrays.push_back(array_of(pre + "centers", "float64", {k, 3}, phases[i].centers));
    arrays.push_back(array_of(pre + "vectors", "float64", {k, 3}, phases[i].vectors));
    arrays.push_back(array_of(pre + "rhos", "float64", {k}, phases[i].rhos));
  }
  if (edit) edit(m);
  return a2l::testing::serialise(m, arrays, patch);
}

a2l::Result load(const std::vector<std::uint8_t>& b, a2l::Skill& s) {
  return a2l::load_bundle_from_memory(b.data(), b.size(), s, "phases.a2lb");
}

void expect_error(const std::vector<std::uint8_t>& b, const std::string& needle) {
  a2l::Skill s;
  const a2l::Result r = load(b, s);
  EXPECT_EQ(r.status, Status::parse_error) << r.message;
  EXPECT_NE(r.message.find(needle), std::string::npos)
      << "message '" << r.message << "' does not name '" << needle << "'";
}

a2l::DSStateValues values(int light, int gripper) {
  a2l::DSStateValues v{};
  v[kLight] = light;
  v[kGripper] = gripper;
  return v;
}

TEST(DSPhases, BundlePhasesLoad) {
  a2l::Skill skill;
  const a2l::Result r = load(phase_bundle(), skill);
  ASSERT_TRUE(r.ok()) << r.message;
  const a2l::DSPhaseSet& set = skill.ds_phases();
  ASSERT_EQ(set.phases.size(), 3u);
  EXPECT_EQ(set.find_state("gripper"), kGripper);
  EXPECT_EQ(set.phases[0].name, "approach");
  EXPECT_EQ(set.phases[0].end_action, MovementAction::close);
  EXPECT_EQ(set.phases[0].when.size(), 2u);
  EXPECT_EQ(set.phases[0].ds.n_maps(), 3);
  EXPECT_EQ(set.phases[1].end_action, MovementAction::none);
  EXPECT_DOUBLE_EQ(set.phases[2].ds.speed(), 2.0);
  EXPECT_EQ(set.select(values(0, 0)), 0);
  EXPECT_EQ(set.select(values(0, 1)), 1);
  EXPECT_EQ(set.select(values(1, 0)), 2);  // first match wins: light on, gripper open
  EXPECT_EQ(set.select(values(1, 1)), 1);  // gripper closed comes before light on
  EXPECT_EQ(set.select(values(0, 7)), -1);
  // A bundle without the section has no phase.
  const auto plain = a2l::testing::build(a2l::testing::sample_parts());
  a2l::Skill none;
  ASSERT_TRUE(load(plain, none).ok());
  EXPECT_TRUE(none.ds_phases().empty());
}

TEST(DSPhases, LoaderNamesThePhaseAndTheField) {
  expect_error(phase_bundle([](json& m) { m["ds_phases"]["phases"][1]["tolerance"] = 0.0; }),
               "ds_phases.phases[1].tolerance: must be > 0");
  expect_error(phase_bundle([](json& m) { m["ds_phases"]["phases"][1].erase("tolerance"); }),
               "ds_phases.phases[1].tolerance: missing");
  expect_error(phase_bundle([](json& m) { m["ds_phases"]["phases"][0]["when"]["colour"] = "red"; }),
               "ds_phases.phases[0].when.colour: not a state");
  expect_error(phase_bundle([](json& m) { m["ds_phases"]["phases"][2]["when"]["light"] = "dim"; }),
               "ds_phases.phases[2].when.light: 'dim' is not a value of the state (off, on)");
  expect_error(phase_bundle([](json& m) { m["ds_phases"]["phases"][0]["end_action"] = "grip"; }),
               "ds_phases.phases[0].end_action: unknown action 'grip'");
  expect_error(phase_bundle([](json& m) { m["ds_phases"]["phases"][2]["ds"]["speed"] = -1.0; }),
               "ds_phases.phases[2].ds.speed: must be > 0");
  expect_error(phase_bundle([](json& m) { m["ds_phases"]["phases"][1]["ds"]["dim"] = 2; }),
               "ds_phases.phases[1].ds.");
  expect_error(phase_bundle([](json& m) { m["ds_phases"]["phases"][0]["name"] = 3; }),
               "ds_phases.phases[0].name: must be a string");
  expect_error(phase_bundle([](json& m) { m["ds_phases"]["states"][1]["name"] = "light"; }),
               "ds_phases.states[1].name: 'light' is declared twice");
  expect_error(phase_bundle([](json& m) { m["ds_phases"]["phases"] = json::array(); }),
               "ds_phases.phases: needs 1 to 64 phases");
  expect_error(phase_bundle(nullptr, sample_phases(), {{"ds_phase1_rhos", nullptr}}),
               "arrays.ds_phase1_rhos: missing");
  // A map breaking the invertibility bound: the message names the phase and the map.
  std::vector<Phase> bad = sample_phases();
  bad[0].rhos[2] = 200.0;
  expect_error(phase_bundle(nullptr, bad), "ds_phases.phases[0].ds: ");
  expect_error(phase_bundle(nullptr, bad), "map 2");
}

TEST(DSPhases, StepDSApproachesThenClosesOnceThenConverges) {
  a2l::Skill skill;
  ASSERT_TRUE(load(phase_bundle(), skill).ok());
  a2l::SkillState state(skill);
  const Eigen::Vector3d object(0.6, -0.2, 0.1);
  Eigen::Vector3d eef = object + Eigen::Vector3d(0.15, 0.05, 0.10);
  const Eigen::Vector3d target = object + Eigen::Vector3d(0.0, 0.0, 0.02);
  a2l::StepOutput out;
  int moves = 0;
  double last = (eef - target).norm();
  for (; moves < 12; ++moves) {
    ASSERT_EQ(a2l::step_ds(skill, state, eef, object, values(0, 0), out), Status::ok);
    EXPECT_EQ(out.record.phase, 0);
    if (out.action != MovementAction::none) break;
    EXPECT_EQ(out.movement, -1);
    const double len = out.displacement.norm();
    EXPECT_NEAR(len, std::min(0.05, (eef - target).norm()), 1e-12);  // capped at the target
    Eigen::Vector3d v;
    ASSERT_EQ(skill.ds_phases().phases[0].ds.velocity(eef - object, v), Status::ok);
    EXPECT_NEAR(out.displacement.normalized().dot(v.normalized()), 1.0, 1e-12);
    eef += out.displacement;
    const double d = (eef - target).norm();
    EXPECT_LT(d, last);
    last = d;
  }
  EXPECT_LE(moves, 6);  // about 0.19 m in 0.05 m steps
  EXPECT_EQ(out.action, MovementAction::close);
  EXPECT_EQ(out.movement, kClose);
  EXPECT_TRUE(out.displacement.isZero());
  EXPECT_LE((eef - target).norm(), 0.01);
  // emitted once: the gripper did not close (state unchanged), the phase has converged
  EXPECT_EQ(a2l::step_ds(skill, state, eef, object, values(0, 0), out), Status::converged);
  EXPECT_EQ(out.action, MovementAction::none);
  // the gripper closed: the lift phase moves up
  ASSERT_EQ(a2l::step_ds(skill, state, eef, object, values(0, 1), out), Status::ok);
  EXPECT_EQ(out.record.phase, 1);
  EXPECT_NEAR(out.displacement.z(), 0.05, 1e-9);
  // a new run may emit the end action again
  state.reset();
  ASSERT_EQ(a2l::step_ds(skill, state, eef, object, values(0, 0), out), Status::ok);
  EXPECT_EQ(out.action, MovementAction::close);
}

TEST(DSPhases, LightToggleMidRunSwitchesThePhaseInTheNextStep) {
  a2l::Skill skill;
  ASSERT_TRUE(load(phase_bundle(), skill).ok());
  a2l::SkillState state(skill);
  const Eigen::Vector3d object(0.6, -0.2, 0.1);
  const Eigen::Vector3d eef = object + Eigen::Vector3d(0.05, 0.0, 0.10);
  a2l::StepOutput out;
  ASSERT_EQ(a2l::step_ds(skill, state, eef, object, values(0, 0), out), Status::ok);
  EXPECT_EQ(out.record.phase, 0);
  EXPECT_LT(out.displacement.z(), 0.0);  // down toward the object
  ASSERT_EQ(a2l::step_ds(skill, state, eef, object, values(1, 0), out), Status::ok);
  EXPECT_EQ(out.record.phase, 2);
  // linear retreat DS: straight toward (0.15, 0, 0) relative to the object
  const Eigen::Vector3d want = (Eigen::Vector3d(0.15, 0.0, 0.0) - (eef - object)).normalized();
  EXPECT_NEAR(out.displacement.normalized().dot(want), 1.0, 1e-12);
  // at the retreat target: no end action, converged
  const Eigen::Vector3d away = object + Eigen::Vector3d(0.155, 0.0, 0.0);
  EXPECT_EQ(a2l::step_ds(skill, state, away, object, values(1, 0), out), Status::converged);
  EXPECT_EQ(out.record.phase, 2);
  ASSERT_EQ(state.trace_size(), 3u);
  EXPECT_EQ(state.trace(0).phase, 0);
  EXPECT_EQ(state.trace(1).phase, 2);
}

TEST(DSPhases, StopsOnUnknownContextsAndTheStepCap) {
  a2l::Skill skill;
  ASSERT_TRUE(load(phase_bundle(), skill).ok());
  a2l::SkillState state(skill);
  const Eigen::Vector3d object(0.6, -0.2, 0.1);
  const Eigen::Vector3d eef = object + Eigen::Vector3d(0.15, 0.0, 0.1);
  a2l::StepOutput out;
  EXPECT_EQ(a2l::step_ds(skill, state, eef, object, values(0, 5), out), Status::unknown_context);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(a2l::step_ds(skill, state, Eigen::Vector3d(nan, 0, 0), object, values(0, 0), out),
            Status::unknown_context);
  EXPECT_TRUE(out.displacement.isZero());
  for (int i = 0; i < 12; ++i) {
    ASSERT_EQ(a2l::step_ds(skill, state, eef, object, values(1, 0), out), Status::ok);
  }
  EXPECT_EQ(a2l::step_ds(skill, state, eef, object, values(1, 0), out), Status::step_cap);
  // a skill without phases, or an unusable state
  a2l::Skill plain;
  const auto b = a2l::testing::build(a2l::testing::sample_parts());
  ASSERT_TRUE(load(b, plain).ok());
  a2l::SkillState ps(plain);
  EXPECT_EQ(a2l::step_ds(plain, ps, eef, object, values(0, 0), out), Status::not_initialized);
  a2l::SkillState unusable;
  EXPECT_EQ(a2l::step_ds(skill, unusable, eef, object, values(0, 0), out), Status::not_initialized);
}

TEST(StepDSNoAlloc, RandomInputsAllocateNothingThrowNothing) {
  a2l::Skill skill;
  ASSERT_TRUE(load(phase_bundle(), skill).ok());
  a2l::SkillState state(skill, 64);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> near(-0.3, 0.3);
  std::uniform_int_distribution<int> pick(0, 19), value(-1, 2);
  const double specials[3] = {std::numeric_limits<double>::quiet_NaN(),
                              std::numeric_limits<double>::infinity(), 1e300};
  const int n = 100000;
  std::vector<Eigen::Vector3d> eefs(n), objects(n);
  std::vector<a2l::DSStateValues> states(n);
  for (int i = 0; i < n; ++i) {
    objects[i] = Eigen::Vector3d(0.6, -0.2, 0.1);
    for (int j = 0; j < 3; ++j) {
      const int k = pick(rng);
      eefs[i][j] = objects[i][j] + (k < 3 ? specials[k] : near(rng));
    }
    states[i] = values(value(rng), value(rng));
  }
  a2l::StepOutput out;
  int ok = 0, actions = 0, stops = 0;  // actions: end actions emitted
  {
    a2l::test::AllocationGuard guard;
    for (int i = 0; i < n; ++i) {
      if (i % 10 == 0) state.reset();
      const Status s = a2l::step_ds(skill, state, eefs[i], objects[i], states[i], out);
      if (s == Status::ok) {
        ++ok;
        actions += out.action != MovementAction::none;
        if (!(out.displacement.norm() <= 0.05 + 1e-12)) ADD_FAILURE() << "step too long";
      } else {
        ++stops;
        if (!out.displacement.isZero()) ADD_FAILURE() << "a stop displaced";
      }
    }
    EXPECT_EQ(guard.allocations(), 0u);
  }
  EXPECT_GT(ok, n / 4);
  EXPECT_GT(stops, n / 10);
  EXPECT_GT(actions, 0);
}

}  // namespace test_skill_ds
