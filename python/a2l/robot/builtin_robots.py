"""The robots a2l knows by name, each a :class:`~a2l.robot.RobotEntry` on a URDF of the
installed ``example-robot-data``, and :func:`arm_spec`, their view for the scenes.

Each neutral pose has the tool pointing down (within 0.1 degree; Baxter's, the scenes' pose
since the start, within 3.2 degrees) over the table in front of the base, elbow up; each
``tool_down`` closes the fingers along the base's y axis. Mounts are in the table frame of
:mod:`a2l.robot.entries`; Baxter's is where today's scenes put it, the others are a plausible
place at a table of the same height (0.724 m above the floor), not used by any scene yet.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable

from a2l.errors import A2LValueError
from a2l.robot.descriptions import (
    BAXTER_ARMS,
    PUSHER_TIP,
    ArmSpec,
    baxter_urdf,
    panda_urdf,
    pusher_urdf,
    robots_dir,
)
from a2l.robot.entries import Gripper, Mount, RobotEntry
from a2l.robot.gripper import BAXTER_FINGER_OPEN, GRIPPER_DOWN, PANDA_DOWN

__all__ = ["BUILTIN_ROBOTS", "DEFAULT_ROBOT", "arm_spec", "builtin_robot"]

_DOWN_Y = ((-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0))  # z down, y along y
#: Baxter's mount: the thesis' table (centre (0.75, -0.15) and top at z = -0.20 in Baxter's
#: base frame); its work point: the thesis' box at (0.62, -0.25) in the base frame
_BAXTER_MOUNT = Mount((-0.75, 0.15, 0.20), 0.0)
_BAXTER_WORK_POINT = {"right": (-0.13, -0.10), "left": (-0.13, 0.40)}  # left: mirrored


def _baxter(arm: str) -> RobotEntry:
    base, tip, neutral = BAXTER_ARMS[arm]
    p = arm[0]
    other, other_p = ("left", "l") if arm == "right" else ("right", "r")
    rest = [(f"{other}_{s}", q) for s, q in zip(("s0", "s1", "e0", "e1", "w0", "w1", "w2"),
                                                 BAXTER_ARMS[other][2], strict=True)]
    rest += [(f"{other_p}_gripper_l_finger_joint", BAXTER_FINGER_OPEN),
             (f"{other_p}_gripper_r_finger_joint", -BAXTER_FINGER_OPEN)]
    return RobotEntry(
        name="baxter" if arm == "right" else "baxter-left", urdf=baxter_urdf(),
        base_link=base, tool_link=tip, neutral=neutral, mount=_BAXTER_MOUNT,
        tool_down=tuple(map(tuple, GRIPPER_DOWN.tolist())),  # type: ignore[arg-type]
        gripper=Gripper((f"{p}_gripper_l_finger_joint", f"{p}_gripper_r_finger_joint"),
                        (BAXTER_FINGER_OPEN, -BAXTER_FINGER_OPEN), (0.0, 0.0)),
        work_point=_BAXTER_WORK_POINT[arm], rest=tuple(rest))


def _panda() -> RobotEntry:
    # on a stand level with the table top, 0.10 m before the near edge of a 0.7 m deep table;
    # open: 4 cm between the fingers as Baxter's (at its 8 cm stop the fingers straddled the
    # 8.5 cm push box and clipped it 10 cm off the tool point: 68 of 128 held-out pushes of a
    # tuning run moved it the wrong way); opened for a grasp to its stop, 8 cm: with 4 cm a
    # finger landed on the 3 cm block when the hand came down 1-2 cm off its centre and
    # pushed it away (the demonstrated grasp, tuning trial seeds 500-579: 70 of 80, with 8
    # cm 79 of 80; Baxter's fingers open 4.2 cm at their stop: 76)
    return RobotEntry(
        name="panda", urdf=panda_urdf(), base_link="panda_link0", tool_link="panda_hand_tcp",
        neutral=(0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785), mount=Mount((-0.45, 0.0, 0.0)),
        tool_down=tuple(map(tuple, PANDA_DOWN.tolist())),  # type: ignore[arg-type]
        gripper=Gripper(("panda_finger_joint1", "panda_finger_joint2"), (0.02, 0.02),
                        (0.0, 0.0), grasp_open=(0.04, 0.04)))


def _ur5() -> RobotEntry:
    # wrist_1 = -pi/2 - (shoulder_lift + elbow): the tool's z axis vertical, down. A bare
    # flange pushes with the wrist: reaching over the 8 cm push box, the wrist_1 link hangs
    # at the box's top (0.08 m, measured) and shoved it from 15 cm off. The UR5 pushes with a
    # rod of 12 cm on its flange (pusher_urdf), the tool point at its tip.
    urdf = pusher_urdf(robots_dir() / "ur_description" / "urdf" / "ur5_robot.urdf", "tool0",
                       (0.0, 0.0, 1.0), 0.12, 0.015)
    return RobotEntry(
        name="ur5", urdf=urdf, base_link="base_link", tool_link=PUSHER_TIP,
        neutral=(0.0, -1.55, 2.0, -2.0208, -1.5708, 1.5708), mount=Mount((-0.45, 0.0, 0.0)),
        tool_down=_DOWN_Y, gripper=None)


def _so101() -> RobotEntry:
    # on the table top, 0.05 m inside its near edge; tool 5 cm above the table (the wrist
    # flex limit keeps a pointing-down tool low); the jaw: closed at its lower limit, where
    # the jaw tips meet, opened for a grasp 0.6 rad (about 6 cm between the tips). It pushes
    # closed: open 0.6 rad, the moving jaw reaches 8.9 cm to the side of the tool point (5.0
    # closed; the scaled push box is 4.5 cm wide) and swept the box from 8 cm off
    return RobotEntry(
        name="so101", urdf=robots_dir() / "so_arm_description" / "urdf" / "so101.urdf",
        base_link="base_link", tool_link="gripper_frame_link",
        neutral=(0.0, -0.26, 0.47, 1.36, -1.52), mount=Mount((-0.30, 0.0, 0.0)),
        tool_down=((0.0, 1.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, -1.0)),
        gripper=Gripper(("gripper",), (-0.174533,), (-0.174533,), grasp_open=(0.6,)))


def _pr2() -> RobotEntry:
    # the chain includes the torso lift (prismatic, 0.2 m up); the upper arm rolled by -pi
    # so that the elbow bends down: elbow 0.27 m above the tool. The base stands on the
    # floor (base_link 0.051 m up), 0.35 m before the table's near edge.
    gripper = ("r_gripper_l_finger_joint", "r_gripper_r_finger_joint",
               "r_gripper_l_finger_tip_joint", "r_gripper_r_finger_tip_joint")
    return RobotEntry(
        name="pr2", urdf=robots_dir() / "pr2_description" / "urdf" / "pr2.urdf",
        base_link="base_link", tool_link="r_gripper_tool_frame",
        neutral=(0.2, 0.0, -0.5, -math.pi, -0.8, 0.0, -1.2708, math.pi),
        mount=Mount((-0.70, 0.0, -0.673)),
        tool_down=((0.0, 0.0, 1.0), (0.0, 1.0, 0.0), (-1.0, 0.0, 0.0)),
        gripper=Gripper(gripper, (0.25,) * 4, (0.0,) * 4))


_BUILDERS: dict[str, Callable[[], RobotEntry]] = {
    "baxter": lambda: _baxter("right"),
    "baxter-left": lambda: _baxter("left"),
    "panda": _panda,
    "ur5": _ur5,
    "so101": _so101,
    "pr2": _pr2,
}

#: Names of the built-in robots.
BUILTIN_ROBOTS: tuple[str, ...] = tuple(_BUILDERS)

#: The robot of every scene, experiment and node not told another: Baxter (right arm), the
#: thesis' robot.
DEFAULT_ROBOT = "baxter"


def builtin_robot(name: str) -> RobotEntry:
    """The built-in robot `name` (one of :data:`BUILTIN_ROBOTS`).

    Raises
    ------
    a2l.A2LValueError
        `name` is not a built-in robot (they are listed).
    a2l.A2LFileNotFoundError
        ``example-robot-data`` is not installed.
    """
    if name not in _BUILDERS:
        raise A2LValueError(f"no built-in robot '{name}'; choose one of "
                            f"{', '.join(BUILTIN_ROBOTS)}, or give a robot file")
    return _BUILDERS[name]()


def arm_spec(robot: str | os.PathLike[str] = DEFAULT_ROBOT, arm: str = "right") -> ArmSpec:
    """The arm chain of a built-in robot: the :class:`ArmSpec` view of its entry.

    Parameters
    ----------
    robot : str or PathLike
        A name of :data:`BUILTIN_ROBOTS` (``"baxter"``, ``"panda"``...).
    arm : str
        ``"right"`` or ``"left"`` for Baxter (``"baxter"`` with ``"left"`` is
        ``"baxter-left"``); ignored for the other robots.

    Raises
    ------
    ValueError
        An unknown robot, or an unknown arm of Baxter.
    """
    if robot == "baxter":
        if arm not in BAXTER_ARMS:
            raise ValueError(f"unknown Baxter arm '{arm}'; choose one of {sorted(BAXTER_ARMS)}")
        return _baxter(arm).arm_spec()
    if isinstance(robot, str) and robot in _BUILDERS:
        return _BUILDERS[robot]().arm_spec()
    raise ValueError(f"no built-in arm for robot '{robot}'; choose one of "
                     f"{', '.join(BUILTIN_ROBOTS)} or build an ArmSpec from its URDF")
