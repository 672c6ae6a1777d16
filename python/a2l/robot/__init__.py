"""Robot descriptions: locating URDFs and preparing them for PyBullet.

Baxter's URDF and meshes come from the PyPI package ``example-robot-data``; any other URDF
path is accepted wherever a robot is asked for.
"""

from __future__ import annotations

from a2l.robot.descriptions import (
    BAXTER_ARMS,
    ArmSpec,
    arm_spec,
    baxter_urdf,
    panda_urdf,
    pybullet_urdf,
    resolve_urdf,
    robots_dir,
    urdf_sha256,
)
from a2l.robot.gripper import GRIPPER_DOWN, PANDA_DOWN, gripper_down, rotation_angle

__all__ = [
    "BAXTER_ARMS",
    "GRIPPER_DOWN",
    "PANDA_DOWN",
    "ArmSpec",
    "arm_spec",
    "baxter_urdf",
    "gripper_down",
    "panda_urdf",
    "pybullet_urdf",
    "resolve_urdf",
    "robots_dir",
    "rotation_angle",
    "urdf_sha256",
]
