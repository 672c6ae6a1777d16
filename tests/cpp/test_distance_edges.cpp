// Distance bins between explicit edges (Variable::edges, the manifest's "edges"): the bin is
// the number of edges <= d, NaN an unknown context; Discretizer::create and the bundle loader
// refuse edges that are not finite, not > 0 or not increasing, a count that does not give
// n_bins, edges on another kind; the skill's fallback limits and approach targets follow the
// edges (first_bin_edge, range_upper_end, bin_centre), and equal bins keep their formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "a2l/bundle.hpp"
#include "a2l/discretizer.hpp"
#include "a2l/skill.hpp"
#include "bundle_builder.hpp"

namespace test_distance_edges {

using a2l::Discretizer;
using a2l::Status;
using a2l::Variable;
using a2l::VariableKind;
using a2l::testing::json;
using V = Eigen::Vector3d;

Variable distance(std::vector<double> edges, double low = 0.05, double high = 0.20) {
  Variable v;
  v.name = "distance";
  v.kind = VariableKind::distance;
  v.n_bins = static_cast<int>(edges.size()) + 1;
  v.low = low;
  v.high = high;
  v.edges = std::move(edges);
  return v;
}

// The context bin of a point at distance d from the object, along a slanted direction.
int bin_at(const Variable& v, double d) {
  const V obj(0.7, -0.1, 0.04);
  return Discretizer::context_bin(v, obj + d * V(2.0, -1.0, 2.0) / 3.0, obj);
}

TEST(DistanceEdges, TheBinIsTheNumberOfEdgesAtOrBelowTheDistance) {
  const Variable v = distance({0.07, 0.10, 0.15});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double* e = v.edges.data();
  // below the first edge, on each edge (the bin above it), between, at and above the last
  const std::vector<std::pair<double, int>> cases = {
      {0.0, 0},    {0.03, 0}, {std::nextafter(0.07, 0.0), 0},
      {0.07, 1},   {0.09, 1}, {0.10, 2},
      {0.1499, 2}, {0.15, 3}, {0.40, 3},
      {1e300, 3}};
  for (const auto& [d, b] : cases) {
    EXPECT_EQ(Discretizer::edges_bin(d, e, 3), b) << d;
  }
  EXPECT_EQ(Discretizer::edges_bin(nan, e, 3), -1);
  EXPECT_EQ(Discretizer::edges_bin(inf, e, 3), -1);
  EXPECT_EQ(Discretizer::edges_bin(-inf, e, 3), -1);
  // One edge: two bins.
  const double one = 0.1;
  EXPECT_EQ(Discretizer::edges_bin(0.0999, &one, 1), 0);
  EXPECT_EQ(Discretizer::edges_bin(0.1, &one, 1), 1);
  // Through context_bin (the step's and context_bins' path): away from the edges (a point
  // computed at d lands within rounding of d), the object at the eef, unknown contexts.
  for (const auto& [d, b] :
       std::vector<std::pair<double, int>>{{0.03, 0}, {0.085, 1}, {0.12, 2}, {0.16, 3}, {5.0, 3}}) {
    EXPECT_EQ(bin_at(v, d), b) << d;
  }
  const V p(0.7, -0.1, 0.04);
  EXPECT_EQ(Discretizer::context_bin(v, p, p), 0);
  EXPECT_EQ(Discretizer::context_bin(v, V(nan, 0, 0), V::Zero()), -1);
  EXPECT_EQ(Discretizer::context_bin(v, V::Zero(), V(0, inf, 0)), -1);
  const double big = std::numeric_limits<double>::max();
  EXPECT_EQ(Discretizer::context_bin(v, V(big, 0, 0), V(-big, 0, 0)), -1);
  // Exactly on an edge along an axis (d = |rx| exactly): the bin above it.
  EXPECT_EQ(Discretizer::context_bin(v, V(0.10, 0, 0), V::Zero()), 2);
  EXPECT_EQ(Discretizer::context_bin(v, V(0, -0.15, 0), V::Zero()), 3);
  // discretize() agrees.
  Discretizer disc;
  ASSERT_TRUE(Discretizer::create({v}, disc).ok());
  a2l::Context c;
  c.eef = V(0.0, 0.0, 0.08);
  int bins[a2l::kMaxVariables];
  EXPECT_EQ(disc.discretize(c, bins), Status::ok);
  EXPECT_EQ(bins[0], 1);
  c.eef = V(nan, 0.0, 0.0);
  EXPECT_EQ(disc.discretize(c, bins), Status::unknown_context);
  EXPECT_EQ(bins[0], -1);
}

TEST(DistanceEdges, CreateRefusesBadEdgesNamingTheVariable) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    Variable v;
    std::string needle;
  };
  Variable mismatch = distance({0.07, 0.10});
  mismatch.n_bins = 4;
  Variable offset = distance({0.07});
  offset.kind = VariableKind::offset_x;
  offset.name = "offset_x";
  const std::vector<Case> cases = {
      {distance({0.07, nan}), "('distance').edges[1]"},
      {distance({inf}), "('distance').edges[0]"},
      {distance({0.0, 0.1}), "('distance').edges[0]"},
      {distance({-0.05, 0.1}), "('distance').edges[0]"},
      {distance({0.10, 0.07}), "('distance').edges[1]"},
      {distance({0.07, 0.07}), "('distance').edges[1]"},
      {mismatch, "('distance').n_bins: 4, but 2 edges make 3 bins"},
      {offset, "('offset_x').edges: only a distance variable may have edges"},
  };
  for (const Case& c : cases) {
    Discretizer disc;
    const a2l::Result r = Discretizer::create({c.v}, disc);
    EXPECT_EQ(r.status, Status::invalid_argument) << c.needle;
    EXPECT_NE(r.message.find("variables[0] " + c.needle), std::string::npos) << r.message;
  }
  Discretizer disc;
  EXPECT_TRUE(Discretizer::create({distance({0.07, 0.10, 0.15})}, disc).ok());
  EXPECT_EQ(disc.variable(0).n_bins, 4);
}

TEST(DistanceEdges, FallbackLimitsAndBinCentresFollowTheEdges) {
  const Variable e = distance({0.07, 0.10, 0.15});
  EXPECT_EQ(a2l::first_bin_edge(e), 0.07);
  EXPECT_EQ(a2l::range_upper_end(e), 0.15);
  EXPECT_DOUBLE_EQ(a2l::bin_centre(e, 0), 0.035);  // [0, 0.07]
  EXPECT_DOUBLE_EQ(a2l::bin_centre(e, 1), 0.085);  // [0.07, 0.10]
  EXPECT_DOUBLE_EQ(a2l::bin_centre(e, 2), 0.125);  // [0.10, 0.15]
  EXPECT_DOUBLE_EQ(a2l::bin_centre(e, 3), 0.175);  // [0.15, 0.20]: as wide as the one before
  EXPECT_DOUBLE_EQ(a2l::bin_centre(distance({0.1}), 1), 0.15);  // one edge: [0.1, 0.2]
  // Equal bins: the formulas the skill used before edges, bit for bit.
  Variable q;
  q.kind = VariableKind::distance;
  q.n_bins = 3;
  q.low = 0.05;
  q.high = 0.20;
  EXPECT_EQ(a2l::first_bin_edge(q), q.low + (q.high - q.low) / q.n_bins);
  EXPECT_EQ(a2l::range_upper_end(q), 0.20);
  for (int b = 0; b < 3; ++b) {
    const double w = (q.high - q.low) / q.n_bins;
    EXPECT_EQ(a2l::bin_centre(q, b), q.low + (b + 0.5) * w);
  }
}

// sample_parts' distance (3 bins) with the edges 0.07 and 0.10.
a2l::testing::BundleParts parts_with_edges() {
  auto p = a2l::testing::sample_parts(9, 0.6);
  p.manifest["variables"][1]["edges"] = {0.07, 0.10};
  return p;
}

a2l::Result load(const a2l::testing::BundleParts& p, a2l::Skill& s) {
  const auto b = a2l::testing::build(p);
  return a2l::load_bundle_from_memory(b.data(), b.size(), s, "edges.a2lb");
}

TEST(DistanceEdges, ABundleWithEdgesLoadsAndItsSkillUsesThem) {
  auto p = parts_with_edges();
  p.manifest["execution"]["fallback"] = "nearest";
  a2l::Skill skill;
  const a2l::Result r = load(p, skill);
  ASSERT_TRUE(r.ok()) << r.message;
  const Variable& v = skill.discretizer().variable(1);
  EXPECT_EQ(v.edges, (std::vector<double>{0.07, 0.10}));
  EXPECT_DOUBLE_EQ(v.low, 0.05);  // read, but not used by the bins
  EXPECT_EQ(skill.fallback_near(), 0.07);
  EXPECT_EQ(skill.fallback_reach(), 0.10);
  a2l::Context c;
  c.object = V(0.7, 0.0, 0.04);
  int bins[a2l::kMaxVariables];
  for (const auto& [d, b] : std::vector<std::pair<double, int>>{{0.06, 0}, {0.08, 1}, {0.3, 2}}) {
    c.eef = c.object + V(0.0, d, 0.0);
    ASSERT_EQ(skill.discretizer().discretize(c, bins), Status::ok);
    EXPECT_EQ(bins[1], b) << d;
  }
  // Without the key: equal bins over [0.05, 0.20], as before.
  a2l::Skill plain;
  ASSERT_TRUE(load(a2l::testing::sample_parts(9, 0.6), plain).ok());
  EXPECT_TRUE(plain.discretizer().variable(1).edges.empty());
  c.eef = c.object + V(0.0, 0.08, 0.0);
  ASSERT_EQ(plain.discretizer().discretize(c, bins), Status::ok);
  EXPECT_EQ(bins[1], 0);
  EXPECT_DOUBLE_EQ(plain.fallback_near(), 0.10);
  EXPECT_DOUBLE_EQ(plain.fallback_reach(), 0.20);
}

TEST(DistanceEdges, TheLoaderRefusesMalformedEdges) {
  struct Case {
    json edges;
    int variable;
    std::string needle;
  };
  const std::vector<Case> cases = {
      {"0.07", 1, "variables[1].edges: must be an array of numbers, got string"},
      {0.07, 1, "variables[1].edges: must be an array of numbers, got number"},
      {json::object(), 1, "variables[1].edges: must be an array"},
      {json::array(), 1, "variables[1].edges: needs 1 to 1023 edges, got 0"},
      {{0.07, "0.1"}, 1, "variables[1].edges[1]: must be a number, got string"},
      {{0.07, nullptr}, 1, "variables[1].edges[1]: must be a number, got null"},  // a NaN
      {{0.10, 0.07}, 1, "variables[1].edges[1]: 0.07 is not above edges[0] = 0.1"},
      {{0.07, 0.07}, 1, "variables[1].edges[1]: 0.07 is not above edges[0]"},
      {{0.0, 0.07}, 1, "variables[1].edges[0]: 0 (must be finite and > 0)"},
      {{-0.1, 0.07}, 1, "variables[1].edges[0]: -0.1 (must be finite and > 0)"},
      {{0.07}, 1, "variables[1].n_bins: 3, but 1 edges make 2 bins ('distance')"},
      {{0.07, 0.1, 0.15}, 1, "variables[1].n_bins: 3, but 3 edges make 4 bins"},
      {{1.0, 2.0},
       2,
       "variables[2].edges: 'orientation' is of kind orientation, only a "
       "distance variable may have edges"},
      {{1.0}, 0, "variables[0].edges: 'effect' is of kind effect"},
  };
  for (const Case& c : cases) {
    auto p = a2l::testing::sample_parts(9, 0.6);
    p.manifest["variables"][static_cast<std::size_t>(c.variable)]["edges"] = c.edges;
    a2l::Skill s;
    const a2l::Result r = load(p, s);
    EXPECT_EQ(r.status, Status::parse_error) << c.needle;
    EXPECT_NE(r.message.find(c.needle), std::string::npos)
        << "message '" << r.message << "' does not name '" << c.needle << "'";
    EXPECT_NE(r.message.find("edges.a2lb"), std::string::npos) << r.message;
  }
}

}  // namespace test_distance_edges
