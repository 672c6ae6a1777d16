"""Checking a robot entry against its URDF, each refusal naming the key at fault.

:func:`check_entry` is what :func:`a2l.robot.load_robot` runs on a robot file (and the tests
on every built-in robot). The table check is deliberately simple: at the neutral pose the
tool must be above the table top, and the point of the table top straight below it must lie
within the arm's reach of the base link's origin (:attr:`RobotEntry.reach`). Both are
necessary for the arm to work at the table, not sufficient: the reach is measured from the
base link, not from the shoulder, and says nothing of the tool's orientation.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from a2l.errors import RobotEntryError, UnknownLinkError, URDFError
from a2l.robot.entries import Gripper, RobotEntry
from a2l.robot.layout import TABLE_SIZE

__all__ = ["ROTATION_TOLERANCE", "UrdfTree", "check_entry", "read_urdf_tree"]

#: Largest deviation of ``R^T R`` from the identity (each entry) and of ``det R`` from 1
#: accepted for `tool_down`: room for values typed to 4 decimals (0.7071), no more.
ROTATION_TOLERANCE = 1e-4
#: Slack (rad or m) on a joint limit for the neutral and the gripper positions.
LIMIT_SLACK = 1e-9
_MOVABLE = ("revolute", "continuous", "prismatic")


@dataclass(frozen=True)
class UrdfTree:
    """The names a URDF declares: its links and its joints.

    Attributes
    ----------
    links : tuple of str
        Link names, in file order.
    joints : dict
        Joint name -> (type, lower, upper); the limits are -inf, inf for a continuous joint
        and 0, 0 for a joint without any (urdfdom's default).
    """

    links: tuple[str, ...]
    joints: dict[str, tuple[str, float, float]]


def read_urdf_tree(path: Path, source: str) -> UrdfTree:
    """The links and joints of the URDF at `path`.

    Raises
    ------
    a2l.RobotEntryError
        Key ``urdf``: the file is missing, is not XML or has no ``<robot>`` root.
    """
    if not path.is_file():
        raise RobotEntryError(source, "urdf", f"no such file '{path}'")
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise RobotEntryError(source, "urdf", f"'{path}' is not XML: {exc}") from None
    if root.tag != "robot":
        raise RobotEntryError(source, "urdf", f"'{path}' has no <robot> root (found "
                              f"<{root.tag}>)")
    links = tuple(str(e.get("name")) for e in root.findall("link"))
    joints: dict[str, tuple[str, float, float]] = {}
    for e in root.findall("joint"):
        kind = str(e.get("type"))
        limit = e.find("limit")
        lo = float(limit.get("lower", 0.0)) if limit is not None else 0.0
        hi = float(limit.get("upper", 0.0)) if limit is not None else 0.0
        if kind == "continuous":
            lo, hi = -math.inf, math.inf
        joints[str(e.get("name"))] = (kind, lo, hi)
    return UrdfTree(links, joints)


def check_entry(entry: RobotEntry, source: str | None = None) -> None:
    """Check `entry` against its URDF; return quietly when it is right.

    Parameters
    ----------
    entry : RobotEntry
        The entry.
    source : str, optional
        What holds it, for the messages (``robot file '/path/arm.yaml'``); ``robot '<name>'``
        by default.

    Raises
    ------
    a2l.RobotEntryError
        Naming the source and the key: values not finite, `tool_down` not a rotation, a
        missing or unreadable URDF, an unknown link (the URDF's links listed), no chain
        between the links, a `neutral` whose length is not the chain's joint count (both
        given) or outside the joint limits, gripper joints the URDF does not have or values
        outside their limits, `rest` joints the URDF does not have, a `work_point` off the
        table, an arm that cannot reach the table (module docstring).
    """
    src = source if source is not None else f"robot '{entry.name}'"
    _check_values(entry, src)
    tree = read_urdf_tree(entry.urdf, src)
    for key in ("base_link", "tool_link"):
        link = getattr(entry, key)
        if link not in tree.links:
            raise RobotEntryError(src, key, f"unknown link '{link}': the URDF '{entry.urdf}' "
                                  f"has the links {', '.join(tree.links)}")
    try:
        kin = entry.kinematics()
    except URDFError as exc:
        raise RobotEntryError(src, "urdf", str(exc)) from None
    except UnknownLinkError:
        raise RobotEntryError(src, "tool_link", f"no chain of joints joins '{entry.base_link}' "
                              f"to '{entry.tool_link}' in '{entry.urdf}'") from None
    names = list(kin.joint_names)
    if len(entry.neutral) != len(names):
        raise RobotEntryError(src, "neutral", f"{len(entry.neutral)} values, but the chain "
                              f"'{entry.base_link}' -> '{entry.tool_link}' has {len(names)} "
                              f"movable joints ({', '.join(names)})")
    for name, q, lo, hi in zip(names, entry.neutral, kin.lower, kin.upper, strict=True):
        if not lo - LIMIT_SLACK <= q <= hi + LIMIT_SLACK:
            raise RobotEntryError(src, "neutral", f"joint '{name}' at {q:g} is outside its "
                                  f"limits [{lo:g}, {hi:g}]")
    if entry.gripper is not None:
        _check_gripper(entry.gripper, tree, set(names), entry.urdf, src)
    for joint, _ in entry.rest:
        if joint not in tree.joints:
            raise RobotEntryError(src, f"rest.{joint}", f"unknown joint: '{entry.urdf}' has "
                                  f"the joints {', '.join(tree.joints)}")
    if entry.work_point is not None:
        x, y = entry.work_point
        if not (abs(x) < TABLE_SIZE[0] / 2 and abs(y) < TABLE_SIZE[1] / 2):
            raise RobotEntryError(src, "work_point", f"({x:g}, {y:g}) is off the table top "
                                  f"(table frame: |x| < {TABLE_SIZE[0] / 2:g}, |y| < "
                                  f"{TABLE_SIZE[1] / 2:g} m)")
    _check_table(entry, src)


def _check_values(entry: RobotEntry, src: str) -> None:
    """Sizes and finiteness of the typed values, and `tool_down` a rotation."""
    if not all(math.isfinite(v) for v in entry.neutral):
        raise RobotEntryError(src, "neutral", f"values must be finite, got {entry.neutral}")
    if len(entry.mount.xyz) != 3 or not all(math.isfinite(v) for v in entry.mount.xyz):
        raise RobotEntryError(src, "mount.xyz", f"must be 3 finite numbers, got "
                              f"{entry.mount.xyz}")
    if not math.isfinite(entry.mount.yaw):
        raise RobotEntryError(src, "mount.yaw", f"must be finite, got {entry.mount.yaw}")
    if entry.tool_down is not None:
        rows = entry.tool_down
        if len(rows) != 3 or any(len(r) != 3 for r in rows):
            raise RobotEntryError(src, "tool_down", "must be a 3 x 3 matrix (3 rows of 3), got "
                                  f"rows of lengths {[len(r) for r in rows]}")
        r = np.asarray(rows, dtype=float)
        if not np.all(np.isfinite(r)):
            raise RobotEntryError(src, "tool_down", f"values must be finite, got {rows}")
        off = float(np.max(np.abs(r.T @ r - np.eye(3))))
        det = float(np.linalg.det(r))
        if off > ROTATION_TOLERANCE or abs(det - 1.0) > ROTATION_TOLERANCE:
            raise RobotEntryError(src, "tool_down", f"not a rotation matrix: R^T R is off the "
                                  f"identity by {off:.3g}, det R = {det:.6g} (must be 1)")
    g = entry.gripper
    if g is not None:
        if not g.joints:
            raise RobotEntryError(src, "gripper.joints", "names no joint")
        for key, values in _gripper_positions(g):
            if len(values) != len(g.joints):
                raise RobotEntryError(src, key, f"{len(values)} values for the "
                                      f"{len(g.joints)} gripper.joints")
            if not all(math.isfinite(v) for v in values):
                raise RobotEntryError(src, key, f"values must be finite, got {values}")


def _gripper_positions(g: Gripper) -> list[tuple[str, tuple[float, ...]]]:
    """The gripper's position sets with their robot-file keys (`grasp_open` when given)."""
    sets = [("gripper.open", g.open), ("gripper.closed", g.closed)]
    return sets + ([("gripper.grasp_open", g.grasp_open)] if g.grasp_open is not None else [])


def _check_gripper(g: Gripper, tree: UrdfTree, chain: set[str], urdf: Path, src: str) -> None:
    movable = [n for n, (kind, _, _) in tree.joints.items() if kind in _MOVABLE]
    for i, joint in enumerate(g.joints):
        if joint not in tree.joints or tree.joints[joint][0] not in _MOVABLE:
            what = "not a movable joint of" if joint in tree.joints else "not a joint of"
            raise RobotEntryError(src, "gripper.joints", f"'{joint}' is {what} the URDF "
                                  f"'{urdf}': its movable joints are {', '.join(movable)}")
        if joint in chain:
            raise RobotEntryError(src, "gripper.joints", f"'{joint}' is a joint of the arm's "
                                  "chain, not of the gripper")
        _, lo, hi = tree.joints[joint]
        for key, values in _gripper_positions(g):
            if not lo - LIMIT_SLACK <= values[i] <= hi + LIMIT_SLACK:
                raise RobotEntryError(src, key, f"joint '{joint}' at {values[i]:g} is outside "
                                      f"its limits [{lo:g}, {hi:g}]")


def _check_table(entry: RobotEntry, src: str) -> None:
    """The neutral tool above the table top, the table top below it within reach."""
    tool = (entry.mount.pose() @ entry.neutral_pose())[:3, 3]
    base = np.asarray(entry.mount.xyz)
    if tool[2] <= 0.0:
        raise RobotEntryError(src, "mount.xyz", f"at the neutral pose the tool is "
                              f"{-tool[2]:.3f} m below the table top (base {base[2]:.3f} m "
                              "above it): raise the mount or the neutral pose")
    below = np.array([tool[0], tool[1], 0.0])
    distance = float(np.linalg.norm(below - base))
    if distance > entry.reach:
        raise RobotEntryError(src, "mount.xyz", f"the table top below the neutral tool is "
                              f"{distance:.3f} m from the base, beyond the arm's reach "
                              f"{entry.reach:.3f} m (base {base[2]:.3f} m above the table)")
