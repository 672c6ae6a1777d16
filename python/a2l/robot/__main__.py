"""``python -m a2l.robot --robots-dir | --baxter | --baxter-pybullet | --export ROBOT [--out
FILE]``: print where robot descriptions are, or write a robot resolved for ``a2l-run
--robot`` (:mod:`a2l.robot.export`)."""

from __future__ import annotations

import argparse
import json
import sys

from a2l.errors import A2LError
from a2l.robot import baxter_urdf, pybullet_urdf, robots_dir
from a2l.robot.export import export_robot, resolved_robot


def main(argv: list[str] | None = None) -> int:
    """Run the command (`argv` without the program name); the exit code."""
    parser = argparse.ArgumentParser(prog="python -m a2l.robot", description=__doc__)
    g = parser.add_mutually_exclusive_group(required=True)
    g.add_argument("--robots-dir", action="store_true", help="example-robot-data's robots/")
    g.add_argument("--baxter", action="store_true", help="Baxter's URDF")
    g.add_argument("--baxter-pybullet", action="store_true", help="PyBullet-loadable copy")
    g.add_argument("--export", metavar="ROBOT", help="a built-in robot's name or a robot "
                   "file: write it resolved for a2l-run --robot (JSON)")
    parser.add_argument("--out", metavar="FILE.json", help="with --export: the file to write "
                        "(default: standard output)")
    args = parser.parse_args(argv)
    if args.out is not None and args.export is None:
        parser.error("--out: only with --export")
    if args.robots_dir:
        print(robots_dir())
    elif args.baxter:
        print(baxter_urdf())
    elif args.baxter_pybullet:
        print(pybullet_urdf())
    else:
        try:
            if args.out is None:
                print(json.dumps(resolved_robot(args.export), indent=2))
            else:
                print(export_robot(args.export, args.out))
        except A2LError as exc:
            print(f"python -m a2l.robot: error: {exc}", file=sys.stderr)
            return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
