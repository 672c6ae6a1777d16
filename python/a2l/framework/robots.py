"""A configuration on a robot: the checks of its ``robot`` field, and the lengths a
:class:`~a2l.framework.FrameworkConfig` leaves at their defaults scaled to a small arm's
scene (the robot's scene scale, :func:`a2l.robot.table_layout`; 1 for Baxter, the Panda, the
UR5)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

from a2l.errors import ConfigError
from a2l.robot import DEFAULT_ROBOT

__all__ = ["LENGTHS", "check_robot", "scaled_parts"]

#: The lengths (m) of a configuration, by part: on a robot whose scene is scaled (a small
#: arm, :func:`a2l.robot.table_layout`), those left at their defaults are scaled with it.
LENGTHS: dict[str, tuple[str, ...]] = {
    "discretization": ("effect_threshold", "step", "dist_low", "dist_high", "offset_half_x",
                       "offset_half_y"),
    "starts": ("radius", "r_low", "r_high"), "skill": ("clearance", "align"),
    "validation": ("r_low", "r_high"), "directed": ("waypoint_aim",),
    "heldout": ("r_low", "r_high"),
}


def check_robot(robot: object, scene_config: Mapping[str, Any]) -> None:
    """Raise :class:`a2l.errors.ConfigError` naming the field: `robot` not a non-empty string,
    a robot also named by `scene_config`. (An earlier scene name given with another robot
    than its own is refused where it is read, :func:`a2l.rollout.env.normalise_scene`.)"""
    if not isinstance(robot, str) or not robot:
        raise ConfigError("robot", f"must be a robot's name or a robot file's path, got "
                          f"{robot!r}")
    if "robot" in scene_config and scene_config["robot"] != robot:
        raise ConfigError("scene_config", "names a robot: give it as the robot field")


def scaled_parts(scene: str, robot: str, parts: Mapping[str, Any]) -> dict[str, Any]:
    """The parts of a configuration (by name, from `parts`) whose lengths left at their
    defaults change on `robot`'s scene: each scaled, rounded to the micrometre. Empty
    outside the ``bullet`` scene, on Baxter, and on a robot of scale 1."""
    if scene != "bullet" or robot == DEFAULT_ROBOT:
        return {}
    from a2l.robot import robot_entry, table_layout

    scale = table_layout(robot_entry(robot)).scale
    out: dict[str, Any] = {}
    if scale >= 1.0:
        return out
    for name, lengths in LENGTHS.items():
        part = parts[name]
        default = type(part)()
        changes = {n: round(getattr(part, n) * scale, 6) for n in lengths
                   if getattr(part, n) == getattr(default, n)}
        if changes:
            out[name] = replace(part, **changes)
    return out
