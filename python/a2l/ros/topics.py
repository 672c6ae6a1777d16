"""The ROS 2 interface of a2l: topic names, the high-level states as ``std_msgs/Bool``, and the
conversions between messages and the arrays a skill step reads (``docs/ros.md``).

Topic names are relative, so a namespace (``--namespace``) or a remap (``--remap
joint_states:=/robot/joint_states``) moves them:

=========================  ===================================  ====================================
topic                      type                                 what
=========================  ===================================  ====================================
``joint_states``           ``sensor_msgs/JointState``           the arm's joints (by name; others
                                                                ignored)
``objects/<name>/pose``    ``geometry_msgs/PoseStamped``        one topic per object, in the base
                                                                frame
``states/<name>``          ``std_msgs/Bool``                    one topic per high-level state
``joint_trajectory``       ``trajectory_msgs/JointTrajectory``  the command, joint-level robots
``target_pose``            ``geometry_msgs/PoseStamped``        the command, robots with their own
                                                                Cartesian controller
``gripper/command``        ``std_msgs/Bool``                    an action: true closes, false opens
``skill/trace``            ``std_msgs/String``                  one JSON record per step (no fitting
                                                                standard message exists)
=========================  ===================================  ====================================

A high-level state is two-valued on the wire: :data:`BOOL_STATES` maps ``False``/``True`` to
its value names (``light``: off/on, ``gripper``: open/closed).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l.errors import A2LValueError

__all__ = ["BOOL_STATES", "GRIPPER", "JOINT_STATES", "JOINT_TRAJECTORY", "TARGET_POSE", "TRACE",
           "bool_to_state", "joint_positions", "joint_trajectory", "object_topic",
           "pose_position", "pose_stamped", "state_to_bool", "state_topic", "stamp_seconds",
           "trace_json"]

JOINT_STATES = "joint_states"
JOINT_TRAJECTORY = "joint_trajectory"
TARGET_POSE = "target_pose"
GRIPPER = "gripper/command"
TRACE = "skill/trace"

#: High-level state -> its value names for ``(False, True)``.
BOOL_STATES: dict[str, tuple[str, str]] = {
    "light": ("off", "on"),
    "gripper": ("open", "closed"),
}


def object_topic(name: str) -> str:
    """The pose topic of object `name` (``objects/<name>/pose``)."""
    return f"objects/{name}/pose"


def state_topic(name: str) -> str:
    """The topic of high-level state `name` (``states/<name>``)."""
    return f"states/{name}"


def _values(name: str) -> tuple[str, str]:
    if name not in BOOL_STATES:
        raise A2LValueError(f"high-level state {name!r} has no std_msgs/Bool mapping; known: "
                            f"{sorted(BOOL_STATES)} (a2l.ros.topics.BOOL_STATES)")
    return BOOL_STATES[name]


def state_to_bool(name: str, value: str) -> bool:
    """The ``std_msgs/Bool`` data of state `name` at `value`."""
    values = _values(name)
    if value not in values:
        raise A2LValueError(f"state {name!r}: value {value!r} is not one of {values}")
    return value == values[1]


def bool_to_state(name: str, data: bool) -> str:
    """The value name of state `name` for a ``std_msgs/Bool`` `data`."""
    return _values(name)[int(bool(data))]


def stamp_seconds(stamp: Any) -> float:
    """A ``builtin_interfaces/Time`` in seconds."""
    return float(stamp.sec) + 1e-9 * float(stamp.nanosec)


def pose_position(msg: Any, frame: str) -> NDArray[np.float64]:
    """The position (3,) of a ``geometry_msgs/PoseStamped`` given in `frame`.

    Raises
    ------
    a2l.A2LValueError
        Another frame, or a coordinate that is not finite.
    """
    if msg.header.frame_id not in ("", frame):
        raise A2LValueError(f"pose in frame {msg.header.frame_id!r}; the node expects {frame!r} "
                            "(transform it before publishing)")
    p = msg.pose.position
    xyz = np.array([p.x, p.y, p.z], dtype=np.float64)
    if not np.all(np.isfinite(xyz)):
        raise A2LValueError(f"pose position {tuple(xyz)} is not finite")
    return xyz


def pose_stamped(position: ArrayLike, stamp: Any, frame: str,
                 quaternion: Sequence[float] = (1.0, 0.0, 0.0, 0.0)) -> Any:
    """A ``geometry_msgs/PoseStamped`` at `position` (3,) in `frame`, orientation
    `quaternion` (w, x, y, z; default the identity)."""
    from geometry_msgs.msg import PoseStamped

    msg = PoseStamped()
    msg.header.stamp, msg.header.frame_id = stamp, frame
    p, o = msg.pose.position, msg.pose.orientation
    p.x, p.y, p.z = (float(v) for v in np.asarray(position, dtype=float).reshape(3))
    o.w, o.x, o.y, o.z = (float(v) for v in quaternion)
    return msg


def joint_trajectory(names: Sequence[str], points: Sequence[ArrayLike], period: float,
                     stamp: Any, frame: str) -> Any:
    """A ``trajectory_msgs/JointTrajectory`` through `points` (each (n,), joints `names`),
    the i-th (from 1) at ``i * period`` seconds from the start."""
    from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

    msg = JointTrajectory()
    msg.header.stamp, msg.header.frame_id = stamp, frame
    msg.joint_names = list(names)
    for i, q in enumerate(points, 1):
        pt = JointTrajectoryPoint(positions=[float(v) for v in np.asarray(q).reshape(-1)])
        pt.time_from_start.sec, pt.time_from_start.nanosec = divmod(
            int(round(i * period * 1e9)), 1_000_000_000)
        msg.points.append(pt)
    return msg


def joint_positions(msg: Any, names: Sequence[str]) -> NDArray[np.float64]:
    """The positions (n,) of joints `names` from a ``sensor_msgs/JointState``.

    Raises
    ------
    a2l.A2LValueError
        A joint missing from the message, or a position that is not finite.
    """
    index = {n: i for i, n in enumerate(msg.name)}
    missing = [n for n in names if n not in index]
    if missing or len(msg.position) < len(msg.name):
        raise A2LValueError(f"joint state lacks joint(s) {missing or list(names)}; it names "
                            f"{list(msg.name)[:10]}")
    q = np.array([msg.position[index[n]] for n in names], dtype=np.float64)
    if not np.all(np.isfinite(q)):
        raise A2LValueError(f"joint positions {tuple(np.round(q, 4))} are not finite")
    return q


def _clean(v: Any) -> Any:
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, np.ndarray):
        return [_clean(float(x)) for x in v.reshape(-1)]
    if isinstance(v, np.generic):
        return _clean(v.item())
    return v


def trace_json(record: Mapping[str, Any]) -> str:
    """One step's trace record as JSON (non-finite numbers as null)."""
    return json.dumps({k: _clean(v) for k, v in record.items()}, separators=(",", ":"))
