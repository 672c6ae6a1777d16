// The real-time path allocates nothing and throws nothing: step() over 1e5 random contexts
// (out-of-range positions, NaN, inf, unknown effects and high-level values), with and without
// smoothing; the executor's tick; the virtual scene's move.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <tuple>
#include <type_traits>

#include "a2l/bundle.hpp"
#include "a2l/executor.hpp"
#include "a2l/scene/virtual.hpp"
#include "a2l/skill.hpp"
#include "alloc_counter.hpp"
#include "bundle_builder.hpp"

namespace test_skill_noalloc {

using a2l::Status;

static_assert(
    noexcept(a2l::step(std::declval<const a2l::Skill&>(), std::declval<a2l::SkillState&>(),
                       std::declval<const a2l::Context&>(), std::declval<a2l::StepOutput&>())),
    "step() must be noexcept");
static_assert(noexcept(std::declval<a2l::Executor&>().tick()), "tick() must be noexcept");

double random_coordinate(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> pick(0, 19);
  std::uniform_real_distribution<double> near(-0.4, 0.4), far(-1e6, 1e6);
  switch (pick(rng)) {
    case 0:
      return std::numeric_limits<double>::quiet_NaN();
    case 1:
      return std::numeric_limits<double>::infinity();
    case 2:
      return -std::numeric_limits<double>::infinity();
    case 3:
      return far(rng);
    case 4:
      return std::numeric_limits<double>::max();
    default:
      return near(rng);
  }
}

int random_index(std::mt19937_64& rng, int n) {
  std::uniform_int_distribution<int> pick(0, 9);
  std::uniform_int_distribution<int> in(0, n - 1);
  switch (pick(rng)) {
    case 0:
      return -1 - in(rng);
    case 1:
      return n + in(rng);
    case 2:
      return std::numeric_limits<int>::min();
    default:
      return in(rng);
  }
}

// (smoothing, nearest-cell fallback, distance bins between explicit edges)
class StepNoAlloc : public ::testing::TestWithParam<std::tuple<bool, bool, bool>> {};

TEST_P(StepNoAlloc, RandomContextsAllocateNothingThrowNothingAndNeverGuess) {
  const auto [smoothing, fallback, edges] = GetParam();
  auto parts = a2l::testing::sample_parts(11, 0.3, smoothing);
  if (fallback) parts.manifest["execution"]["fallback"] = "nearest";
  if (edges) parts.manifest["variables"][1]["edges"] = {0.07, 0.10};
  const auto bytes = a2l::testing::build(parts);
  a2l::Skill skill;
  ASSERT_TRUE(a2l::load_bundle_from_memory(bytes.data(), bytes.size(), skill).ok());
  a2l::SkillState state(skill, 256);
  std::mt19937_64 rng(42);
  const int n = 100000;
  std::vector<a2l::Context> contexts(static_cast<size_t>(n));
  for (auto& c : contexts) {
    c.object = {0.7 + random_coordinate(rng) * 0.01, random_coordinate(rng) * 0.01,
                0.04 + random_coordinate(rng) * 0.01};
    c.eef = c.object +
            Eigen::Vector3d(random_coordinate(rng), random_coordinate(rng), random_coordinate(rng));
    c.effect = random_index(rng, 4);
    c.high_level[4] = random_index(rng, 2);
    c.effect_produced = std::uniform_int_distribution<int>(0, 99)(rng) == 0;
  }
  int counts[32] = {};
  int wrong = 0, fallbacks = 0;
  a2l::StepOutput out;
  bool threw = false;
  std::size_t allocations = 0;
  {
    a2l::test::AllocationGuard guard;
    try {
      for (int i = 0; i < n; ++i) {
        const a2l::Context& c = contexts[static_cast<size_t>(i)];
        if (state.steps() >= 10) state.reset();
        const Status s = a2l::step(skill, state, c, out);
        ++counts[static_cast<int>(s)];
        const bool unknown_input = !c.eef.allFinite() || !c.object.allFinite() || c.effect < 0 ||
                                   c.effect >= 4 || c.high_level[4] < 0 || c.high_level[4] >= 2;
        // Never a movement for an unknown input, always a movement from the table otherwise.
        if (s == Status::ok && (unknown_input || c.effect_produced)) ++wrong;
        if (s == Status::ok && (out.movement < 0 || out.movement >= 8)) ++wrong;
        if (s != Status::ok && out.movement != -1) ++wrong;
        if (unknown_input && !c.effect_produced && s != Status::unknown_context) ++wrong;
        if (out.record.fallback) {
          ++fallbacks;
          if (!fallback || s != Status::ok) ++wrong;  // marked only when it answered
        }
      }
    } catch (...) {
      threw = true;
    }
    allocations = guard.allocations();
  }
  EXPECT_FALSE(threw);
  EXPECT_EQ(allocations, 0u) << "step() allocated";
  EXPECT_EQ(wrong, 0);
  // The random contexts exercised every outcome.
  EXPECT_GT(counts[static_cast<int>(Status::ok)], 1000);
  EXPECT_GT(counts[static_cast<int>(Status::unknown_context)], 1000);
  EXPECT_GT(counts[static_cast<int>(Status::effect_produced)], 100);
  EXPECT_EQ(state.trace_size(), 256u);
  // With the fallback, the uniform rows (30 %) of known contexts answer from it.
  if (fallback) {
    EXPECT_GT(fallbacks, 1000);
  }
}

INSTANTIATE_TEST_SUITE_P(SmoothingFallbackEdges, StepNoAlloc,
                         ::testing::Combine(::testing::Bool(), ::testing::Bool(),
                                            ::testing::Bool()));

// The `approach` fallback on a planar table (effect, distance, orientation, light: the push
// skills' kind of variables, where it heads for a cell's centre), with and without smoothing,
// the distance in equal bins or between explicit edges; variants 4 and 5 with the revisit rule
// over runs that come back to the cells of a few points; 0 and 5 with the alignment rule.
TEST(StepNoAlloc, ApproachFallbackAllocatesNothingAndThrowsNothing) {
  for (const int variant : {0, 1, 2, 3, 4, 5}) {
    const bool smoothing = variant % 2 == 1, edges = variant == 2 || variant == 3;
    const bool revisits = variant >= 4;
    auto parts = a2l::testing::sample_parts(11, 0.3, smoothing);
    parts.manifest["variables"].erase(3);  // no inclination
    if (edges) parts.manifest["variables"][1]["edges"] = {0.07, 0.10};
    parts.shape = {4, 3, 8, 2};
    parts.argmax.resize(4 * 3 * 8 * 2);
    parts.posterior.resize(parts.argmax.size() * 8);
    parts.manifest["execution"]["fallback"] = "approach";
    if (variant == 0 || variant >= 3) parts.manifest["execution"]["clearance"] = 0.10;
    if (variant == 0 || variant == 5) parts.manifest["execution"]["align"] = 0.05;
    if (revisits) parts.manifest["execution"]["avoid_revisits"] = true;
    const auto bytes = a2l::testing::build(parts);
    a2l::Skill skill;
    ASSERT_TRUE(a2l::load_bundle_from_memory(bytes.data(), bytes.size(), skill).ok());
    a2l::SkillState state(skill, 256);
    std::mt19937_64 rng(43);
    const int n = 50000;
    std::vector<a2l::Context> contexts(static_cast<size_t>(n));
    std::array<Eigen::Vector3d, 12> points;  // the revisit variants' points (valid ones)
    std::uniform_real_distribution<double> around(-0.25, 0.25);
    std::uniform_int_distribution<int> which(0, 11);
    for (auto& q : points) q = {around(rng), around(rng), 0.0};
    std::vector<int> point_of(static_cast<size_t>(n), -1), moves(static_cast<size_t>(n), -1);
    for (std::size_t i = 0; i < contexts.size(); ++i) {
      a2l::Context& c = contexts[i];
      point_of[i] = which(rng);
      c.object = {0.7, 0.0, 0.04};
      c.eef = c.object +
              (revisits ? points[static_cast<size_t>(point_of[i])]
                        : Eigen::Vector3d(random_coordinate(rng), random_coordinate(rng), 0.0));
      c.effect = revisits ? 1 : random_index(rng, 4);
      c.high_level[3] = revisits ? 0 : random_index(rng, 2);
    }
    int fallbacks = 0, wrong = 0;
    bool threw = false;
    std::size_t allocations = 0;
    a2l::StepOutput out;
    {
      a2l::test::AllocationGuard guard;
      try {
        for (std::size_t i = 0; i < contexts.size(); ++i) {
          if (state.steps() >= 10) state.reset();
          const Status s = a2l::step(skill, state, contexts[i], out);
          if (s == Status::ok && (out.movement < 0 || out.movement >= 8)) ++wrong;
          if (out.record.fallback) ++fallbacks;
          moves[i] = out.movement;
        }
      } catch (...) {
        threw = true;
      }
      allocations = guard.allocations();
    }
    EXPECT_FALSE(threw);
    EXPECT_EQ(allocations, 0u) << "step() allocated (smoothing " << smoothing << ", edges " << edges
                               << ")";
    EXPECT_EQ(wrong, 0);
    EXPECT_GT(fallbacks, 1000);
    if (revisits) {  // the rule did change answers: a point answered differently in a run
      int differs = 0;
      for (std::size_t i = 1; i < contexts.size(); ++i) {
        const std::size_t run = i / 10 * 10;  // runs of 10 steps (every step is ok here)
        for (std::size_t j = run; j < i; ++j) {
          if (point_of[j] == point_of[i] && moves[j] >= 0 && moves[i] >= 0 &&
              moves[j] != moves[i]) {
            ++differs;
            break;
          }
        }
      }
      EXPECT_GT(differs, 1000);
    }
  }
}

TEST(SceneNoAlloc, VirtualMoveAllocatesNothing) {
  a2l::VirtualScene scene;
  scene.reset({0.2, 0.0, 0.04}, {0.0, 0.0, 0.04});
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  a2l::test::AllocationGuard guard;
  int moved = 0;
  for (int i = 0; i < 10000; ++i) {
    if (i % 20 == 0) scene.reset({0.2 * std::cos(i), 0.2 * std::sin(i), 0.04}, {0, 0, 0.04});
    Eigen::Vector3d to_box = scene.object_position() - scene.eef_position();
    moved += scene.move(0.3 * to_box + Eigen::Vector3d(u(rng), u(rng), 0.0));
  }
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_GT(moved, 100);
}

TEST(ExecutorNoAlloc, TickAllocatesNothing) {
  const char* dir = std::getenv("A2L_ROBOTS_DIR");
  ASSERT_TRUE(dir != nullptr && *dir) << "set A2L_ROBOTS_DIR (make test-cpp does)";
  a2l::Kinematics kin;
  ASSERT_TRUE(a2l::Kinematics::load(std::string(dir) + "/baxter_description/urdf/baxter.urdf",
                                    "base", "right_gripper", kin)
                  .ok());
  Eigen::VectorXd q0(7);
  q0 << 0.08, -1.0, 1.19, 1.94, -0.67, 1.03, 0.5;
  a2l::Executor ex;
  ASSERT_TRUE(ex.init(kin, q0).ok());
  const Eigen::Vector3d p0 = ex.position();
  const Eigen::Matrix3d r0 = ex.pose().linear();
  // 16 movements of 5 cm, as the runtime makes them: out along 8 headings and back to p0,
  // each aiming at the start's orientation as the ROS node aims at the skill's.
  constexpr int kMoves = 16;
  int ticks[kMoves] = {};
  Eigen::Vector3d targets[kMoves], reached_at[kMoves];
  a2l::JointVector q_at[kMoves];
  for (auto& q : q_at) q.resize(7);
  for (int k = 0; k < kMoves; ++k) {
    const double a = (k / 2) * 3.14159265358979 / 4;
    targets[k] = k % 2 == 0 ? p0 + 0.05 * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0) : p0;
  }
  {
    a2l::test::AllocationGuard guard;
    for (int k = 0; k < kMoves; ++k) {
      ASSERT_EQ(ex.set_orientation(r0), Status::ok);
      ASSERT_EQ(ex.set_target(targets[k]), Status::ok);
      while (!ex.reached()) {
        ASSERT_EQ(ex.tick(), Status::ok);
        ++ticks[k];
      }
      reached_at[k] = ex.position();
      q_at[k] = ex.q();
    }
    EXPECT_EQ(guard.allocations(), 0u);
  }
  for (int k = 0; k < kMoves; ++k) {
    // 5 cm at most 0.25 m/s, one tick per 1 ms: at least 200 ticks; the reference point
    // moves at full speed on a straight line, so the arm follows within a few ticks.
    EXPECT_GE(ticks[k], 200) << "movement " << k;
    EXPECT_LE(ticks[k], 210) << "movement " << k;
    // Independently of the executor's own bookkeeping: forward kinematics of the command.
    Eigen::Isometry3d pose;
    kin.fk(q_at[k], pose);
    EXPECT_LT((pose.translation() - targets[k]).norm(), 1e-5) << "movement " << k;
    EXPECT_LT((reached_at[k] - targets[k]).norm(), 1e-5) << "movement " << k;
  }
  // The same movements with commands scaled down to a fifth of the velocity limits.
  a2l::ExecutorOptions slow;
  slow.velocity_margin = 0.2;
  ASSERT_TRUE(ex.init(kin, q0, slow).ok());
  {
    a2l::test::AllocationGuard guard;
    for (int k = 0; k < kMoves; ++k) {
      ASSERT_EQ(ex.set_target(targets[k]), Status::ok);
      while (!ex.reached()) ASSERT_EQ(ex.tick(), Status::ok);
    }
    EXPECT_EQ(guard.allocations(), 0u);
  }
  EXPECT_GT(ex.scaled_ticks(), 0);
  EXPECT_LT((ex.position() - p0).norm(), 1e-5);
  // A joint inside its limit band: the self-motion away from the limit, held in place.
  Eigen::VectorXd q_band = q0;
  q_band[0] = kin.lower()[0] + 0.04 * (kin.upper()[0] - kin.lower()[0]);
  ASSERT_TRUE(ex.init(kin, q_band).ok());
  ASSERT_EQ(ex.set_target(ex.position()), Status::ok);
  {
    a2l::test::AllocationGuard guard;
    for (int k = 0; k < 500; ++k) ASSERT_EQ(ex.tick(), Status::ok);
    EXPECT_EQ(guard.allocations(), 0u);
  }
  EXPECT_GT(ex.q()[0], q_band[0]);  // it moved away from the limit
}

}  // namespace test_skill_noalloc
