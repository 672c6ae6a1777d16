// The nearest-cell fallback (execution.fallback = "nearest"): a context cell with no data
// (a uniform row) gets the movement of the nearest informative cell with the same effect and
// high-level values, compiled when the bundle is loaded, and the trace marks it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <random>

#include "a2l/bundle.hpp"
#include "a2l/skill.hpp"
#include "bundle_builder.hpp"

namespace test_skill_fallback {

using a2l::Status;
using a2l::testing::build;
using a2l::testing::BundleParts;
using a2l::testing::sample_parts;

a2l::Skill load(const BundleParts& p) { return a2l::testing::load_skill(p); }

BundleParts with_fallback(BundleParts p, const char* rule = "nearest") {
  p.manifest["execution"]["fallback"] = rule;
  return p;
}

// Bins of row r of a C-order table of `shape`.
std::vector<int> bins_of(std::size_t r, const std::vector<std::int64_t>& shape) {
  std::vector<int> b(shape.size());
  for (int i = static_cast<int>(shape.size()) - 1; i >= 0; --i) {
    b[static_cast<size_t>(i)] = static_cast<int>(r % static_cast<std::size_t>(shape[i]));
    r /= static_cast<std::size_t>(shape[i]);
  }
  return b;
}

// The context of the cell `bins` of sample_parts' variables (effect, distance(3, 0.05-0.20),
// orientation(8), inclination(4), light): its centre.
a2l::Context context_of(const std::vector<int>& b) {
  constexpr double kPi = 3.14159265358979323846;
  a2l::Context c;
  c.object = {0.7, 0.0, 0.04};
  const double d = 0.075 + 0.05 * b[1];
  const double yaw = -kPi + 2 * kPi / 8 * b[2];
  const double incl = kPi / 4 * (b[3] + 0.5);
  c.eef = c.object + d * Eigen::Vector3d(std::sin(incl) * std::cos(yaw),
                                         std::sin(incl) * std::sin(yaw), std::cos(incl));
  c.effect = b[0];
  c.high_level[4] = b[4];
  return c;
}

// The movement a fallback step without smoothing takes from row `f` at context `c`: the most
// probable (lowest index on a tie) of those that end between min(|r|, near) and max(|r|,
// reach) from the object, or the row's argmax if none does.
int expected_fallback_move(const a2l::Skill& skill, std::size_t f, const a2l::Context& c) {
  const Eigen::Vector3d r = c.eef - c.object;
  const double limit = std::max(r.norm(), skill.fallback_reach());
  const double near = std::min(r.norm(), skill.fallback_near());
  const double* p = skill.table().posterior_row(f);
  int best = -1;
  for (int m = 0; m < skill.n_moves(); ++m) {
    const double d = (r + skill.movements().displacement(m)).norm();
    if (d > limit + 1e-12 || d < near - 1e-12) continue;
    if (best < 0 || p[m] > p[best]) best = m;
  }
  return best < 0 ? skill.table().argmax(f) : best;
}

TEST(Fallback, EveryUniformRowGetsTheNearestInformativeRowOfItsEffectAndStates) {
  const BundleParts p = sample_parts(9, 0.6);
  const a2l::Skill skill = load(with_fallback(p));
  const std::size_t rows = skill.table().n_rows();
  int uniform = 0;
  for (std::size_t r = 0; r < rows; ++r) {
    const std::int32_t f = skill.fallback_row(r);
    if (p.argmax[r] >= 0) {
      EXPECT_EQ(f, static_cast<std::int32_t>(r));
      continue;
    }
    ++uniform;
    // Brute force: the distance to every informative row of the same effect and light.
    const auto a = bins_of(r, p.shape);
    int best = -1;
    std::size_t best_row = 0;
    for (std::size_t q = 0; q < rows; ++q) {
      const auto b = bins_of(q, p.shape);
      if (p.argmax[q] < 0 || a[0] != b[0] || a[4] != b[4]) continue;
      const int dor = std::abs(a[2] - b[2]);
      const int d = std::abs(a[1] - b[1]) + std::min(dor, 8 - dor) + std::abs(a[3] - b[3]);
      if (best < 0 || d < best) best = d, best_row = q;
    }
    ASSERT_GE(best, 1) << "sample_parts(9, 0.6) has informative rows for every effect";
    EXPECT_EQ(f, static_cast<std::int32_t>(best_row)) << "row " << r;
  }
  EXPECT_GT(uniform, 100);
}

TEST(Fallback, AnUnseenCellGetsTheFallbackMovementAndTheTraceMarksIt) {
  const BundleParts p = sample_parts(9, 0.6);
  const a2l::Skill plain = load(p);
  const a2l::Skill skill = load(with_fallback(p));
  EXPECT_EQ(plain.settings().fallback, a2l::Fallback::none);
  EXPECT_EQ(skill.settings().fallback, a2l::Fallback::nearest);
  a2l::SkillState state(skill), plain_state(plain);
  int checked = 0;
  for (std::size_t r = 0; r < skill.table().n_rows(); ++r) {
    const a2l::Context c = context_of(bins_of(r, p.shape));
    int bins[a2l::kMaxVariables];
    ASSERT_EQ(skill.discretizer().discretize(c, bins), Status::ok);
    ASSERT_EQ(skill.table().row_index(bins), r);
    state.reset();
    plain_state.reset();
    a2l::StepOutput out, plain_out;
    ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
    const Status ps = a2l::step(plain, plain_state, c, plain_out);
    if (p.argmax[r] >= 0) {
      EXPECT_EQ(ps, Status::ok);
      EXPECT_EQ(out.movement, plain_out.movement);
      EXPECT_FALSE(out.record.fallback);
      continue;
    }
    // The cell has no data: without the fallback the step stops, with it the step takes
    // the fallback row's movement (the most probable one within reach), and the trace says so.
    EXPECT_EQ(ps, Status::unknown_context);
    const auto f = static_cast<std::size_t>(skill.fallback_row(r));
    EXPECT_EQ(out.movement, expected_fallback_move(skill, f, c));
    EXPECT_EQ(out.probability, skill.table().posterior_row(f)[out.movement]);
    EXPECT_TRUE(out.record.fallback);
    const a2l::TraceRecord& last = state.trace(state.trace_size() - 1);
    EXPECT_TRUE(last.fallback);
    EXPECT_EQ(last.movement, out.movement);
    EXPECT_EQ(last.bins[2], bins[2]);  // the trace keeps the cell observed, not the fallback's
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(Fallback, AFallbackStepKeepsTheEndEffectorOutOfTheFirstBinAndWithinTheRange) {
  // Beyond the last (saturated) distance bin the cell no longer changes as the end-effector
  // moves outward: an outward fallback movement would repeat until the arm's reach ends.
  const BundleParts p = sample_parts(9, 0.6);
  const a2l::Skill skill = load(with_fallback(p));
  EXPECT_DOUBLE_EQ(skill.fallback_reach(), 0.20);  // the distance variable's upper end
  a2l::SkillState state(skill);
  int outward_argmax = 0, checked = 0;
  for (std::size_t r = 0; r < skill.table().n_rows(); ++r) {
    if (p.argmax[r] >= 0) continue;
    auto b = bins_of(r, p.shape);
    if (b[1] != 2) continue;  // the saturated bin, here 0.1 m past its upper end
    for (const double d : {0.20, 0.30}) {
      a2l::Context c = context_of(b);
      c.eef = c.object + (c.eef - c.object).normalized() * d;
      const auto f = static_cast<std::size_t>(skill.fallback_row(r));
      const Eigen::Vector3d rel = c.eef - c.object;
      outward_argmax +=
          (rel + skill.movements().displacement(skill.table().argmax(f))).norm() > d ? 1 : 0;
      state.reset();
      a2l::StepOutput out;
      ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
      ASSERT_TRUE(out.record.fallback);
      EXPECT_LE((rel + out.displacement).norm(), d + 1e-12) << "row " << r << " at " << d;
      EXPECT_EQ(out.movement, expected_fallback_move(skill, f, c));
      ++checked;
    }
  }
  EXPECT_GT(checked, 40);
  EXPECT_GT(outward_argmax, 10) << "the fallback rows' own movements point outward often";
  // Nor nearer than min(its distance, the first bin's upper edge, 0.10 m): a movement
  // borrowed from another cell does not push the object.
  EXPECT_DOUBLE_EQ(skill.fallback_near(), 0.10);
  int inward_argmax = 0;
  for (std::size_t r = 0; r < skill.table().n_rows(); ++r) {
    if (p.argmax[r] >= 0) continue;
    const auto b = bins_of(r, p.shape);
    if (b[1] == 2) continue;
    for (const double d : {0.07, 0.12}) {
      a2l::Context c = context_of(b);
      c.eef = c.object + (c.eef - c.object).normalized() * d;
      int bins[a2l::kMaxVariables];
      ASSERT_EQ(skill.discretizer().discretize(c, bins), Status::ok);
      const std::size_t cell = skill.table().row_index(bins);
      if (p.argmax[cell] >= 0) continue;  // moved into a cell with data
      const auto f = static_cast<std::size_t>(skill.fallback_row(cell));
      const Eigen::Vector3d rel = c.eef - c.object;
      inward_argmax +=
          (rel + skill.movements().displacement(skill.table().argmax(f))).norm() < std::min(d, 0.10)
              ? 1
              : 0;
      state.reset();
      a2l::StepOutput out;
      ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
      ASSERT_TRUE(out.record.fallback);
      EXPECT_GE((rel + out.displacement).norm(), std::min(d, 0.10) - 1e-12) << "row " << r;
      EXPECT_EQ(out.movement, expected_fallback_move(skill, f, c));
    }
  }
  EXPECT_GT(inward_argmax, 10) << "the fallback rows' own movements point inward often";
  // A cell with data is never restricted: its movement is its row's argmax wherever it is.
  for (std::size_t r = 0; r < skill.table().n_rows(); ++r) {
    auto b = bins_of(r, p.shape);
    if (p.argmax[r] < 0 || b[1] != 2) continue;
    a2l::Context c = context_of(b);
    c.eef = c.object + (c.eef - c.object).normalized() * 0.30;
    state.reset();
    a2l::StepOutput out;
    ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
    EXPECT_FALSE(out.record.fallback);
    EXPECT_EQ(out.movement, p.argmax[r]);
  }
}

TEST(Fallback, NoInformativeCellOfTheEffectIsStillAnUnknownContext) {
  BundleParts p = sample_parts(9, 0.3);
  // Effect 2 has no data at all: every one of its rows uniform.
  for (std::size_t r = 0; r < p.argmax.size(); ++r) {
    if (bins_of(r, p.shape)[0] != 2) continue;
    p.argmax[r] = -1;
    for (int m = 0; m < p.n_moves; ++m) p.posterior[r * 8 + static_cast<size_t>(m)] = 1.0 / 8;
  }
  const a2l::Skill skill = load(with_fallback(p));
  a2l::SkillState state(skill);
  a2l::StepOutput out;
  a2l::Context c = context_of({2, 1, 3, 2, 0});
  EXPECT_EQ(a2l::step(skill, state, c, out), Status::unknown_context);
  EXPECT_EQ(out.movement, -1);
  EXPECT_FALSE(out.record.fallback);
  c.effect = 1;  // another effect, with data: never borrowed across effects
  EXPECT_EQ(a2l::step(skill, state, c, out), Status::ok);
}

TEST(Fallback, SmoothingAppliesToTheFallbackRow) {
  const BundleParts p = sample_parts(9, 0.6, true);
  const a2l::Skill skill = load(with_fallback(p));
  a2l::SkillState state(skill);
  int fallbacks = 0;
  for (std::size_t r = 0; r < skill.table().n_rows(); ++r) {
    if (p.argmax[r] >= 0) continue;
    state.reset();
    a2l::StepOutput out;
    ASSERT_EQ(a2l::step(skill, state, context_of(bins_of(r, p.shape)), out), Status::ok);
    EXPECT_TRUE(out.record.fallback);
    ++fallbacks;
    // With smoothing too, a fallback step beyond the distance range never goes farther out.
    auto b = bins_of(r, p.shape);
    if (b[1] != 2) continue;
    a2l::Context c = context_of(b);
    c.eef = c.object + (c.eef - c.object).normalized() * 0.30;
    state.reset();
    ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
    EXPECT_TRUE(out.record.fallback);
    EXPECT_LE((c.eef - c.object + out.displacement).norm(), 0.30 + 1e-12) << "row " << r;
  }
  EXPECT_GT(fallbacks, 100);
}

// sample_parts without its inclination variable: distance and orientation are the only
// geometric variables, as in the push skills (effect, distance(3), orientation(8), light).
BundleParts planar_parts(std::uint64_t seed, double uniform_share) {
  BundleParts p = sample_parts(seed, uniform_share);
  auto& vars = p.manifest["variables"];
  vars.erase(3);
  const std::vector<std::int64_t> full = p.shape;
  p.shape = {4, 3, 8, 2};
  std::vector<double> post;
  std::vector<std::int32_t> am;
  for (std::size_t r = 0; r < p.argmax.size(); ++r) {
    if (bins_of(r, full)[3] != 1) continue;  // keep one inclination bin's rows
    am.push_back(p.argmax[r]);
    post.insert(post.end(), p.posterior.begin() + static_cast<std::ptrdiff_t>(r * 8),
                p.posterior.begin() + static_cast<std::ptrdiff_t>(r * 8 + 8));
  }
  p.argmax = am;
  p.posterior = post;
  return p;
}

// The planar centre of cell `b` of planar_parts (eef - object), and a context there.
Eigen::Vector2d planar_centre(const std::vector<int>& b) {
  constexpr double kPi = 3.14159265358979323846;
  const double d = 0.075 + 0.05 * b[1];
  const double yaw = -kPi + 2 * kPi / 8 * b[2];
  return {d * std::cos(yaw), d * std::sin(yaw)};
}

a2l::Context planar_context(const std::vector<int>& b) {
  a2l::Context c;
  c.object = {0.7, 0.0, 0.04};
  const Eigen::Vector2d x = planar_centre(b);
  c.eef = c.object + Eigen::Vector3d(x.x(), x.y(), 0.0);
  c.effect = b[0];
  c.high_level[3] = b[3];
  return c;
}

TEST(Fallback, ApproachHeadsForTheCentreOfTheNearestCellWithData) {
  const BundleParts p = planar_parts(9, 0.6);
  const a2l::Skill nearest = load(with_fallback(p));
  const a2l::Skill skill = load(with_fallback(p, "approach"));
  EXPECT_EQ(skill.settings().fallback, a2l::Fallback::approach);
  EXPECT_STREQ(a2l::fallback_name(skill.settings().fallback), "approach");
  a2l::SkillState state(skill);
  int checked = 0, other_than_nearest = 0;
  for (std::size_t r = 0; r < skill.table().n_rows(); ++r) {
    // The same fallback rows as `nearest`.
    ASSERT_EQ(skill.fallback_row(r), nearest.fallback_row(r)) << "row " << r;
    double tx = 0.0, ty = 0.0;
    const bool has = skill.fallback_target(r, tx, ty);
    if (p.argmax[r] >= 0 || skill.fallback_row(r) < 0) {
      EXPECT_FALSE(has) << "row " << r;
      continue;
    }
    ASSERT_TRUE(has);
    const auto f = static_cast<std::size_t>(skill.fallback_row(r));
    const Eigen::Vector2d t = planar_centre(bins_of(f, p.shape));
    EXPECT_NEAR(tx, t.x(), 1e-12);
    EXPECT_NEAR(ty, t.y(), 1e-12);
    const a2l::Context c = planar_context(bins_of(r, p.shape));
    state.reset();
    a2l::StepOutput out;
    ASSERT_EQ(a2l::step(skill, state, c, out), Status::ok);
    EXPECT_TRUE(out.record.fallback);
    // The movement within the limits that ends nearest the target.
    const Eigen::Vector3d rel = c.eef - c.object;
    const double limit = std::max(rel.norm(), skill.fallback_reach());
    const double near = std::min(rel.norm(), skill.fallback_near());
    int best = -1;
    double best_d = 0.0;
    for (int m = 0; m < skill.n_moves(); ++m) {
      const Eigen::Vector3d e = rel + skill.movements().displacement(m);
      if (e.norm() > limit + 1e-12 || e.norm() < near - 1e-12) continue;
      const double d = (e.head<2>() - t).norm();
      if (best < 0 || d < best_d - 1e-12) {
        best = m;
        best_d = d;
      }
    }
    ASSERT_GE(best, 0);
    // the step's movement is allowed and ends as near the target as the nearest (a tie
    // may go either way by rounding)
    const Eigen::Vector3d e = rel + out.displacement;
    EXPECT_LE(e.norm(), limit + 1e-12) << "row " << r;
    EXPECT_GE(e.norm(), near - 1e-12) << "row " << r;
    EXPECT_LE((e.head<2>() - t).norm(), best_d + 1e-9) << "row " << r;
    a2l::SkillState ns(nearest);
    a2l::StepOutput nout;
    ASSERT_EQ(a2l::step(nearest, ns, c, nout), Status::ok);
    other_than_nearest += nout.movement != out.movement ? 1 : 0;
    ++checked;
  }
  EXPECT_GT(checked, 40);
  EXPECT_GT(other_than_nearest, 10) << "heading for the cell differs from copying its movement";
}

TEST(Fallback, ApproachWithoutAPlanarContextIsNearest) {
  // With an inclination variable the cell's centre is not a planar point: `approach` keeps
  // `nearest`'s answer.
  const BundleParts p = sample_parts(9, 0.6);
  const a2l::Skill nearest = load(with_fallback(p));
  const a2l::Skill skill = load(with_fallback(p, "approach"));
  a2l::SkillState s1(nearest), s2(skill);
  int checked = 0;
  for (std::size_t r = 0; r < skill.table().n_rows(); ++r) {
    double tx = 0.0, ty = 0.0;
    EXPECT_FALSE(skill.fallback_target(r, tx, ty));
    if (p.argmax[r] >= 0) continue;
    const a2l::Context c = context_of(bins_of(r, p.shape));
    s1.reset();
    s2.reset();
    a2l::StepOutput o1, o2;
    ASSERT_EQ(a2l::step(nearest, s1, c, o1), Status::ok);
    ASSERT_EQ(a2l::step(skill, s2, c, o2), Status::ok);
    EXPECT_EQ(o1.movement, o2.movement);
    EXPECT_TRUE(o2.record.fallback);
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(Fallback, WithApproachNoStepUndoesThePreviousMovement) {
  // A step is a function of the context: a movement undone brings the end-effector back to
  // the context it left, and the run repeats the pair until the step cap. With `approach`
  // a cell with data whose movement undoes the previous one takes its next most probable.
  const BundleParts p = planar_parts(9, 0.3);
  const a2l::Skill nearest = load(with_fallback(p));
  const a2l::Skill skill = load(with_fallback(p, "approach"));
  int checked = 0;
  for (std::size_t r = 0; r < skill.table().n_rows(); ++r) {
    if (p.argmax[r] < 0) continue;
    const a2l::Context a = planar_context(bins_of(r, p.shape));
    a2l::SkillState s(skill), n(nearest);
    a2l::StepOutput o1, o2, n1, n2;
    ASSERT_EQ(a2l::step(skill, s, a, o1), Status::ok);
    ASSERT_EQ(a2l::step(nearest, n, a, n1), Status::ok);
    ASSERT_EQ(o1.movement, n1.movement);  // no previous movement: the same answer
    a2l::Context b = a;
    b.eef += o1.displacement;
    int bins[a2l::kMaxVariables];
    if (skill.discretizer().discretize(b, bins) != Status::ok) continue;
    const std::size_t cell = skill.table().row_index(bins);
    const int am = skill.table().argmax(cell);
    if (am < 0) continue;
    const Eigen::Vector3d back = skill.movements().displacement(am) + o1.displacement;
    if (back.norm() > 1e-9) continue;  // its movement does not undo the first
    ASSERT_EQ(a2l::step(nearest, n, b, n2), Status::ok);
    EXPECT_EQ(n2.movement, am) << "without the rule the pair repeats";
    ASSERT_EQ(a2l::step(skill, s, b, o2), Status::ok);
    const double* post = skill.table().posterior_row(cell);
    int want = -1;
    for (int m = 0; m < skill.n_moves(); ++m) {
      if (m == am) continue;
      if (want < 0 || post[m] > post[want]) want = m;
    }
    EXPECT_EQ(o2.movement, want) << "row " << cell;
    EXPECT_EQ(o2.probability, post[want]);
    EXPECT_FALSE(o2.record.fallback);
    ++checked;
  }
  EXPECT_GT(checked, 3);
}

TEST(Fallback, AnUnknownRuleIsAParseError) {
  const auto bytes = build(with_fallback(sample_parts(), "guess"));
  a2l::Skill s;
  const a2l::Result r = a2l::load_bundle_from_memory(bytes.data(), bytes.size(), s, "test");
  EXPECT_EQ(r.status, Status::parse_error);
  EXPECT_NE(r.message.find("execution.fallback"), std::string::npos) << r.message;
}

}  // namespace test_skill_fallback
