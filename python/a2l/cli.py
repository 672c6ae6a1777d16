"""The ``a2l`` command.

Subcommands
-----------
demo
    The main job (see ``a2l demo --help``).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence


def _cmd_demo(args: argparse.Namespace) -> int:
    from a2l.demo import run_demo

    return run_demo(seed=args.seed, gui=args.gui)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``a2l`` command (one sub-parser per subcommand)."""
    parser = argparse.ArgumentParser(
        prog="a2l",
        description="Adaptive Affordance Learning: learn manipulation skills and run them.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    demo = sub.add_parser("demo", help="run the main demonstration job")
    demo.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    demo.add_argument("--gui", action="store_true", help="open the PyBullet GUI")
    demo.set_defaults(func=_cmd_demo)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``a2l`` command; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
