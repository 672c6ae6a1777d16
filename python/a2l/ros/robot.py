"""The robot a node runs (``--robot``, ``a2l ros sim`` and ``a2l ros skill``): a built-in name
or a robot file (``docs/robots.md``), by default the robot the bundle was learned for; the
skill node's check of a bundle against it, and the object a skill acts on."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from a2l.errors import A2LValueError
from a2l.robot import (
    BAXTER_ARMS,
    BUILTIN_ROBOTS,
    DEFAULT_ROBOT,
    ArmSpec,
    RobotEntry,
    arm_entry,
)
from a2l.skills.runner import CppSkillRunner

__all__ = ["check_robot", "node_robot", "skill_object"]


def node_robot(robot: str, bundle_robot: Mapping[str, Any] | None = None,
               arm: str = "right") -> RobotEntry:
    """The robot entry of a node.

    Parameters
    ----------
    robot : str
        A built-in robot's name or a robot file's path; empty: the robot `bundle_robot`
        names when it is a built-in one, else Baxter.
    bundle_robot : mapping, optional
        A skill bundle's robot record (``name``, ``urdf_sha256``...), or None.
    arm : {"right", "left"}
        Baxter's arm (robot ``baxter`` with ``arm="left"`` is ``baxter-left``); another
        robot takes only ``"right"``, the default.

    Returns
    -------
    a2l.robot.RobotEntry

    Raises
    ------
    a2l.A2LValueError
        An unknown robot or arm, an unreadable robot file, or no robot given for a bundle
        learned for a robot of a robot file (its path is not in the bundle).
    """
    if arm not in BAXTER_ARMS:
        raise A2LValueError(f"unknown arm {arm!r}; Baxter's are {sorted(BAXTER_ARMS)}")
    if not robot:
        name = str((bundle_robot or {}).get("name", "")) or DEFAULT_ROBOT
        if name not in BUILTIN_ROBOTS:
            raise A2LValueError(f"the bundle was learned for robot {name!r}, not a built-in "
                                "one: give its robot file (robot parameter, --robot FILE)")
        robot = name
    if arm == "left" and robot != DEFAULT_ROBOT:
        raise A2LValueError(f"arm 'left' is Baxter's (robot 'baxter-left'), not robot "
                            f"{robot!r}'s")
    return arm_entry(robot, arm)


def check_robot(runner: CppSkillRunner, robot: str, arm: str = "right") -> ArmSpec:
    """The arm spec of `robot` (:func:`a2l.ros.robot.node_robot`: empty for the bundle's),
    checked against the bundle's robot entry.

    Raises
    ------
    a2l.A2LValueError
        The bundle was learned for another robot (name or URDF checksum), an unknown robot
        or arm, a robot without ``tool_down``.
    """
    entry = node_robot(robot, runner.skill.robot, arm)
    entry.check_learned_for(runner.skill.robot, f"skill bundle '{runner.path}'")
    return entry.arm_spec()


def skill_object(name: str, given: str) -> str:
    """The object a skill named `name` acts on: `given`, else the object of the
    demonstrated manipulation skill of that name (:data:`a2l.lfd.manipulation.SKILL_OBJECTS`:
    the grasp's block, the press's button), else ``"box"`` (the pushes')."""
    if given:
        return given
    from a2l.lfd.manipulation import SKILL_OBJECTS  # not the library: no simulator loaded

    return SKILL_OBJECTS.get(name, "box")
