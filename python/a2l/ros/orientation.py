"""The orientation the skill node commands: the gripper pointing down, turned about the
vertical as the skill was learned (``docs/ros.md``, "What the node takes from the bundle").

Every movement of the simulated scenes asks the IK for the gripper pointing down, turned by
the scene's ``gripper_yaw`` (:func:`a2l.robot.gripper.gripper_down`); a skill learned from
demonstrations keeps the turn it was learned with in its bundle
(:attr:`a2l.skills.spec.SkillSpec.scene_settings`: the sideways pushes' 90 degrees). The
skill node commands the same orientation to the robot, in its Cartesian target and as the
aim of its joint trajectory's IK.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l.errors import A2LValueError
from a2l.robot.gripper import gripper_down, rotation_angle
from a2l.skills.bundle import load_bundle

__all__ = ["CommandedOrientation", "commanded_orientation", "quaternion"]


@dataclass(frozen=True)
class CommandedOrientation:
    """The orientation a skill node commands.

    Attributes
    ----------
    yaw : float
        The gripper's turn about the vertical (degrees).
    source : str
        Where the turn comes from (the bundle, the parameter, or neither).
    rotation : ndarray, shape (3, 3)
        The orientation in the arm's base frame.
    quaternion : tuple of float
        The same as ``(w, x, y, z)``.
    settings : dict
        The bundle's scene settings.
    """

    yaw: float
    source: str
    rotation: NDArray[np.float64]
    quaternion: tuple[float, float, float, float]
    settings: dict[str, Any]

    def describe(self) -> str:
        """One line for the node's log."""
        return (f"the gripper pointing down, turned {self.yaw:g} degrees ({self.source}); "
                f"the bundle's scene settings: {self.settings or 'none'}")

    def check_start(self, rotation: ArrayLike, tolerance: float) -> None:
        """Refuse a start orientation (3, 3) more than `tolerance` rad from this one.

        Raises
        ------
        a2l.A2LValueError
            Naming the angle and the turn the skill wants.
        """
        angle = rotation_angle(self.rotation, rotation)
        if angle > tolerance:
            raise A2LValueError(
                f"the gripper starts {math.degrees(angle):.0f} degrees from the orientation "
                f"the skill commands (pointing down, turned {self.yaw:g} degrees: "
                f"{self.source}); turn it there first (orientation_tolerance {tolerance} rad)")


def commanded_orientation(bundle: str, down: ArrayLike, gripper_yaw: float = math.nan
                          ) -> CommandedOrientation:
    """The orientation a node running `bundle` commands to an arm whose gripper points down
    at `down` (3, 3) (:attr:`a2l.robot.ArmSpec.down`): turned by `gripper_yaw` degrees, or
    when that is NaN by the bundle's scene setting ``gripper_yaw`` (0 if it names none).

    Raises
    ------
    a2l.A2LValueError
        `gripper_yaw` outside [-180, 180] (and not NaN).
    """
    given = not math.isnan(gripper_yaw)
    if given and not -180 <= gripper_yaw <= 180:
        raise A2LValueError(f"gripper_yaw {gripper_yaw} must be in [-180, 180] degrees (NaN: "
                            "the bundle's)")
    settings = load_bundle(bundle).scene_settings
    if given:
        yaw, source = float(gripper_yaw), "the gripper_yaw parameter"
    elif "gripper_yaw" in settings:
        yaw, source = float(settings["gripper_yaw"]), "as the skill was learned"
    else:
        yaw, source = 0.0, "the bundle names no turn"
    r = gripper_down(yaw, down)
    return CommandedOrientation(yaw, source, r, quaternion(r), settings)


def quaternion(r: ArrayLike) -> tuple[float, float, float, float]:
    """A rotation matrix (3, 3) as a unit quaternion ``(w, x, y, z)``."""
    from scipy.spatial.transform import Rotation

    x, y, z, w = Rotation.from_matrix(np.asarray(r, dtype=float)).as_quat()
    return float(w), float(x), float(y), float(z)
