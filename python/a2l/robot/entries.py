"""A robot is data: the entry that names its URDF, its arm chain, its neutral pose, its
gripper and where it stands at the table.

What an entry holds is typed (by hand in :mod:`a2l.robot.builtin_robots`, or in a robot file
read by :func:`a2l.robot.load_robot`); what follows from the URDF (the chain's joints, its
limits, the arm's reach) is computed from it, never typed. :func:`a2l.robot.check_entry`
checks an entry against its URDF.

The table frame: a mount places the robot's base link in it; origin at the centre of the table
top, x across the table away from the robot, y to the robot's left, z up. Today's scenes put
Baxter's base at the world origin with the table top at ``table_z = -0.20`` and its centre at
``(0.75, -0.15)`` (:class:`a2l.sim.SceneConfig`): Baxter's mount is ``xyz = (-0.75, 0.15,
0.20)``, ``yaw = 0``.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from a2l import _core
from a2l.errors import A2LValueError
from a2l.robot.descriptions import ArmSpec

__all__ = ["REACH_CLIMBS", "REACH_SAMPLES", "Gripper", "Mount", "RobotEntry", "arm_reach"]

#: Joint configurations sampled (uniformly within the limits, seed 0) to measure an arm's
#: reach; a continuous joint is sampled in [-pi, pi].
REACH_SAMPLES = 4096
#: The best sampled configurations climbed to the arm's farthest point (:func:`arm_reach`).
REACH_CLIMBS = 8

Matrix3 = tuple[tuple[float, float, float], tuple[float, float, float],
                tuple[float, float, float]]


def _floats(values: object) -> tuple[float, ...]:
    return tuple(float(v) for v in values)  # type: ignore[attr-defined]


@dataclass(frozen=True)
class Gripper:
    """The joints that open and close a gripper, and their two positions.

    Attributes
    ----------
    joints : tuple of str
        Joint names in the URDF, shape (m,). Joints that mimic another are listed too, with
        their own values: PyBullet does not follow a URDF's ``<mimic>``.
    open, closed : tuple of float
        Joint positions (rad or m), shape (m,), of the open and of the closed gripper. The
        scenes hold it `open` while the arm moves and pushes.
    grasp_open : tuple of float or None
        Joint positions, shape (m,), of the gripper opened for a grasp, in the scenes that
        grasp a block (``grasp``, ``grasp_light``); None: `open`. A gripper that pushes half
        open can grasp wide open (the Panda's).
    """

    joints: tuple[str, ...]
    open: tuple[float, ...]
    closed: tuple[float, ...]
    grasp_open: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "joints", tuple(str(j) for j in self.joints))
        object.__setattr__(self, "open", _floats(self.open))
        object.__setattr__(self, "closed", _floats(self.closed))
        if self.grasp_open is not None:
            object.__setattr__(self, "grasp_open", _floats(self.grasp_open))

    def opening(self, grasp: bool) -> tuple[float, ...]:
        """The open positions, shape (m,): `grasp_open` in a scene that grasps (when given),
        else `open`."""
        return self.grasp_open if grasp and self.grasp_open is not None else self.open


@dataclass(frozen=True)
class Mount:
    """Where a robot stands at the table: its base link's pose in the table frame.

    Attributes
    ----------
    xyz : tuple of 3 float
        Position (m) of the base link's origin in the table frame (module docstring: origin
        at the centre of the table top, x away from the robot, z up); ``xyz[2]`` is the
        base's height above the table top (negative: below it).
    yaw : float
        Turn (degrees, as the scenes' ``gripper_yaw``) of the base about the vertical; 0 has
        the base's x axis along the table frame's x.
    """

    xyz: tuple[float, float, float]
    yaw: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "xyz", _floats(self.xyz))
        object.__setattr__(self, "yaw", float(self.yaw))

    def pose(self) -> NDArray[np.float64]:
        """Transform (4, 4) of the base link in the table frame."""
        a = math.radians(self.yaw)
        out = np.eye(4)
        out[:2, :2] = [[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]
        out[:3, 3] = self.xyz
        return out


@dataclass(frozen=True)
class RobotEntry:
    """One robot arm as data; see :mod:`a2l.robot.entries`.

    Attributes
    ----------
    name : str
        The robot's name (``baxter``, ``panda``, a robot file's ``name`` or stem).
    urdf : Path
        The robot's URDF file.
    base_link, tool_link : str
        First and last links of the arm's chain (the tool link is the point the skills move:
        between the fingertips for a gripper).
    neutral : tuple of float
        Joint positions (rad, m for a prismatic joint), shape (n,), of the chain's movable
        joints base to tool: the arm over the table, tool pointing down. Seeds IK.
    mount : Mount
        Where the robot stands at the table.
    tool_down : tuple of 3 tuple of 3 float or None
        Orientation (3, 3) of the tool frame in the base frame when the tool points down
        with the fingers closing along the base's y axis (what the skills ask for, turned
        about the vertical by a scene's ``gripper_yaw``); None when not given.
    gripper : Gripper or None
        The gripper's joints and their open and closed positions; None for a bare arm.
    work_point : tuple of 2 float or None
        Where the scenes put their objects, ``(x, y)`` in the table frame (m); None: computed
        from what the arm reaches (:func:`a2l.robot.table_layout`). Baxter's is the thesis'
        scene.
    rest : tuple of (str, float)
        Positions (rad, m) the robot's joints outside the chain and the gripper hold in the
        scenes, by URDF joint name (Baxter's other arm at its neutral pose); a joint not
        named holds 0, or its nearest limit.
    """

    name: str
    urdf: Path
    base_link: str
    tool_link: str
    neutral: tuple[float, ...]
    mount: Mount
    tool_down: Matrix3 | None = None
    gripper: Gripper | None = None
    work_point: tuple[float, float] | None = None
    rest: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "urdf", Path(os.fspath(self.urdf)))
        if self.work_point is not None:
            object.__setattr__(self, "work_point", _floats(self.work_point))
        object.__setattr__(self, "rest", tuple((str(n), float(v)) for n, v in self.rest))
        object.__setattr__(self, "neutral", _floats(self.neutral))
        if self.tool_down is not None:
            rows = tuple(_floats(r) for r in self.tool_down)  # type: ignore[union-attr]
            object.__setattr__(self, "tool_down", rows)

    # --- what follows from the URDF -------------------------------------------------------

    def kinematics(self) -> _core.Kinematics:
        """The C++ kinematics of the chain ``base_link -> tool_link`` (a new object).

        Raises
        ------
        a2l.URDFError, a2l.UnknownLinkError, FileNotFoundError
            As :class:`a2l.Kinematics`; :func:`a2l.robot.check_entry` names the key.
        """
        return _core.Kinematics(self.urdf, self.base_link, self.tool_link)

    @cached_property
    def joint_names(self) -> tuple[str, ...]:
        """Names of the chain's movable joints, base to tool, shape (n,)."""
        return tuple(self.kinematics().joint_names)

    @property
    def n_joints(self) -> int:
        """Number of movable joints of the chain (the URDF's, not ``len(neutral)``)."""
        return len(self.joint_names)

    @cached_property
    def limits(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """Lower and upper joint limits, each shape (n,); +-inf for a continuous joint."""
        kin = self.kinematics()
        return _floats(kin.lower), _floats(kin.upper)

    @cached_property
    def reach(self) -> float:
        """The arm's reach (m): the largest distance of the tool link's origin from the base
        link's origin with the joints within their limits.

        :data:`REACH_SAMPLES` configurations drawn uniformly within the limits (seed 0;
        continuous joints in [-pi, pi]) and the neutral one; the best :data:`REACH_CLIMBS`
        climbed by gradient ascent (:func:`arm_reach`). Deterministic; a local maximum, so at
        worst a little short of the true one. Measured from the base link, not from the
        shoulder: Baxter's includes the offset of its arm mounts on the torso.
        """
        return arm_reach(self.kinematics(), np.asarray(self.neutral))

    def neutral_pose(self) -> NDArray[np.float64]:
        """Transform (4, 4) of the tool link in the base frame at the neutral pose."""
        return np.asarray(self.kinematics().fk(np.asarray(self.neutral)), dtype=np.float64)

    @property
    def neutral_tilt(self) -> float | None:
        """Angle (rad) between the tool's pointing axis at the neutral pose and the vertical
        down; None without `tool_down`.

        The pointing axis is the tool-frame axis that `tool_down` sends to the base's -z; the
        turn of the tool about the vertical is not counted.
        """
        if self.tool_down is None:
            return None
        axis = np.asarray(self.tool_down).T @ np.array([0.0, 0.0, -1.0])
        pointing = self.neutral_pose()[:3, :3] @ axis
        return math.acos(max(-1.0, min(1.0, -float(pointing[2]) / np.linalg.norm(pointing))))

    @property
    def tool_height(self) -> float:
        """Height (m) of the tool link above the table top at the neutral pose."""
        return float((self.mount.pose() @ self.neutral_pose())[2, 3])

    def record(self) -> dict[str, str]:
        """What a skill bundle records of the robot it was learned for (its ``robot``
        entry, which :meth:`check_learned_for` reads): the name, the URDF's sha256 and the
        chain's links."""
        from a2l.robot.descriptions import urdf_sha256

        return {"name": self.name, "urdf_sha256": urdf_sha256(self.urdf),
                "base_link": self.base_link, "tip_link": self.tool_link}

    def check_learned_for(self, record: object, what: str) -> None:
        """Refuse a skill learned for another robot.

        Parameters
        ----------
        record : mapping or None
            A skill bundle's robot record (``name``, ``urdf_sha256``...); None (a skill of
            the virtual scene) is taken anywhere.
        what : str
            The bundle, for the message (``"skill bundle 'push.a2lb'"``).

        Raises
        ------
        a2l.A2LValueError
            The record names another robot, or a URDF of another content.
        """
        if not record:
            return
        from a2l.robot.descriptions import urdf_sha256

        rec = dict(record)  # type: ignore[call-overload]
        name, sha = str(rec.get("name", "")), str(rec.get("urdf_sha256", ""))
        if name != self.name or (sha and sha != urdf_sha256(self.urdf)):
            raise A2LValueError(
                f"{what} was learned for robot {name!r} (URDF sha256 {sha[:12]}...), not for "
                f"{self.name!r} ({self.urdf.name}): learn the skill on this robot")

    # --- views ----------------------------------------------------------------------------

    def arm_spec(self) -> ArmSpec:
        """The :class:`~a2l.robot.ArmSpec` view of the entry (what the scenes, the transit
        planner and the ROS node take).

        Raises
        ------
        a2l.A2LValueError
            The entry has no `tool_down` (an ArmSpec needs one).
        """
        if self.tool_down is None:
            raise A2LValueError(f"robot '{self.name}' has no tool_down: an ArmSpec needs the "
                                "orientation of its tool pointing down")
        return ArmSpec(self.urdf, self.base_link, self.tool_link, self.neutral, self.tool_down)


def arm_reach(kin: _core.Kinematics, neutral: NDArray[np.float64],
              samples: int = REACH_SAMPLES, seed: int = 0) -> float:
    """Largest distance (m) of the tip from the base origin: the best of `samples` uniform
    joint configurations within the limits of `kin` (continuous joints in [-pi, pi]) and
    `neutral` (shape (n,)), each of the best :data:`REACH_CLIMBS` then climbed by projected
    gradient ascent of the distance (the Jacobian's position rows), within the limits."""
    lower = np.where(np.isfinite(kin.lower), kin.lower, -math.pi)
    upper = np.where(np.isfinite(kin.upper), kin.upper, math.pi)
    qs = np.random.default_rng(seed).uniform(lower, upper, size=(samples, kin.n_joints))
    qs = np.vstack([neutral, qs])
    dist = np.array([np.linalg.norm(kin.fk(q)[:3, 3]) for q in qs])
    best = float(dist.max())
    for q in qs[np.argsort(dist)[-REACH_CLIMBS:]]:
        best = max(best, _climb(kin, q, lower, upper))
    return best


def _climb(kin: _core.Kinematics, q: NDArray[np.float64], lower: NDArray[np.float64],
           upper: NDArray[np.float64], steps: int = 100) -> float:
    """Distance of the tip from the base origin after gradient ascent from `q` (shape (n,)),
    each step clipped to [lower, upper]; a step that does not gain is halved."""
    p = kin.fk(q)[:3, 3]
    d, rate = float(np.linalg.norm(p)), 0.1
    for _ in range(steps):
        grad = (p / max(d, 1e-12)) @ kin.jacobian(q)[:3]
        norm = float(np.linalg.norm(grad))
        if norm < 1e-12 or rate < 1e-6:
            break
        trial = np.clip(q + rate * grad / norm, lower, upper)
        p_trial = kin.fk(trial)[:3, 3]
        d_trial = float(np.linalg.norm(p_trial))
        if d_trial > d:
            q, p, d, rate = trial, p_trial, d_trial, rate * 1.5
        else:
            rate *= 0.5
    return d
