"""The ``a2l`` command.

Subcommands
-----------
demo
    The main job (see ``a2l demo --help``).
demo-record
    Record demonstrations by teleoperation in the PyBullet GUI (keys: a2l.lfd.teleop).
experiment push
    The A2L push experiment (see ``a2l experiment push --help``: one flag per
    FrameworkConfig field).
experiment discretization
    The orientation x distance discretization study.
experiment lasa
    The diffeomorphic DS on the LASA handwriting benchmark.
experiment babbling
    One exploration method (NovEB, random or goal babbling) on Baxter's push scenes.
experiment babbling-compare
    Every exploration method over several seeds, side by side.
experiment lfd-skills
    Demonstrated skills learned, then run on held-out seeds (``--help``).
experiment parametrization
    Grid x step x bins x smoothing study of demonstrated skills; selects the default.
experiment perturbations
    Demonstrated skills under perturbations: context skill vs DS alone.
experiment sweep
    The push experiment over many seeds: iterations to reach score 100.
experiment tasks
    Planned tasks with the learned skills, with and without faults.
results
    Run the experiments behind the published tables; write docs/results/ (``--help``).
skill show BUNDLE
    What a skill or DS bundle holds.
skill learn --demos FILE --out BUNDLE --effect E
    Learn a skill from a demonstrations file (e.g. from ``demo-record``).
skill run BUNDLE --effect E
    Run a skill bundle in a scene (table or DS mode); print the outcome and the trace.
ros skill BUNDLE --effect E
    Run a skill bundle on a robot through ROS 2 (``a2l[ros]``, docs/ros.md).
ros sim
    The simulated Baxter as a ROS 2 robot behind the same topics.
robot export ROBOT --out FILE.json
    A robot resolved for the C++ runtime (``a2l-run --robot FILE.json``, docs/runtime.md).
view FILE.rrd
    Open a Rerun recording of a run (``--record`` of ``skill run``, ``ros skill`` and every
    ``experiment``).

Layout: ``parser`` (the jsonargparse parser class, configuration flags, config files),
``args`` (usage error, argument checks), ``demo`` (demo, demo-record), ``experiments`` (the
``experiment`` group; lasa, babbling), ``push`` (push, discretization, sweep), ``lfd``
(lfd-skills, parametrization, perturbations), ``tasks``, ``skill`` (show, learn,
run), ``ros`` (skill, sim), ``robot`` (export), ``view``. Every argument is parsed here,
and everything, names included, is checked before any work starts; the experiments raise
:class:`a2l.errors.ConfigError` naming the argument at fault, which :func:`main` reports as
a usage error (exit code 2).
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence

from jsonargparse import Namespace

from a2l.cli import demo, experiments, results, robot, ros, skill, view
from a2l.cli.args import UsageError
from a2l.cli.parser import Parser, command_path, normalize_argv
from a2l.errors import ConfigError

__all__ = ["UsageError", "build_parser", "main", "parse"]

#: A command's handler: its namespace in, the exit code out.
Handler = Callable[[Namespace], int]

#: The parser of the command :func:`parse` parsed last, by command path (the spellings of
#: its options, for the messages of :func:`main`).
_LAST: dict[tuple[str, ...], Parser] = {}


def build_parser() -> tuple[Parser, dict[tuple[str, ...], tuple[Parser, Handler]]]:
    """The parser of the ``a2l`` command and, per command path (``("experiment",
    "push")``), its parser and handler."""
    parser = Parser(prog="a2l", description="Adaptive Affordance Learning: learn "
                    "manipulation skills and run them.")
    sub = parser.add_subcommands(metavar="COMMAND")
    commands: dict[tuple[str, ...], tuple[Parser, Handler]] = {}
    demo.add_demo_parsers(sub, commands)
    experiments.add_experiment_parsers(sub, commands)
    skill.add_skill_parsers(sub, commands)
    results.add_results_parser(sub, commands)
    ros.add_ros_parsers(sub, commands)
    robot.add_robot_parsers(sub, commands)
    view.add_view_parser(sub, commands)
    return parser, commands


def parse(argv: Sequence[str]) -> tuple[tuple[str, ...], Namespace, Handler]:
    """Parse `argv` (without the program name): the command path, the command's namespace
    and its handler. Exits with code 2 on a bad argument (the message names it)."""
    parser, commands = build_parser()
    argv = list(argv)
    for n in range(min(len(argv), 2), 0, -1):  # flags of the command: its own spellings
        if tuple(argv[:n]) in commands:
            leaf = commands[tuple(argv[:n])][0]
            _LAST[tuple(argv[:n])] = leaf
            argv = argv[:n] + normalize_argv(argv[n:], leaf, getattr(leaf, "aliases", None))
            break
    path, ns = command_path(parser.parse_args(argv))
    return path, ns, commands[path][1]


def _spelled(path: tuple[str, ...], field: str) -> str:
    """The option of a configuration field as the user gave it."""
    parser = _LAST.get(path)
    option = field if field.startswith("--") else f"--{field}"
    return parser.spelled.get(option, option) if isinstance(parser, Parser) else option


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``a2l`` command; returns the exit code."""
    argv = sys.argv[1:] if argv is None else list(argv)
    path, ns, handler = parse(argv)
    prog = " ".join(("a2l", *path))
    try:
        return int(handler(ns) or 0)
    except UsageError as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        raise SystemExit(2) from None
    except ConfigError as exc:
        print(f"{prog}: error: argument {_spelled(path, exc.field)}: {exc.message}",
              file=sys.stderr)
        raise SystemExit(2) from None
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
