// The context bins (Discretizer::context_bin; a distance with equal bins or explicit edges) and
// the effect classification (classify_effect), the one implementation the runtime step and the
// Python learning side share: unknown contexts, the object at the end-effector, agreement with
// discretize(), and no allocation and no exception over 1e5 random inputs (NaN, inf, huge and
// ordinary coordinates).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <type_traits>

#include "a2l/discretizer.hpp"
#include "a2l/effects.hpp"
#include "alloc_counter.hpp"

namespace test_bins_noalloc {

using a2l::Discretizer;
using a2l::Variable;
using a2l::VariableKind;
using V = Eigen::Vector3d;

static_assert(noexcept(Discretizer::context_bin(std::declval<const Variable&>(),
                                                std::declval<const V&>(),
                                                std::declval<const V&>())),
              "context_bin() must be noexcept");
static_assert(noexcept(a2l::classify_effect(std::declval<const V&>())),
              "classify_effect() must be noexcept");

Variable variable(VariableKind kind, int n, double low = 0.0, double high = 0.0) {
  Variable v;
  v.name = a2l::variable_kind_name(kind);
  v.kind = kind;
  v.n_bins = n;
  v.low = low;
  v.high = high;
  return v;
}

double coordinate(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> pick(0, 19);
  std::uniform_real_distribution<double> near(-0.4, 0.4);
  switch (pick(rng)) {
    case 0:
      return std::numeric_limits<double>::quiet_NaN();
    case 1:
      return std::numeric_limits<double>::infinity();
    case 2:
      return -std::numeric_limits<double>::max();
    case 3:
      return 0.0;
    default:
      return near(rng);
  }
}

TEST(ContextBin, UnknownContextIsMinusOneAndTheObjectAtTheEefHasABin) {
  const Variable d = variable(VariableKind::distance, 3, 0.05, 0.20);
  const Variable o = variable(VariableKind::orientation, 16);
  const Variable i = variable(VariableKind::inclination, 8);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double big = std::numeric_limits<double>::max();
  for (const Variable* v : {&d, &o, &i}) {
    EXPECT_EQ(Discretizer::context_bin(*v, V(nan, 0, 0), V::Zero()), -1) << v->name;
    EXPECT_EQ(Discretizer::context_bin(*v, V::Zero(), V(0, 0, INFINITY)), -1) << v->name;
    // Both positions finite, their difference not: an unknown context too.
    EXPECT_EQ(Discretizer::context_bin(*v, V(big, 0, 0), V(-big, 0, 0)), -1) << v->name;
  }
  // The object exactly at the end-effector: d = 0, atan2(0, 0) = 0 (theta 0: bin n/2), phi 0.
  const V p(0.7, -0.1, 0.04);
  EXPECT_EQ(Discretizer::context_bin(d, p, p), 0);
  EXPECT_EQ(Discretizer::context_bin(o, p, p), 8);
  EXPECT_EQ(Discretizer::context_bin(i, p, p), 0);
  // Kinds without geometry have no context bin.
  Variable e = variable(VariableKind::effect, 4);
  EXPECT_EQ(Discretizer::context_bin(e, p, V::Zero()), -1);
}

TEST(ContextBin, OffsetsAreDistanceBinsOfTheEefOffsetAlongXAndY) {
  // 3 bins over [-0.135, 0.135]: edges at -0.045 and 0.045 (a box face grown by 1 cm).
  const Variable x = variable(VariableKind::offset_x, 3, -0.135, 0.135);
  const Variable y = variable(VariableKind::offset_y, 3, -0.135, 0.135);
  const V obj(0.6, -0.2, 0.05);
  // 4.1 cm off the object's centre along x: in front of the y faces (middle bin); 5.9 cm:
  // beside them. The same points along y, and the other coordinate does not matter.
  EXPECT_EQ(Discretizer::context_bin(x, obj + V(0.041, 0.141, 0.3), obj), 1);
  EXPECT_EQ(Discretizer::context_bin(x, obj + V(0.059, 0.091, 0.0), obj), 2);
  EXPECT_EQ(Discretizer::context_bin(x, obj + V(-0.059, 0.0, 0.0), obj), 0);
  EXPECT_EQ(Discretizer::context_bin(y, obj + V(0.141, 0.041, 0.0), obj), 1);
  EXPECT_EQ(Discretizer::context_bin(y, obj + V(0.0, -0.059, 0.0), obj), 0);
  // Saturated at both ends, and -1 for a non-finite offset.
  EXPECT_EQ(Discretizer::context_bin(x, obj + V(5.0, 0.0, 0.0), obj), 2);
  EXPECT_EQ(Discretizer::context_bin(y, obj + V(0.0, -5.0, 0.0), obj), 0);
  EXPECT_EQ(Discretizer::context_bin(x, V(NAN, 0, 0), obj), -1);
  EXPECT_STREQ(a2l::variable_kind_name(VariableKind::offset_y), "offset_y");
  VariableKind k = VariableKind::effect;
  ASSERT_TRUE(a2l::parse_variable_kind("offset_x", k));
  EXPECT_EQ(k, VariableKind::offset_x);
  // An offset needs a range, like a distance.
  Discretizer disc;
  const a2l::Result r = Discretizer::create({variable(VariableKind::offset_x, 3, 0.1, 0.1)}, disc);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message.find("low/high"), std::string::npos) << r.message;
}

TEST(ContextBin, DiscretizeUsesContextBin) {
  Variable edges = variable(VariableKind::distance, 4, 0.02, 0.3);
  edges.edges = {0.05, 0.1, 0.2};
  for (const Variable& distance : {variable(VariableKind::distance, 5, 0.02, 0.3), edges}) {
    std::vector<Variable> vars = {distance, variable(VariableKind::orientation, 12),
                                  variable(VariableKind::inclination, 6),
                                  variable(VariableKind::offset_x, 3, -0.12, 0.12),
                                  variable(VariableKind::offset_y, 5, -0.2, 0.2)};
    Discretizer disc;
    ASSERT_TRUE(Discretizer::create(vars, disc).ok());
    std::mt19937_64 rng(5);
    int bins[a2l::kMaxVariables];
    for (int k = 0; k < 20000; ++k) {
      a2l::Context c;
      c.eef = V(coordinate(rng), coordinate(rng), coordinate(rng));
      c.object = V(coordinate(rng), coordinate(rng), coordinate(rng));
      const a2l::Status s = disc.discretize(c, bins);
      bool unknown = false;
      for (int j = 0; j < static_cast<int>(vars.size()); ++j) {
        const int b = Discretizer::context_bin(vars[static_cast<size_t>(j)], c.eef, c.object);
        ASSERT_EQ(bins[j], b) << k << " " << j;
        unknown = unknown || b < 0;
      }
      EXPECT_EQ(s == a2l::Status::unknown_context, unknown);
    }
  }
}

TEST(BinsNoAlloc, ContextBinAndClassifyEffectAllocateNothingThrowNothing) {
  Variable edges = variable(VariableKind::distance, 4, 0.05, 0.20);
  edges.edges = {0.07, 0.10, 0.15};  // explicit edges (filled before the guarded section)
  const Variable vars[6] = {variable(VariableKind::distance, 3, 0.05, 0.20),
                            variable(VariableKind::orientation, 16),
                            variable(VariableKind::inclination, 8),
                            variable(VariableKind::offset_x, 3, -0.135, 0.135),
                            variable(VariableKind::offset_y, 3, -0.1575, 0.1575),
                            edges};
  std::mt19937_64 rng(11);
  const int n = 100000;
  std::vector<V> eef(static_cast<size_t>(n)), obj(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    eef[static_cast<size_t>(k)] = V(coordinate(rng), coordinate(rng), coordinate(rng));
    obj[static_cast<size_t>(k)] = V(coordinate(rng), coordinate(rng), coordinate(rng));
  }
  long known = 0, unknown = 0, effects = 0, wrong = 0;
  bool threw = false;
  std::size_t allocations = 0;
  {
    a2l::test::AllocationGuard guard;
    try {
      for (int k = 0; k < n; ++k) {
        const V& e = eef[static_cast<size_t>(k)];
        const V& o = obj[static_cast<size_t>(k)];
        for (const Variable& v : vars) {
          const int b = Discretizer::context_bin(v, e, o);
          if (b < -1 || b >= v.n_bins) ++wrong;
          ++(b < 0 ? unknown : known);
        }
        const int c = a2l::classify_effect(e - o, 8);
        if (c < -1 || c >= 8) ++wrong;
        effects += c >= 0;
      }
    } catch (...) {
      threw = true;
    }
    allocations = guard.allocations();
  }
  EXPECT_FALSE(threw);
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(known, 10000);
  EXPECT_GT(unknown, 10000);
  EXPECT_GT(effects, 10000);
}

}  // namespace test_bins_noalloc
