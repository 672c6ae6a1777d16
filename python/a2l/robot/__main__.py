"""``python -m a2l.robot --robots-dir | --baxter``: print where robot descriptions are."""

from __future__ import annotations

import argparse

from a2l.robot import baxter_urdf, pybullet_urdf, robots_dir


def main() -> None:
    parser = argparse.ArgumentParser(prog="python -m a2l.robot", description=__doc__)
    g = parser.add_mutually_exclusive_group(required=True)
    g.add_argument("--robots-dir", action="store_true", help="example-robot-data's robots/")
    g.add_argument("--baxter", action="store_true", help="Baxter's URDF")
    g.add_argument("--baxter-pybullet", action="store_true", help="PyBullet-loadable copy")
    args = parser.parse_args()
    if args.robots_dir:
        print(robots_dir())
    elif args.baxter:
        print(baxter_urdf())
    else:
        print(pybullet_urdf())


if __name__ == "__main__":
    main()
