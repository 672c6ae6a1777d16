"""The gripper pointing down: the orientation every movement of the skills asks for.

A scene of :mod:`a2l.sim` moves Baxter's end-effector with the gripper pointing down, turned
about the vertical by the scene's ``gripper_yaw`` (the sideways pushes learn with 90
degrees); the ROS skill node (:mod:`a2l.ros.skill_node`) commands the same orientation to a
real arm. One home for it, in the robot's description.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["BAXTER_FINGER_OPEN", "GRIPPER_DOWN", "PANDA_DOWN", "gripper_down", "rotation_angle"]

#: Orientation (3, 3) of Baxter's gripper frame when it points down: z to the floor, fingers
#: closing along the base's y axis.
GRIPPER_DOWN: NDArray[np.float64] = np.diag([-1.0, 1.0, -1.0])

#: Opening (m) of each of Baxter's two prismatic finger joints when the gripper is open: the
#: left finger joint's upper limit, the right one's lower limit with a minus sign (0 closes).
BAXTER_FINGER_OPEN: float = 0.020833

#: The same for the Panda's hand (``panda_hand_tcp``: z out of the hand, fingers along y).
PANDA_DOWN: NDArray[np.float64] = np.diag([1.0, -1.0, -1.0])


def gripper_down(yaw_deg: float = 0.0, down: ArrayLike = GRIPPER_DOWN) -> NDArray[np.float64]:
    """Rotation (3, 3) of the gripper pointing down (`down`, (3, 3): the arm's, default
    Baxter's), turned by `yaw_deg` degrees about the vertical (90: Baxter's fingers close
    along the base's x axis)."""
    a = math.radians(float(yaw_deg))
    c, s = math.cos(a), math.sin(a)
    turn = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return np.asarray(down, dtype=np.float64) @ turn


def rotation_angle(a: ArrayLike, b: ArrayLike) -> float:
    """The angle (rad, in [0, pi]) of the rotation from `b` to `a` (both (3, 3))."""
    c = (float(np.trace(np.asarray(a, dtype=float) @ np.asarray(b, dtype=float).T)) - 1) / 2
    return math.acos(max(-1.0, min(1.0, c)))
