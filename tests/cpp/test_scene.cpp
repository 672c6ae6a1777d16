// The C++ scenes (virtual push model, Bullet) and the differential-IK executor.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "a2l/effects.hpp"
#include "a2l/executor.hpp"
#include "a2l/scene/bullet.hpp"
#include "a2l/scene/virtual.hpp"

namespace test_scene {

using a2l::Status;
using V = Eigen::Vector3d;

TEST(ClassifyEffect, AxesDiagonalsAndThreshold) {
  EXPECT_EQ(a2l::classify_effect(V(0, 0.05, 0)), 0);     // left = +y
  EXPECT_EQ(a2l::classify_effect(V(0, -0.05, 0)), 1);    // right = -y
  EXPECT_EQ(a2l::classify_effect(V(-0.05, 0, 0)), 2);    // close = -x
  EXPECT_EQ(a2l::classify_effect(V(0.05, 0.01, 0)), 3);  // far = +x
  EXPECT_EQ(a2l::classify_effect(V(0.005, 0, 0)), -1);
  EXPECT_EQ(a2l::classify_effect(V(0.0, 0.0, 0.5)), -1);  // z is ignored
  EXPECT_EQ(a2l::classify_effect(V(std::nan(""), 0.1, 0)), -1);
  EXPECT_EQ(a2l::classify_effect(V(0.05, 0.04, 0), 8), 6);    // far_left
  EXPECT_EQ(a2l::classify_effect(V(-0.05, -0.04, 0), 8), 5);  // close_right
  EXPECT_EQ(a2l::classify_effect(V(0.05, 0.01, 0), 8), 3);    // axis wins at > 3x
}

TEST(VirtualScene, PushAlongTheDominantAxisUntilTheFaceTouches) {
  a2l::VirtualScene s;  // half (0.035, 0.0425, 0.04), radius 0.01
  s.reset(V(-0.1, 0.01, 0.0), V(0, 0, 0));
  EXPECT_FALSE(s.move(V(0.05, 0, 0)));    // p' = -0.05: outside -0.045
  EXPECT_TRUE(s.move(V(0.05, 0.01, 0)));  // p' = (0, 0.02): inside, dominant x
  EXPECT_NEAR(s.object_position().x(), 0.0 + 0.035 + 0.01, 1e-15);
  EXPECT_EQ(s.object_position().y(), 0.0);
  EXPECT_EQ(s.object_position().z(), 0.0);
  EXPECT_TRUE(s.eef_position().isApprox(V(0.0, 0.02, 0.0)));
  // Pushing along -y from above the +y face.
  s.reset(V(0.0, 0.1, 0.0), V(0, 0, 0));
  EXPECT_TRUE(s.move(V(0.01, -0.07, 0)));
  EXPECT_NEAR(s.object_position().y(), 0.03 - 0.0425 - 0.01, 1e-15);
  EXPECT_EQ(s.object_position().x(), 0.0);
}

TEST(VirtualScene, VerticalMovesNeverPushAndTouchingIsNotInside) {
  a2l::VirtualScene s;
  s.reset(V(0.0, 0.0, 0.2), V(0, 0, 0));
  EXPECT_FALSE(s.move(V(0, 0, -0.2)));
  EXPECT_EQ(s.object_position(), V(0, 0, 0));
  s.reset(V(-0.1, 0.0, 0.0), V(0, 0, 0));
  EXPECT_FALSE(s.move(V(0.055, 0, 0)));  // exactly at the grown face: touching only
  EXPECT_FALSE(s.in_contact(s.eef_position()));
}

TEST(VirtualScene, Options) {
  a2l::VirtualSceneOptions o;
  o.half_size = V(0.1, 0.1, 0.1);
  o.eef_radius = 0.0;
  o.table_z = 0.5;
  a2l::VirtualScene s(o);
  s.reset(V(-0.2, 0, 0.6), V(0, 0, 0.6));
  EXPECT_TRUE(s.move(V(0.15, 0, 0)));
  EXPECT_NEAR(s.object_position().x(), 0.05, 1e-15);
  EXPECT_EQ(s.table_z(), 0.5);
}

#if A2L_HAVE_BULLET
TEST(VirtualScene, GraspHoldsWhatTheClosedGripperReachedAndDropsItOnOpening) {
  a2l::VirtualSceneOptions o;
  o.half_size = V(0.015, 0.015, 0.03);
  o.table_z = -0.03;
  o.object_kind = a2l::ObjectKind::graspable;
  a2l::VirtualScene s(o);
  s.reset(V(0.0, 0.0, 0.15), V(0, 0, 0));
  EXPECT_FALSE(s.set_gripper(true));  // closed in the air: nothing held
  EXPECT_TRUE(s.gripper_closed());
  s.set_gripper(false);
  // going down (and a little sideways) with the open gripper passes around the block
  EXPECT_FALSE(s.move(V(0.0, 0.0, -0.08)));
  EXPECT_FALSE(s.move(V(0.01, 0.0, -0.05)));
  EXPECT_TRUE(s.object_position().isZero());
  EXPECT_FALSE(s.holding());
  EXPECT_TRUE(s.set_gripper(true));  // within the block grown by grasp_margin
  EXPECT_TRUE(s.move(V(0.0, 0.0, 0.07)));
  EXPECT_TRUE(s.object_position().isApprox(V(0.0, 0.0, 0.07)));
  EXPECT_FALSE(s.set_gripper(false));  // dropped back onto the table
  EXPECT_NEAR(s.object_position().z(), 0.0, 1e-15);
  EXPECT_FALSE(s.move(V(0.0, 0.0, 0.05)));
  // a sideways move with the open gripper still pushes it
  s.reset(V(-0.05, 0.0, 0.0), V(0, 0, 0));
  EXPECT_TRUE(s.move(V(0.04, 0.0, 0.0)));
  EXPECT_NEAR(s.object_position().x(), -0.01 + 0.025, 1e-15);
}

TEST(VirtualScene, GoingDownOnTheButtonTogglesTheLightOncePerPress) {
  a2l::VirtualSceneOptions o;
  o.half_size = V(0.03, 0.03, 0.01);
  o.object_kind = a2l::ObjectKind::button;
  a2l::VirtualScene s(o);
  s.reset(V(0.0, 0.0, 0.10), V(0, 0, 0));
  EXPECT_FALSE(s.light_on());
  EXPECT_FALSE(s.move(V(0.0, 0.0, -0.05)));  // z 0.05: above top + radius (0.02)
  EXPECT_FALSE(s.light_on());
  EXPECT_FALSE(s.move(V(0.0, 0.0, -0.04)));  // z 0.01: pressed, the button never moves
  EXPECT_TRUE(s.light_on());
  EXPECT_EQ(s.presses(), 1);
  EXPECT_FALSE(s.move(V(0.0, 0.0, -0.005)));  // still down: no second toggle
  EXPECT_EQ(s.presses(), 1);
  EXPECT_TRUE(s.object_position().isZero());
  s.move(V(0.0, 0.0, 0.05));   // released
  s.move(V(0.0, 0.0, -0.05));  // pressed again
  EXPECT_FALSE(s.light_on());
  EXPECT_EQ(s.presses(), 2);
  // beside the button, or coming sideways: nothing
  s.reset(V(0.05, 0.0, 0.05), V(0, 0, 0));
  s.move(V(0.0, 0.0, -0.05));
  EXPECT_EQ(s.presses(), 2);
  s.set_light(true);
  s.reset(V(0.0, 0.0, 0.0), V(0, 0, 0));  // reset keeps the light
  EXPECT_TRUE(s.light_on());
}

TEST(BulletScene, PushMovesTheBoxAlongThePushAndKeepsItOnTheTable) {
  a2l::BulletScene s;
  const V box(0.0, 0.0, 0.04);
  s.reset(V(-0.1, 0.0, 0.04), box);
  EXPECT_FALSE(s.move(V(0.03, 0.0, 0.0)));  // p' = -0.07: no contact yet
  EXPECT_LT((s.object_position() - box).norm(), 1e-3);
  EXPECT_TRUE(s.move(V(0.06, 0.0, 0.0)));
  const V d = s.object_position() - box;
  EXPECT_GT(d.x(), 0.01);
  EXPECT_LT(std::abs(d.y()), 0.3 * d.x());
  EXPECT_NEAR(s.object_position().z(), 0.04, 3e-3);
  EXPECT_EQ(a2l::classify_effect(d), 3);  // far
  EXPECT_GT(s.physics_steps(), 10);
  // Reset puts the box back at rest.
  s.reset(V(0.0, 0.1, 0.04), box);
  EXPECT_TRUE(s.move(V(0.0, -0.09, 0.0)));
  EXPECT_EQ(a2l::classify_effect(s.object_position() - box), 1);  // right
}
#endif

class ExecutorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* dir = std::getenv("A2L_ROBOTS_DIR");
    ASSERT_TRUE(dir != nullptr && *dir) << "set A2L_ROBOTS_DIR (make test-cpp does)";
    ASSERT_TRUE(a2l::Kinematics::load(std::string(dir) + "/baxter_description/urdf/baxter.urdf",
                                      "base", "right_gripper", kin_)
                    .ok());
    q0_.resize(7);
    q0_ << 0.08, -1.0, 1.19, 1.94, -0.67, 1.03, 0.5;
  }
  a2l::Kinematics kin_;
  Eigen::VectorXd q0_;
};

TEST_F(ExecutorTest, ReachesAStepTargetWithinLimitsAndHoldsTheOrientation) {
  a2l::Executor ex;
  ASSERT_TRUE(ex.init(kin_, q0_).ok());
  const Eigen::Isometry3d start = ex.pose();
  const V target = start.translation() + V(0.05, -0.05, 0.0) / std::sqrt(2.0);
  ASSERT_EQ(ex.set_target(target), Status::ok);
  EXPECT_FALSE(ex.reached());
  Eigen::VectorXd prev = ex.q();
  while (!ex.reached()) {
    ASSERT_EQ(ex.tick(), Status::ok) << ex.ticks();
    // Velocity within the URDF limits, position within the joint limits.
    for (int i = 0; i < 7; ++i) {
      EXPECT_LE(std::abs(ex.q()[i] - prev[i]), kin_.velocity_limits()[i] * 1e-3 + 1e-12);
    }
    EXPECT_TRUE(kin_.within_limits(ex.q()));
    prev = ex.q();
  }
  EXPECT_LT((ex.position() - target).norm(), 2e-4);
  // 5 cm at 0.25 m/s at 1 kHz: 200 ticks and a few to settle.
  EXPECT_GE(ex.ticks(), 200);
  EXPECT_LT(ex.ticks(), 400);
  const Eigen::AngleAxisd err(start.linear() * ex.pose().linear().transpose());
  EXPECT_LT(std::abs(err.angle()), 1e-3);
  Eigen::Isometry3d fk;
  ASSERT_EQ(kin_.fk(ex.q(), fk), Status::ok);
  EXPECT_LT((fk.translation() - ex.position()).norm(), 1e-12);
}

TEST_F(ExecutorTest, TurnsTowardASetOrientationAtMostMaxAngularSpeed) {
  a2l::ExecutorOptions o;
  o.max_angular_speed = 1.0;  // rad/s: 1 mrad per 1 ms tick
  a2l::Executor ex;
  ASSERT_TRUE(ex.init(kin_, q0_, o).ok());
  const Eigen::Isometry3d start = ex.pose();
  // the start turned 0.2 rad about the base's vertical
  const Eigen::Matrix3d aim =
      Eigen::AngleAxisd(0.2, V::UnitZ()).toRotationMatrix() * start.linear();
  auto angle_to = [&](const Eigen::Matrix3d& r) {
    return Eigen::AngleAxisd(r * ex.pose().linear().transpose()).angle();
  };
  // not a rotation, or not finite: refused, the aim unchanged
  EXPECT_EQ(ex.set_orientation(2.0 * aim), Status::invalid_argument);
  EXPECT_EQ(ex.set_orientation(-aim), Status::invalid_argument);  // a reflection
  Eigen::Matrix3d nan_aim = aim;
  nan_aim(0, 0) = std::nan("");
  EXPECT_EQ(ex.set_orientation(nan_aim), Status::invalid_argument);
  EXPECT_LT((ex.orientation() - start.linear()).norm(), 1e-12);
  ASSERT_EQ(ex.set_orientation(aim), Status::ok);
  EXPECT_LT((ex.orientation() - aim).norm(), 1e-12);
  ASSERT_EQ(ex.set_target(start.translation() + V(0.02, 0.0, 0.0)), Status::ok);
  double before = angle_to(aim);
  Eigen::VectorXd prev = ex.q();
  for (int k = 0; k < 400; ++k) {
    ASSERT_EQ(ex.tick(), Status::ok) << k;
    const double now = angle_to(aim);
    EXPECT_LE(now, before + 1e-6) << k;         // it turns toward the aim
    EXPECT_GE(now, before - 1e-3 - 2e-4) << k;  // by at most 1 mrad a tick (plus coupling)
    for (int i = 0; i < 7; ++i) {
      EXPECT_LE(std::abs(ex.q()[i] - prev[i]), kin_.velocity_limits()[i] * 1e-3 + 1e-12);
    }
    before = now;
    prev = ex.q();
  }
  EXPECT_LT(angle_to(aim), 1e-3);  // 0.2 rad within 0.4 s at 1 rad/s
  EXPECT_LT((ex.position() - ex.target()).norm(), 1e-4);
  // reset() holds the orientation the arm has again
  ASSERT_EQ(ex.reset(q0_), Status::ok);
  EXPECT_LT((ex.orientation() - start.linear()).norm(), 1e-9);
  o.max_angular_speed = 0.0;
  EXPECT_EQ(ex.init(kin_, q0_, o).status, Status::invalid_argument);
  a2l::Executor unbound;
  EXPECT_EQ(unbound.set_orientation(aim), Status::not_initialized);
}

TEST_F(ExecutorTest, ScalesACommandOverTheVelocityLimitsAndKeepsTheDirection) {
  // A fifth of the URDF's joint velocity limits: the 0.25 m/s reference asks more of the
  // joints than that, so the commands are scaled, every joint by the same factor.
  a2l::ExecutorOptions o;
  o.velocity_margin = 0.2;
  a2l::Executor ex;
  ASSERT_TRUE(ex.init(kin_, q0_, o).ok());
  const V start = ex.position();
  const V target = start + V(0.05, 0.0, 0.0);
  ASSERT_EQ(ex.set_target(target), Status::ok);
  Eigen::VectorXd prev = ex.q();
  double progress = 0.0;  // along the line from start to target
  while (!ex.reached()) {
    ASSERT_EQ(ex.tick(), Status::ok) << ex.ticks();
    for (int i = 0; i < 7; ++i) {
      EXPECT_LE(std::abs(ex.q()[i] - prev[i]), 0.2 * kin_.velocity_limits()[i] * 1e-3 + 1e-12);
    }
    // it keeps to the straight line and never goes back along it
    const V p = ex.position() - start;
    EXPECT_LT(std::hypot(p.y(), p.z()), 1e-3) << ex.ticks();
    EXPECT_GE(p.x(), progress - 1e-9) << ex.ticks();
    progress = p.x();
    prev = ex.q();
    ASSERT_LT(ex.ticks(), 10000);
  }
  EXPECT_LT((ex.position() - target).norm(), 2e-4);
  EXPECT_GT(ex.scaled_ticks(), 0);
  // slower than the 200 ticks of the unscaled motion
  EXPECT_GT(ex.ticks(), 250);
  // the default (full limits) scales nothing on this motion, and reset() clears the count
  ASSERT_TRUE(ex.init(kin_, q0_).ok());
  EXPECT_EQ(ex.scaled_ticks(), 0);
  ASSERT_EQ(ex.set_target(target), Status::ok);
  while (!ex.reached()) ASSERT_EQ(ex.tick(), Status::ok);
  EXPECT_EQ(ex.scaled_ticks(), 0);
}

TEST_F(ExecutorTest, MovesAJointOutOfItsLimitBandWithoutMovingTheEndEffector) {
  // Baxter's shoulder s0 at 4 % of its range above the lower limit (inside the default band
  // of 10 %), the end-effector held where it is: the self-motion turns s0 toward the
  // interior (slower as it leaves the band), and the end-effector stays within a millimetre
  // and keeps its orientation.
  Eigen::VectorXd q = q0_;
  const double lo = kin_.lower()[0], hi = kin_.upper()[0];
  q[0] = lo + 0.04 * (hi - lo);
  a2l::Executor ex;
  ASSERT_TRUE(ex.init(kin_, q).ok());
  const Eigen::Isometry3d start = ex.pose();
  ASSERT_EQ(ex.set_target(start.translation()), Status::ok);
  double prev = ex.q()[0];
  for (int k = 0; k < 2000; ++k) {
    ASSERT_EQ(ex.tick(), Status::ok) << k;
    EXPECT_GE(ex.q()[0], prev - 1e-12) << k;  // never toward the limit
    prev = ex.q()[0];
    EXPECT_LT((ex.position() - start.translation()).norm(), 1e-3) << k;
  }
  EXPECT_GT(ex.q()[0], q[0] + 0.03);  // 2 s of self-motion: 0.065 rad at this depth
  EXPECT_LT(Eigen::AngleAxisd(start.linear() * ex.pose().linear().transpose()).angle(), 1e-2);
  // off: nothing moves
  a2l::ExecutorOptions off;
  off.limit_avoidance = 0.0;
  ASSERT_TRUE(ex.init(kin_, q, off).ok());
  ASSERT_EQ(ex.set_target(start.translation()), Status::ok);
  for (int k = 0; k < 200; ++k) ASSERT_EQ(ex.tick(), Status::ok);
  EXPECT_LT((Eigen::VectorXd(ex.q()) - q).norm(), 1e-9);
  // out of their domain
  off.limit_avoidance = 1.5;
  EXPECT_EQ(ex.init(kin_, q, off).status, Status::invalid_argument);
  off.limit_avoidance = 0.5;
  off.limit_band = 0.5;
  EXPECT_EQ(ex.init(kin_, q, off).status, Status::invalid_argument);
}

TEST_F(ExecutorTest, SafetyChecks) {
  a2l::ExecutorOptions o;
  a2l::Executor ex;
  ASSERT_TRUE(ex.init(kin_, q0_, o).ok());
  const V p0 = ex.position();
  // Workspace bounds.
  o.workspace_min = p0 - V(0.1, 0.1, 0.1);
  o.workspace_max = p0 + V(0.1, 0.1, 0.1);
  ASSERT_TRUE(ex.init(kin_, q0_, o).ok());
  EXPECT_EQ(ex.set_target(p0 + V(0.2, 0, 0)), Status::workspace_limit);
  EXPECT_EQ(ex.set_target(V(std::nan(""), 0, 0)), Status::workspace_limit);
  // Velocity limits, with scaling off: a margin so small that any motion exceeds it.
  o = a2l::ExecutorOptions();
  o.velocity_margin = 1e-6;
  o.scale_velocity = false;
  ASSERT_TRUE(ex.init(kin_, q0_, o).ok());
  ASSERT_EQ(ex.set_target(p0 + V(0.05, 0, 0)), Status::ok);
  const Eigen::VectorXd before = ex.q();
  EXPECT_EQ(ex.tick(), Status::velocity_limit);
  EXPECT_EQ(Eigen::VectorXd(ex.q()), before);  // the command was refused
  EXPECT_EQ(ex.scaled_ticks(), 0);
  // A target beyond reach: the arm stretches until a command is refused (joint limit near
  // the singularity) or the watchdog fires; it never leaves the limits.
  o = a2l::ExecutorOptions();
  o.watchdog_ticks = 3000;
  ASSERT_TRUE(ex.init(kin_, q0_, o).ok());
  ASSERT_EQ(ex.set_target(p0 + V(2.0, 0, 0)), Status::ok);  // far beyond reach
  Status s = Status::ok;
  while (s == Status::ok && !ex.reached()) s = ex.tick();
  EXPECT_TRUE(s == Status::joint_limit || s == Status::velocity_limit || s == Status::unreachable)
      << a2l::status_name(s);
  EXPECT_TRUE(kin_.within_limits(ex.q()));
  // Bad set-up.
  Eigen::VectorXd q_bad = q0_;
  q_bad[1] = 5.0;
  EXPECT_EQ(ex.init(kin_, q_bad).status, Status::invalid_argument);
  EXPECT_EQ(ex.init(kin_, Eigen::VectorXd::Zero(3)).status, Status::size_mismatch);
  a2l::Executor unbound;
  EXPECT_EQ(unbound.tick(), Status::not_initialized);
}

}  // namespace test_scene
