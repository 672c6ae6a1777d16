"""A robot resolved for the C++ runtime: one JSON file that ``a2l-run --robot FILE.json``
reads without Python (``a2l robot export ROBOT --out FILE.json``; ``docs/runtime.md``).

A built-in robot or a robot file (:func:`a2l.robot.robot_entry`) names its URDF through
``example-robot-data`` or a ``package://`` URI, and its scenes' geometry is computed
(:func:`a2l.robot.table_layout`, and the push box lowered under the hand when the scene is
built: :meth:`a2l.sim.bullet.build.BuildMixin.tool_clearance`). :func:`resolved_robot`
writes down what follows: the URDF's absolute path and SHA-256, the chain, the neutral pose,
``tool_down``, and the push scene's table height, work point (where its box stands), scale,
box size and end-effector workspace, all in the robot's base frame::

    {"format": "a2l-resolved-robot", "version": 1, "name": "panda",
     "urdf": "/.../panda.urdf", "urdf_sha256": "...", "base_link": "panda_link0",
     "tool_link": "panda_hand_tcp", "joint_names": [...], "neutral": [...],
     "tool_down": [[...], [...], [...]],
     "scene": {"table_z": 0.0, "work_point": [0.43, 0.31], "scale": 1.0,
               "push_box_size": [0.07, 0.085, 0.058876],
               "workspace_min": [...], "workspace_max": [...]}}
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from a2l.atomic import atomic_write_text
from a2l.robot import robot_entry, urdf_sha256

__all__ = ["RESOLVED_FORMAT", "RESOLVED_VERSION", "export_robot", "resolved_robot"]

#: The ``format`` key of a resolved robot file.
RESOLVED_FORMAT = "a2l-resolved-robot"
#: Its ``version``; ``a2l-run`` refuses another.
RESOLVED_VERSION = 1


def resolved_robot(robot: str | os.PathLike[str]) -> dict[str, Any]:
    """The resolved description of a robot (module docstring), as JSON-ready data.

    Builds the robot's push scene once (PyBullet, without a window, a fraction of a second)
    for the size of the box it pushes.

    Parameters
    ----------
    robot : str or PathLike
        A built-in robot's name (``"panda"``) or a robot file's path.

    Returns
    -------
    dict
        ``format``, ``version``, ``name``, ``urdf`` (absolute), ``urdf_sha256``,
        ``base_link``, ``tool_link``, ``joint_names`` (n,), ``neutral`` (n,), ``tool_down``
        (3, 3) or None, and ``scene``: ``table_z``, ``work_point`` (2,), ``scale``,
        ``push_box_size`` (3,), ``workspace_min`` and ``workspace_max`` (3,) (m, base frame;
        the workspace's z absolute, not from the table top as in the scene's configuration).

    Raises
    ------
    a2l.A2LValueError, a2l.A2LFileNotFoundError
        As :func:`a2l.robot.robot_entry` and :func:`a2l.sim.make_scene`.
    """
    from a2l.sim import make_scene

    entry = robot_entry(robot)
    with make_scene("push", robot=str(robot)) as scene:
        cfg = scene.config
        z = float(cfg.table_z)
        geometry = {
            "table_z": z,
            "work_point": [float(v) for v in cfg.box_position],
            "scale": float(cfg.layout().scale),
            "push_box_size": [float(v) for v in cfg.box_size],
            "workspace_min": [*map(float, cfg.workspace_min[:2]),
                              round(z + cfg.workspace_min[2], 6)],
            "workspace_max": [*map(float, cfg.workspace_max[:2]),
                              round(z + cfg.workspace_max[2], 6)],
        }
    urdf = entry.urdf.resolve()
    return {
        "format": RESOLVED_FORMAT,
        "version": RESOLVED_VERSION,
        "name": entry.name,
        "urdf": str(urdf),
        "urdf_sha256": urdf_sha256(urdf),
        "base_link": entry.base_link,
        "tool_link": entry.tool_link,
        "joint_names": list(entry.joint_names),
        "neutral": list(entry.neutral),
        "tool_down": [list(row) for row in entry.tool_down] if entry.tool_down else None,
        "scene": geometry,
    }


def export_robot(robot: str | os.PathLike[str], out: str | os.PathLike[str]) -> Path:
    """Write :func:`resolved_robot` of `robot` to `out` (JSON, atomically); returns `out`."""
    text = json.dumps(resolved_robot(robot), indent=2) + "\n"
    return atomic_write_text(out, text)
