// Collision model and transit planner on a small planar arm: shapes from the URDF (a mesh as
// a convex hull), allowed pairs, a path around an obstacle checked densely, limits, and the
// statuses of impossible requests.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>

#include "a2l/collision_model.hpp"
#include "a2l/transit.hpp"

#if A2L_HAVE_BULLET && A2L_HAVE_OMPL
namespace test_transit {

// base (box) -> j1 (z) -> link1 (cylinder along x) -> j2 (z) -> link2 (mesh cube) -> tip
const char* kArm = R"(<?xml version="1.0"?>
<robot name="planar">
  <link name="base"><collision><origin xyz="0 0 0"/><geometry><box size="0.6 0.6 0.1"/></geometry></collision></link>
  <link name="link1"><collision><origin xyz="0.25 0 0.05" rpy="0 1.5707963 0"/><geometry><cylinder radius="0.03" length="0.4"/></geometry></collision></link>
  <link name="link2"><collision><origin xyz="0.2 0 0.05"/><geometry><mesh filename="cube.stl" scale="0.2 0.05 0.05"/></geometry></collision></link>
  <link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="link1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1.0" effort="1"/></joint>
  <joint name="j2" type="revolute"><parent link="link1"/><child link="link2"/><origin xyz="0.5 0 0"/><axis xyz="0 0 1"/><limit lower="-2.5" upper="2.5" velocity="2.0" effort="1"/></joint>
  <joint name="jt" type="fixed"><parent link="link2"/><child link="tip"/><origin xyz="0.4 0 0"/></joint>
</robot>)";

a2l::MeshVertices cube() {
  Eigen::Matrix<double, Eigen::Dynamic, 3> v(8, 3);
  int k = 0;
  for (double x : {-0.5, 0.5})
    for (double y : {-0.5, 0.5})
      for (double z : {-0.5, 0.5}) v.row(k++) << x, y, z;
  return {{"cube.stl", v}};
}

a2l::CollisionBox box(const std::string& name, Eigen::Vector3d c, Eigen::Vector3d h) {
  a2l::CollisionBox b;
  b.name = name;
  b.pose.translation() = c;
  b.half_extents = h;
  return b;
}

a2l::CollisionModel load() {
  a2l::CollisionModel m;
  const a2l::Result r = a2l::CollisionModel::load_from_string(kArm, "base", "tip", cube(), m);
  EXPECT_TRUE(r.ok()) << r.message;
  return m;
}

TEST(CollisionModel, LinksAndAllowedPairs) {
  a2l::CollisionModel m = load();
  ASSERT_TRUE(m.loaded());
  EXPECT_EQ(m.links(), (std::vector<std::string>{"base", "link1", "link2"}));
  EXPECT_EQ(m.moving_links(), (std::vector<std::string>{"link1", "link2"}));
  // adjacent pairs only: base-link2 are not adjacent
  EXPECT_EQ(m.allowed_pairs(),
            (std::vector<a2l::CollisionPair>{{"base", "link1"}, {"link1", "link2"}}));
}

TEST(CollisionModel, MissingMeshIsNamed) {
  a2l::CollisionModel m;
  const a2l::Result r = a2l::CollisionModel::load_from_string(kArm, "base", "tip", {}, m);
  EXPECT_EQ(r.status, a2l::Status::invalid_argument);
  EXPECT_NE(r.message.find("cube.stl"), std::string::npos);
  EXPECT_NE(r.message.find("link2"), std::string::npos);
}

TEST(CollisionModel, ObstaclesAndSelfCollision) {
  a2l::CollisionModel m = load();
  Eigen::Vector2d q(0.0, 0.0);
  EXPECT_FALSE(m.in_collision(q));
  // a post on the x axis at 0.7 m: the straight arm hits it with link2 (a hull: mesh)
  ASSERT_TRUE(m.set_obstacles({box("post", {0.75, 0, 0.05}, {0.03, 0.03, 0.2})}, 0.0).ok());
  EXPECT_TRUE(m.in_collision(q));
  const auto pairs = m.colliding_pairs(q);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0], (a2l::CollisionPair{"link2", "post"}));
  EXPECT_FALSE(m.in_collision(Eigen::Vector2d(1.0, 0.0)));
  // padding grows the box: 0.15 rad away the arm clears the post, with 10 cm padding it does not
  EXPECT_FALSE(m.in_collision(Eigen::Vector2d(0.15, 0.0)));
  ASSERT_TRUE(m.set_obstacles({box("post", {0.75, 0, 0.05}, {0.03, 0.03, 0.2})}, 0.1).ok());
  EXPECT_TRUE(m.in_collision(Eigen::Vector2d(0.15, 0.0)));
  // folding link2 back over the base is a self-collision (base-link2 is not adjacent)
  ASSERT_TRUE(m.set_obstacles({}, 0.0).ok());
  EXPECT_TRUE(m.in_collision(Eigen::Vector2d(0.0, 2.5)) ||
              m.in_collision(Eigen::Vector2d(0.0, -2.5)));
  // allow_collisions_at ignores the pairs found there from now on
  const Eigen::Vector2d folded = m.in_collision(Eigen::Vector2d(0.0, 2.5))
                                     ? Eigen::Vector2d(0.0, 2.5)
                                     : Eigen::Vector2d(0.0, -2.5);
  ASSERT_TRUE(m.allow_collisions_at(folded).ok());
  EXPECT_FALSE(m.in_collision(folded));
  EXPECT_FALSE(m.set_obstacles({box("bad", {0, 0, 0}, {0, 1, 1})}, 0.0).ok());
  EXPECT_FALSE(m.set_joint_positions({{"j1", 0.0}}).ok());  // a joint of the arm
  EXPECT_FALSE(m.set_joint_positions({{"nope", 0.0}}).ok());
}

TEST(CollisionModel, PairwiseChecksAgreeWithTheWorldPass) {
  // the same verdict and the same colliding pairs by both methods over a grid of the plane
  // around a post (obstacle contacts) and the base (self-collisions when link2 folds back)
  a2l::CollisionModel m = load();
  EXPECT_TRUE(m.pairwise());  // the default
  ASSERT_TRUE(m.set_obstacles({box("post", {0.75, 0, 0.05}, {0.03, 0.03, 0.2})}, 0.01).ok());
  int colliding = 0, free = 0;
  for (double q1 = -3.0; q1 <= 3.0; q1 += 0.05)
    for (double q2 = -2.5; q2 <= 2.5; q2 += 0.05) {
      const Eigen::Vector2d q(q1, q2);
      m.set_pairwise(false);
      const bool world = m.in_collision(q);
      const auto world_pairs = m.colliding_pairs(q);
      m.set_pairwise(true);
      ASSERT_EQ(m.in_collision(q), world) << q.transpose();
      ASSERT_EQ(m.colliding_pairs(q), world_pairs) << q.transpose();
      (world ? colliding : free) += 1;
    }
  EXPECT_GT(colliding, 100);  // the grid has both kinds
  EXPECT_GT(free, 100);
}

TEST(TransitPlanner, PathAroundObstacleIsCollisionFreeAndWithinLimits) {
  a2l::TransitPlanner planner(load());
  // a post the arm cannot sweep through: from j1 = -1 to j1 = +1 the arm must fold link2
  ASSERT_TRUE(
      planner.model().set_obstacles({box("post", {0.85, 0, 0.05}, {0.04, 0.04, 0.2})}, 0.01).ok());
  const Eigen::Vector2d q0(-1.0, 0.0), q1(1.0, 0.0);
  a2l::TransitOptions o;
  o.time_limit = 2.0;
  o.acceleration = 3.0;
  o.velocity_scale = 0.5;
  const a2l::TransitResult r = planner.plan(q0, q1, o);
  ASSERT_EQ(r.status, a2l::TransitStatus::ok) << r.message;
  EXPECT_LE(r.planning_time, o.time_limit + 0.1);
  EXPECT_TRUE(r.positions.row(0).transpose().isApprox(q0, 1e-12));
  EXPECT_TRUE(r.positions.bottomRows(1).transpose().isApprox(q1, 1e-12));
  const Eigen::Vector2d vmax(0.5, 1.0);  // URDF x 0.5
  for (Eigen::Index k = 0; k < r.positions.rows(); ++k) {
    EXPECT_LE(std::abs(r.velocities(k, 0)), vmax[0] + 1e-12);
    EXPECT_LE(std::abs(r.velocities(k, 1)), vmax[1] + 1e-12);
    EXPECT_LE(r.accelerations.row(k).cwiseAbs().maxCoeff(), 3.0 + 1e-12);
  }
  // dense check: 1 mrad between checked configurations, with the obstacle unpadded
  ASSERT_TRUE(
      planner.model().set_obstacles({box("post", {0.85, 0, 0.05}, {0.04, 0.04, 0.2})}, 0.0).ok());
  for (Eigen::Index k = 0; k + 1 < r.positions.rows(); ++k) {
    const Eigen::VectorXd a = r.positions.row(k), b = r.positions.row(k + 1);
    const int n = 1 + static_cast<int>((b - a).cwiseAbs().maxCoeff() / 1e-3);
    for (int i = 0; i <= n; ++i)
      ASSERT_FALSE(planner.model().in_collision(a + (b - a) * (double(i) / n))) << "sample " << k;
  }
}

TEST(TransitPlanner, CoarseSearchIsCheckedFinely) {
  // a thin post between start and goal, and a coarse resolution that steps over it (1.5 rad
  // between checks): the path returned still passes the fine check, here 1 mrad between
  // configurations with the post unpadded
  a2l::TransitPlanner planner(load());
  const a2l::CollisionBox post = box("post", {0.8, 0, 0.05}, {0.005, 0.005, 0.2});
  ASSERT_TRUE(planner.model().set_obstacles({post}, 0.01).ok());
  const Eigen::Vector2d q0(-0.6, 0.0), q1(0.6, 0.0);
  ASSERT_TRUE(planner.model().in_collision(Eigen::Vector2d(0.0, 0.0)));  // the straight line hits
  for (const double coarse : {0.0, 1.5}) {
    a2l::TransitOptions o;
    o.time_limit = 2.0;
    o.coarse_resolution = coarse;
    o.seed = 3;
    const a2l::TransitResult r = planner.plan(q0, q1, o);
    ASSERT_EQ(r.status, a2l::TransitStatus::ok) << r.message;
    ASSERT_TRUE(planner.model().set_obstacles({post}, 0.0).ok());
    for (Eigen::Index k = 0; k + 1 < r.waypoints.rows(); ++k) {
      const Eigen::VectorXd a = r.waypoints.row(k), b = r.waypoints.row(k + 1);
      const int n = 1 + static_cast<int>((b - a).cwiseAbs().maxCoeff() / 1e-3);
      for (int i = 0; i <= n; ++i)
        ASSERT_FALSE(planner.model().in_collision(a + (b - a) * (double(i) / n)))
            << "coarse " << coarse << " edge " << k;
    }
    ASSERT_TRUE(planner.model().set_obstacles({post}, 0.01).ok());
  }
  a2l::TransitOptions bad;
  bad.coarse_resolution = -1.0;
  EXPECT_EQ(planner.plan(q0, q1, bad).status, a2l::TransitStatus::invalid_argument);
}

TEST(TransitPlanner, ImpossibleRequestsHaveAClearStatus) {
  a2l::TransitPlanner planner(load());
  a2l::TransitOptions o;
  o.time_limit = 0.5;
  // goal in collision with a box: named at once
  ASSERT_TRUE(
      planner.model().set_obstacles({box("crate", {0.0, 0.75, 0.05}, {0.1, 0.1, 0.2})}, 0.0).ok());
  a2l::TransitResult r = planner.plan(Eigen::Vector2d(0, 0), Eigen::Vector2d(1.5707963, 0), o);
  EXPECT_EQ(r.status, a2l::TransitStatus::goal_in_collision);
  EXPECT_NE(r.message.find("crate"), std::string::npos);
  r = planner.plan(Eigen::Vector2d(0, 0), Eigen::Vector2d(9, 0), o);
  EXPECT_EQ(r.status, a2l::TransitStatus::goal_out_of_limits);
  r = planner.plan(Eigen::Vector2d(0, 0), Eigen::Vector3d(0, 0, 0), o);
  EXPECT_EQ(r.status, a2l::TransitStatus::invalid_argument);
  // a ring of walls around the base at 0.3 m: from j1 = 0 to j1 = pi / 2 there is no way
  // (the arm passes through the walls at every j1 but 0 and pi/2 through gaps)
  std::vector<a2l::CollisionBox> walls;
  for (int i = 0; i < 16; ++i) {
    const double a = i * M_PI / 8;
    if (i == 0 || i == 4) continue;  // gaps for the start and the goal
    a2l::CollisionBox b =
        box("wall", {0.3 * std::cos(a), 0.3 * std::sin(a), 0.05}, {0.03, 0.07, 0.2});
    b.pose.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    walls.push_back(b);
  }
  ASSERT_TRUE(planner.model().set_obstacles(walls, 0.0).ok());
  ASSERT_FALSE(planner.model().in_collision(Eigen::Vector2d(0, 0)));
  ASSERT_FALSE(planner.model().in_collision(Eigen::Vector2d(M_PI / 2, 0)));
  const auto t0 = std::chrono::steady_clock::now();
  r = planner.plan(Eigen::Vector2d(0, 0), Eigen::Vector2d(M_PI / 2, 0), o);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.status, a2l::TransitStatus::no_path) << r.message;
  EXPECT_LT(wall, o.time_limit + 0.5);
  EXPECT_STREQ(a2l::transit_status_name(r.status), "no_path");
}

TEST(TransitPlanner, UnloadedModelIsRefused) {
  a2l::TransitPlanner planner{a2l::CollisionModel()};
  ASSERT_FALSE(planner.model().loaded());
  const a2l::TransitResult r = planner.plan(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0));
  EXPECT_EQ(r.status, a2l::TransitStatus::invalid_argument);
  EXPECT_EQ(r.message, "the model is not loaded");
  EXPECT_EQ(r.collision_checks, 0);
}

TEST(TransitPlanner, NonFiniteEndPointsAreRefused) {
  a2l::TransitPlanner planner(load());
  const double nan = std::nan(""), inf = INFINITY;
  const Eigen::Vector2d ok(0.0, 0.0);
  for (const Eigen::Vector2d& bad : {Eigen::Vector2d(nan, 0.0), Eigen::Vector2d(0.0, inf)}) {
    for (const bool bad_start : {true, false}) {
      const a2l::TransitResult r = bad_start ? planner.plan(bad, ok) : planner.plan(ok, bad);
      EXPECT_EQ(r.status, a2l::TransitStatus::invalid_argument) << r.message;
      EXPECT_EQ(r.message, "q_start or q_goal contains NaN or inf") << bad.transpose();
      EXPECT_EQ(r.collision_checks, 0);
    }
  }
}

TEST(TransitPlanner, StartOutsideTheJointLimitsIsRefused) {
  a2l::TransitPlanner planner(load());
  // j1 in [-3, 3], j2 in [-2.5, 2.5]; the goal is valid
  for (const Eigen::Vector2d& start : {Eigen::Vector2d(-3.1, 0.0), Eigen::Vector2d(0.0, 2.6)}) {
    const a2l::TransitResult r = planner.plan(start, Eigen::Vector2d(1.0, 0.0));
    EXPECT_EQ(r.status, a2l::TransitStatus::start_out_of_limits) << r.message;
    EXPECT_STREQ(a2l::transit_status_name(r.status), "start_out_of_limits");
    EXPECT_EQ(r.message, "the start violates the joint limits") << start.transpose();
  }
  // the goal's message names the goal
  const a2l::TransitResult r = planner.plan(Eigen::Vector2d(0, 0), Eigen::Vector2d(9, 0));
  EXPECT_EQ(r.status, a2l::TransitStatus::goal_out_of_limits);
  EXPECT_EQ(r.message, "the goal violates the joint limits");
}

TEST(TransitPlanner, StartInCollisionNamesThePair) {
  a2l::TransitPlanner planner(load());
  // a post on the x axis: the straight arm (j1 = 0) hits it with link2, j1 = 1 is free
  ASSERT_TRUE(
      planner.model().set_obstacles({box("post", {0.75, 0, 0.05}, {0.03, 0.03, 0.2})}, 0.0).ok());
  const a2l::TransitResult r = planner.plan(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0));
  EXPECT_EQ(r.status, a2l::TransitStatus::start_in_collision) << r.message;
  EXPECT_STREQ(a2l::transit_status_name(r.status), "start_in_collision");
  EXPECT_EQ(r.message, "the start collides: 'link2'/'post'");
}

}  // namespace test_transit
#endif

TEST(TimeParameterize, RestToRestWithinLimits) {
  Eigen::MatrixXd wp(3, 2);
  wp << 0, 0, 1, -0.5, 1, 0.5;
  const Eigen::Vector2d v(1.0, 0.5), a(2.0, 1.0);
  a2l::TransitResult r;
  ASSERT_TRUE(a2l::time_parameterize(wp, v, a, 0.001, r).ok());
  EXPECT_GT(r.duration, 0.0);
  for (Eigen::Index k = 0; k < r.times.size(); ++k) {
    EXPECT_LE(std::abs(r.velocities(k, 0)), v[0] + 1e-12);
    EXPECT_LE(std::abs(r.velocities(k, 1)), v[1] + 1e-12);
    EXPECT_LE(std::abs(r.accelerations(k, 0)), a[0] + 1e-12);
    EXPECT_LE(std::abs(r.accelerations(k, 1)), a[1] + 1e-12);
  }
  EXPECT_TRUE(r.positions.bottomRows(1).transpose().isApprox(Eigen::Vector2d(1, 0.5)));
  EXPECT_DOUBLE_EQ(r.times[r.times.size() - 1], r.duration);
  EXPECT_EQ(a2l::time_parameterize(wp, Eigen::Vector2d(1, 0), a, 0.01, r).status,
            a2l::Status::invalid_argument);
  EXPECT_EQ(a2l::time_parameterize(wp, Eigen::Vector3d(1, 1, 1), a, 0.01, r).status,
            a2l::Status::size_mismatch);
}
