"""``a2l robot export ROBOT [--out FILE.json]``: a robot resolved for the C++ runtime
(:mod:`a2l.sim.resolved_robot`, read by ``a2l-run --robot FILE.json``)."""

from __future__ import annotations

import json
from typing import Any

from jsonargparse import Namespace

from a2l.cli.args import UsageError
from a2l.cli.parser import Parser, add_config_option
from a2l.errors import A2LError

__all__ = ["add_robot_parsers"]


def _cmd_export(ns: Namespace) -> int:
    # imported here: the other commands do not build scenes
    from a2l.sim.resolved_robot import export_robot, resolved_robot

    try:
        if ns.out is None:
            print(json.dumps(resolved_robot(ns.robot), indent=2))
        else:
            print(export_robot(ns.robot, ns.out))
    except A2LError as exc:
        raise UsageError("ROBOT", str(exc)) from None
    return 0


def add_robot_parsers(sub: Any, commands: dict[tuple[str, ...], Any]) -> None:
    """The ``robot`` subcommand: ``export``."""
    robot = Parser(prog="a2l robot", description="robots for the C++ runtime")
    sub.add_subcommand("robot", robot, help="robots for the C++ runtime")
    cmds = robot.add_subcommands(metavar="ACTION")
    p = Parser(prog="a2l robot export", description="Write a robot resolved for a2l-run "
               "--robot: its URDF (absolute path, SHA-256), chain, joints, neutral pose, "
               "tool_down, and its push scene's table height, work point, scale, box size "
               "and workspace, in its base frame (JSON; docs/runtime.md).")
    p.add_argument("robot", metavar="ROBOT",
                   help="a built-in robot (baxter, panda, ur5, so101, pr2, baxter-left) or a "
                   "robot file (.yaml, .yml, .json)")
    p.add_argument("--out", metavar="FILE.json", default=None,
                   help="the file to write (default: print the JSON)")
    add_config_option(p)
    cmds.add_subcommand("export", p, help="a robot resolved for a2l-run --robot")
    commands[("robot", "export")] = (p, _cmd_export)
