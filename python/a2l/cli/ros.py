"""``a2l ros skill`` and ``a2l ros sim``: a skill bundle run on a robot through ROS 2, and a
simulated robot behind the same topics (:mod:`a2l.ros`, ``docs/ros.md``); both take any robot
(``--robot NAME|FILE``, by default the one the bundle was learned for). Every ROS parameter of
the nodes is a flag; ``--remap from:=to`` and ``--namespace`` move the topics.
"""

from __future__ import annotations

import sys
from dataclasses import fields
from pathlib import Path
from typing import Any

from jsonargparse import Namespace
from jsonargparse.typing import NonNegativeFloat

from a2l.cli.args import UsageError, comma_list
from a2l.cli.parser import Parser, add_config_fields, add_config_option
from a2l.ros.sim_node import SimNodeConfig
from a2l.ros.skill_node import SkillNodeConfig

__all__ = ["add_ros_parsers"]


def _params(ns: Namespace, cls: type, skip: set[str] = frozenset()) -> dict[str, Any]:
    return {f.name: ns[f.name] for f in fields(cls) if f.name not in skip and f.name in ns}


def _rclpy_args(ns: Namespace) -> list[str]:
    from a2l.errors import A2LValueError
    from a2l.ros.spin import ros_args

    try:
        return ros_args(comma_list(ns.remap) or [], ns.namespace)
    except A2LValueError as exc:
        raise UsageError("--remap", str(exc)) from None


def _check_ros() -> None:
    try:
        import rclpy  # noqa: F401
    except ImportError:
        raise UsageError("ros", "rclpy is not installed: pip install 'a2l[ros]'") from None


def _check_record(path: str | None) -> None:
    if path and Path(path).suffix != ".mcap":
        raise UsageError("--record", f"'{path}': a ROS recording ends in .mcap (the Rerun "
                         "recording is written beside it, .rrd)")
    if path and not Path(path).resolve().parent.is_dir():
        raise UsageError("--record", f"'{path}': its directory does not exist")


def _cmd_skill(ns: Namespace) -> int:
    from a2l.ros.run import run_skill

    bundle = Path(ns.bundle)
    if not bundle.is_file():
        raise UsageError("BUNDLE", f"'{bundle}' is not a file")
    _check_ros()
    _check_record(ns.record)
    params = {"bundle": str(bundle), **_params(ns, SkillNodeConfig, {"bundle"})}
    res = run_skill(params, _rclpy_args(ns), record=ns.record)
    if res.code == 2:
        print(f"a2l ros skill: error: {res.message}", file=sys.stderr)
    else:
        print(f"{'success' if res.code == 0 else 'failure'}: stop {res.status} after "
              f"{res.steps} step(s): {res.message}")
    return res.code


def _cmd_sim(ns: Namespace) -> int:
    from a2l.ros.run import run_sim

    if ns.bundle and not Path(ns.bundle).is_file():
        raise UsageError("--bundle", f"'{ns.bundle}' is not a file")
    _check_ros()
    _check_record(ns.record)
    return run_sim(_params(ns, SimNodeConfig), _rclpy_args(ns), duration=ns.duration,
                   record=ns.record)


def _common(p: Parser) -> None:
    p.add_argument("--remap", default=None, metavar="FROM:=TO,...",
                   help="topic remaps, comma-separated, e.g. --remap "
                   "joint_states:=/robot/joint_states,target_pose:=/arm/goal")
    p.add_argument("--namespace", default=None, help="the node's namespace")
    p.add_argument("--record", default=None, metavar="FILE.mcap",
                   help="record the node's messages (MCAP) and a Rerun recording beside it")


def _skill_parser() -> Parser:
    p = Parser(prog="a2l ros skill", description="Run a skill bundle (a push, a grasp, a "
               "press) on a robot through ROS 2: the C++ step on every joint state, commands "
               "as a joint trajectory and a Cartesian target, actions on gripper/command "
               "(docs/ros.md). Exit code 0 at the effect, 1 on another stop, 2 on bad input, "
               "130 on SIGINT.")
    p.add_argument("bundle", metavar="BUNDLE", help="the skill bundle (.a2lb)")
    add_config_fields(p, SkillNodeConfig, skip={"bundle"})
    _common(p)
    return p


def _sim_parser() -> Parser:
    p = Parser(prog="a2l ros sim", description="A PyBullet scene on a robot (Baxter, the "
               "bundle's, or --robot NAME|FILE) as a ROS 2 robot: publishes joint states, "
               "object poses and high-level states, carries out joint trajectories or "
               "Cartesian targets and gripper commands; runs until SIGINT (docs/ros.md).")
    add_config_fields(p, SimNodeConfig)
    p.add_argument("--duration", type=NonNegativeFloat, default=0.0,
                   help="stop after this many seconds (0: at SIGINT)")
    _common(p)
    return p


def add_ros_parsers(sub: Any, commands: dict[tuple[str, ...], Any]) -> None:
    """The ``ros`` subcommand: ``skill``, ``sim``."""
    ros = Parser(prog="a2l ros", description="skills on robots through ROS 2")
    sub.add_subcommand("ros", ros, help="skills on robots through ROS 2 (a2l[ros])")
    cmds = ros.add_subcommands(metavar="ACTION")
    for name, parser, handler, help_ in (
            ("skill", _skill_parser(), _cmd_skill, "run a skill bundle through ROS 2"),
            ("sim", _sim_parser(), _cmd_sim, "a simulated robot as a ROS 2 robot")):
        add_config_option(parser)
        cmds.add_subcommand(name, parser, help=help_)
        commands[("ros", name)] = (parser, handler)
