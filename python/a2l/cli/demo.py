"""``a2l demo`` and ``a2l demo-record``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from jsonargparse import Namespace
from jsonargparse.typing import NonNegativeInt, PositiveInt

from a2l.cli.args import UsageError
from a2l.cli.parser import Parser, add_config_option


def _cmd_demo(args: Namespace) -> int:
    # imported here: parsing and --help do not load this command's stack
    from a2l.experiments.demo import run_demo

    return run_demo(seed=args.seed, gui=args.gui, out=args.out, iterations=args.iterations,
                    starts=args.starts, workers=args.workers)


def _cmd_demo_record(args: Namespace) -> int:
    # imported here: parsing and --help do not load this command's stack
    from a2l.lfd.teleop import record_demonstrations

    start = None
    if args.start is not None:
        try:
            start = [float(v) for v in args.start.split(",")]
        except ValueError:
            start = []
        if len(start) != 3:
            raise UsageError("--start", f"expected DX,DY,DZ (3 numbers, m), got {args.start!r}")
    keys = None
    if args["keys"] is not None:
        keys = [k for k in args["keys"].split(",") if k.strip()]
    if not 0 < args.step <= 0.1:
        raise UsageError("--step", f"must be in (0, 0.1] m, got {args.step}")
    out = Path(args.out)
    if out.suffix.lower() not in (".csv", ".parquet", ".pq"):
        raise UsageError("--out", f"'{out}': use a .csv or .parquet file")
    try:
        rec = record_demonstrations(args.scene, out, seed=args.seed, keys=keys, start=start,
                                    step=args.step)
    except ValueError as exc:
        raise UsageError("--keys" if keys is not None else "--scene", str(exc)) from None
    return 0 if rec.recordings else 1


def _demo_record_parser() -> Parser:
    """``demo-record``: demonstrations by teleoperation."""
    rec = Parser(
        prog="a2l demo-record",
        description="Move Baxter's end-effector with the keyboard in the PyBullet GUI and "
        "record demonstrations (the part-1 demonstration format, relative to the object). "
        "Keys: arrows = x/y, Page Up/Down = z (1 cm steps), Space = gripper, Return = "
        "start/stop recording, q = save and quit.")
    rec.add_argument("--scene", choices=("grasp", "grasp_light", "press", "push"),
                     required=True, help="the scene to demonstrate in")
    rec.add_argument("--out", metavar="FILE", required=True,
                     help="demonstration file to write (.csv or .parquet)")
    rec.add_argument("--seed", type=NonNegativeInt, default=0, help="scene seed (default 0)")
    rec.add_argument("--step", type=float, default=0.01, metavar="M",
                     help="length of one move (default 0.01 m)")
    rec.add_argument("--start", metavar="DX,DY,DZ", default=None,
                     help="start the end-effector here relative to the object (m; default: "
                     "the neutral pose)")
    rec.add_argument("--keys", metavar="CMD,CMD,...", default=None,
                     help="no GUI: run these commands instead of reading the keyboard "
                     "(forward, back, left, right, up, down, gripper, record, quit; "
                     "'down*5' repeats)")
    return rec


DEMO_HELP = ("run the main job: the world, a short A2L push experiment on Baxter, then the "
             "exported skill in the C++ runtime (a2l-run)")


def _demo_parser() -> Parser:
    """``demo``: the main job."""
    demo = Parser(prog="a2l demo", description=DEMO_HELP)
    demo.add_argument("--seed", type=NonNegativeInt, default=0,
                      help="random seed (default 0)")
    demo.add_argument("--gui", action="store_true", help="open the PyBullet GUI (part 1)")
    demo.add_argument("--out", metavar="DIR", default=None,
                      help="run directory of the experiment (default runs/demo-<timestamp>)")
    demo.add_argument("--iterations", type=PositiveInt, default=3, metavar="N",
                      help="iterations of the push experiment (default 3)")
    demo.add_argument("--starts", type=PositiveInt, default=8, metavar="N",
                      help="start positions of the push experiment (default 8)")
    demo.add_argument("--workers", type=PositiveInt | None, default=None, metavar="N",
                      help="worker processes for the rollouts (default: up to 2)")
    return demo


def add_demo_parsers(sub: Any, commands: dict[tuple[str, ...], Any]) -> None:
    """Register ``demo`` and ``demo-record`` (parser and handler in `commands`)."""
    for name, parser, handler, help_ in (
            ("demo", _demo_parser(), _cmd_demo, DEMO_HELP),
            ("demo-record", _demo_record_parser(), _cmd_demo_record,
             "record demonstrations by teleoperation in the PyBullet GUI")):
        add_config_option(parser)
        sub.add_subcommand(name, parser, help=help_)
        commands[(name,)] = (parser, handler)
