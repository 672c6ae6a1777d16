// The vocabulary the core owns (effects.hpp, movement_repertoire.hpp): the push effects'
// names, indices and directions, the push and away tests with their constants, the default
// directions and their labels; the effect tests allocate nothing and throw nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "a2l/effects.hpp"
#include "a2l/movement_repertoire.hpp"
#include "alloc_counter.hpp"

namespace test_effects {

using V = Eigen::Vector3d;
using V2 = Eigen::Vector2d;

static_assert(noexcept(a2l::stayed_away(std::declval<const V&>(), std::declval<const V&>(),
                                        std::declval<const V&>())),
              "stayed_away() must be noexcept");
static_assert(noexcept(a2l::push_test(std::declval<const V2&>(), 0)),
              "push_test() must be noexcept");

TEST(EffectNames, InClassifyEffectOrder) {
  const std::vector<std::string> four{"left", "right", "close", "far"};
  const std::vector<std::string> eight{"left",       "right",       "close",    "far",
                                       "close_left", "close_right", "far_left", "far_right"};
  EXPECT_EQ(a2l::effect_names(4), four);
  EXPECT_EQ(a2l::effect_names(8), eight);
  EXPECT_TRUE(a2l::effect_names(5).empty());
  EXPECT_STREQ(a2l::effect_name(-1), "none");
  EXPECT_STREQ(a2l::effect_name(8), "none");
  for (int i = 0; i < a2l::kMaxPushEffects; ++i) {
    EXPECT_EQ(a2l::effect_index(a2l::effect_name(i)), i);
    // The direction of each effect is classified as that effect.
    const V2 d = a2l::effect_direction(i);
    EXPECT_EQ(a2l::classify_effect(V(0.05 * d.x(), 0.05 * d.y(), 0.0), 8), i) << i;
  }
  EXPECT_EQ(a2l::effect_index("grasped"), -1);
  EXPECT_TRUE(a2l::effect_direction(8).isZero());
}

TEST(EffectTests, PushDoneAlongOrAcross) {
  const int far = a2l::effect_index("far"), left = a2l::effect_index("left");
  EXPECT_DOUBLE_EQ(a2l::kPushDistance, 0.05);
  auto t = a2l::push_test(V2(0.03, 0.0), far);
  EXPECT_FALSE(t.done);
  t = a2l::push_test(V2(0.05, 0.01), far);
  EXPECT_TRUE(t.done);
  EXPECT_TRUE(t.success);
  t = a2l::push_test(V2(0.05, 0.06), far);  // across dominates: failure
  EXPECT_TRUE(t.done);
  EXPECT_FALSE(t.success);
  t = a2l::push_test(V2(0.0, -0.05), far);  // across only
  EXPECT_TRUE(t.done);
  EXPECT_FALSE(t.success);
  t = a2l::push_test(V2(-0.01, 0.06), left);
  EXPECT_TRUE(t.done);
  EXPECT_TRUE(t.success);
  EXPECT_FALSE(a2l::push_test(V2(1.0, 1.0), 5).done);  // not an axis effect
}

TEST(EffectTests, AwayAtTheRetreatPoseObjectStill) {
  EXPECT_TRUE(a2l::retreat_offset().isApprox(V(-0.12, 0.0, 0.16)));
  EXPECT_DOUBLE_EQ(a2l::kAwayRadius, 0.04);
  EXPECT_DOUBLE_EQ(a2l::kAwayTolerance, 0.01);
  const V block(0.6, 0.1, 0.02), still(0.0, 0.0, 0.0);
  const V at = block + a2l::retreat_offset();
  EXPECT_TRUE(a2l::stayed_away(at, block, still));
  EXPECT_TRUE(a2l::stayed_away(at + V(0.0, 0.039, 0.0), block, still));
  EXPECT_FALSE(a2l::stayed_away(at + V(0.0, 0.041, 0.0), block, still));
  EXPECT_FALSE(a2l::stayed_away(at, block, V(0.01, 0.0, 0.0)));  // the block moved 1 cm
  EXPECT_TRUE(a2l::stayed_away(at, block, V(0.009, 0.0, 0.0)));
  EXPECT_FALSE(a2l::stayed_away(V(NAN, 0.0, 0.0), block, still));
  EXPECT_FALSE(a2l::stayed_away(at, block, V(NAN, 0.0, 0.0)));
}

TEST(EffectTestsNoAlloc, RandomInputs) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 0.05);
  std::vector<V> eef(20000), obj(20000);
  for (std::size_t k = 0; k < eef.size(); ++k) {
    eef[k] = V(n(rng), n(rng), n(rng));
    obj[k] = V(n(rng), n(rng), n(rng));
  }
  eef[0].x() = NAN;
  long away = 0, done = 0;
  bool threw = false;
  std::size_t allocations = 0;
  {
    a2l::test::AllocationGuard guard;
    try {
      for (std::size_t k = 0; k < eef.size(); ++k) {
        away += a2l::stayed_away(eef[k], obj[k], 0.1 * (eef[k] - obj[k]));
        done += a2l::push_test(eef[k].head<2>(), static_cast<int>(k % 4)).done;
      }
    } catch (...) {
      threw = true;
    }
    allocations = guard.allocations();
  }
  EXPECT_FALSE(threw);
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(done, 1000);
  EXPECT_GE(away, 0);
}

TEST(DefaultDirections, AxisMovesFirstThenDiagonals) {
  const std::vector<Eigen::Vector3i> d = a2l::default_directions();
  ASSERT_EQ(d.size(), 26u);
  const char* first[] = {"+x",   "-x",   "+y",   "-y",   "+z",  "-z",
                         "+x+y", "+x-y", "-x+y", "-x-y", "+x+z"};
  for (std::size_t i = 0; i < std::size(first); ++i)
    EXPECT_EQ(a2l::direction_label(d[i]), first[i]);
  EXPECT_EQ(a2l::direction_label(d[25]), "-x-y-z");
  for (std::size_t i = 0; i < d.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) EXPECT_NE(d[i], d[j]);
  }
  const std::vector<Eigen::Vector3i> p = a2l::default_directions(true);
  ASSERT_EQ(p.size(), 8u);
  std::vector<std::string> labels;
  for (const auto& v : p) labels.push_back(a2l::direction_label(v));
  EXPECT_EQ(labels,
            (std::vector<std::string>{"+x", "-x", "+y", "-y", "+x+y", "+x-y", "-x+y", "-x-y"}));
  EXPECT_EQ(a2l::direction_label(Eigen::Vector3i::Zero()), "");
  a2l::MovementRepertoire r;
  ASSERT_TRUE(a2l::MovementRepertoire::create(0.05, p, {}, r).ok());
  EXPECT_EQ(r.size(), 8);
}

}  // namespace test_effects
