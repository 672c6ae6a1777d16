"""The ``a2l`` command.

Subcommands
-----------
demo
    The main job (see ``a2l demo --help``).
demo-record
    Record demonstrations by teleoperation in the PyBullet GUI (keys: a2l.lfd.teleop).
experiment push
    The A2L push experiment (see ``a2l experiment push --help``).
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

Layout: ``args`` (usage error, argument types), ``demo`` (demo, demo-record),
``experiments`` (the ``experiment`` group; lasa, babbling), ``push`` (push, discretization,
sweep), ``lfd`` (lfd-skills, parametrization, perturbations), ``tasks``. Every argument is
parsed here; the experiments raise :class:`a2l.errors.ConfigError` naming the argument at
fault, which :func:`main` reports as a usage error (exit code 2).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from a2l.cli import demo, experiments
from a2l.cli.args import UsageError
from a2l.errors import ConfigError

__all__ = ["UsageError", "build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``a2l`` command (one sub-parser per subcommand)."""
    parser = argparse.ArgumentParser(
        prog="a2l",
        description="Adaptive Affordance Learning: learn manipulation skills and run them.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    demo.add_demo_parser(sub)
    demo.add_demo_record_parser(sub)
    experiments.add_experiment_parsers(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``a2l`` command; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except UsageError as exc:
        parser.exit(2, f"{parser.prog}: error: {exc}\n")
    except ConfigError as exc:
        parser.exit(2, f"{parser.prog}: error: argument {exc.field}: {exc.message}\n")
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
