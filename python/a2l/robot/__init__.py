"""Robot descriptions: a robot is data.

A :class:`RobotEntry` names a robot's URDF, its arm chain (base and tool links), a neutral
pose, the tool's downward orientation, its gripper and where it stands at the table; what
follows from the URDF (the joints, their limits, the reach) is computed. The built-in robots
(:data:`BUILTIN_ROBOTS`: Baxter's two arms, the Panda, the UR5, the SO-101, the PR2's right
arm) use the URDFs of the PyPI package ``example-robot-data`` (:func:`builtin_robot`); a
user's arm is a robot file (:func:`load_robot`; :func:`robot_entry` takes a name or a file;
:func:`check_entry` checks an entry against its URDF). :func:`arm_spec` gives the
:class:`ArmSpec` view the scenes use; :func:`pybullet_urdf` a copy of a URDF PyBullet can load;
:func:`table_layout` where a robot's scenes stand (table, work point, scale, cameras).
"""

from __future__ import annotations

from a2l.robot.builtin_robots import BUILTIN_ROBOTS, DEFAULT_ROBOT, arm_spec, builtin_robot
from a2l.robot.descriptions import (
    BAXTER_ARMS,
    ArmSpec,
    baxter_urdf,
    panda_urdf,
    pybullet_urdf,
    resolve_urdf,
    robots_dir,
    urdf_sha256,
)
from a2l.robot.entries import Gripper, Mount, RobotEntry
from a2l.robot.entry_checks import check_entry
from a2l.robot.gripper import GRIPPER_DOWN, PANDA_DOWN, gripper_down, rotation_angle
from a2l.robot.layout import TableLayout, table_layout
from a2l.robot.robot_file import arm_entry, load_robot, robot_entry

__all__ = [
    "DEFAULT_ROBOT",
    "BAXTER_ARMS",
    "BUILTIN_ROBOTS",
    "GRIPPER_DOWN",
    "PANDA_DOWN",
    "ArmSpec",
    "Gripper",
    "Mount",
    "RobotEntry",
    "TableLayout",
    "arm_entry",
    "arm_spec",
    "baxter_urdf",
    "builtin_robot",
    "check_entry",
    "gripper_down",
    "load_robot",
    "panda_urdf",
    "pybullet_urdf",
    "resolve_urdf",
    "robot_entry",
    "robots_dir",
    "rotation_angle",
    "table_layout",
    "urdf_sha256",
]
