"""a2l.ros.topics: the messages the nodes build read back as the arrays they were built from;
a pose in another frame, a missing joint or a value that is not finite is refused."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("rclpy", reason="the ros extra (pip install 'a2l[ros]') is not installed")

from builtin_interfaces.msg import Time  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402

from a2l.errors import A2LValueError  # noqa: E402
from a2l.ros import topics as T  # noqa: E402


def test_a_pose_reads_back_as_its_position_in_its_frame() -> None:
    stamp = Time(sec=12, nanosec=500_000_000)
    msg = T.pose_stamped(np.array([0.6, -0.2, 0.05]), stamp, "base", (0.0, 1.0, 0.0, 0.0))
    assert np.allclose(T.pose_position(msg, "base"), [0.6, -0.2, 0.05])
    o = msg.pose.orientation
    assert (o.w, o.x, o.y, o.z) == (0.0, 1.0, 0.0, 0.0)
    assert T.stamp_seconds(msg.header.stamp) == 12.5
    assert T.pose_stamped([0, 0, 0], stamp, "base").pose.orientation.w == 1.0  # identity
    with pytest.raises(A2LValueError, match="pose in frame 'base'; the node expects 'world'"):
        T.pose_position(msg, "world")
    with pytest.raises(A2LValueError, match="not finite"):
        T.pose_position(T.pose_stamped([math.nan, 0, 0], stamp, "base"), "base")


def test_a_joint_trajectory_times_its_points_by_the_period() -> None:
    points = [np.array([0.1, 0.2]), np.array([0.3, 0.4]), np.array([0.5, 0.6])]
    msg = T.joint_trajectory(["a", "b"], points, 0.4, Time(), "base")
    assert list(msg.joint_names) == ["a", "b"] and msg.header.frame_id == "base"
    times = [p.time_from_start.sec + 1e-9 * p.time_from_start.nanosec for p in msg.points]
    assert np.allclose(times, [0.4, 0.8, 1.2])
    assert np.allclose([list(p.positions) for p in msg.points], points)


def test_joint_positions_take_the_arms_joints_by_name() -> None:
    js = JointState(name=["head", "b", "a"], position=[9.0, 2.0, 1.0])
    assert np.array_equal(T.joint_positions(js, ["a", "b"]), [1.0, 2.0])
    with pytest.raises(A2LValueError, match=r"lacks joint\(s\) \['c'\]"):
        T.joint_positions(js, ["a", "c"])
    with pytest.raises(A2LValueError, match="not finite"):
        T.joint_positions(JointState(name=["a"], position=[math.inf]), ["a"])
