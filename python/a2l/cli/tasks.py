"""``a2l experiment tasks``: planned tasks with the learned skills (a2l.experiments.tasks)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from jsonargparse import Namespace
from jsonargparse.typing import NonNegativeInt, PositiveInt

from a2l.cli.args import check_record, comma_list
from a2l.cli.parser import Parser, add_config_option
from a2l.experiments.tasks import DEFAULT_SEED, TASKS
from a2l.robot import DEFAULT_ROBOT


def _cmd_tasks(args: Namespace) -> int:
    # imported here: `a2l --help` and the other commands do not load the planner's stack
    from a2l.experiments.tasks import run_tasks

    faults = {"both": (False, True), "without": (False,), "with": (True,)}[args.faults]
    if args.record is not None:
        check_record(Path(args.record))
    run_tasks(args.out, comma_list(args.tasks), args.trials, args.seed, args.workers, faults,
              args.planner, quiet=args.quiet, plots=not args.no_plots,
              context_source=args.context_source, record=args.record, robot=args.robot)
    return 0


TASKS_HELP = "planned tasks with the learned skills, with and without faults"


def add_tasks_parser(exps: Any, commands: dict[tuple[str, ...], Any]) -> None:
    """Register ``a2l experiment tasks``."""
    p = Parser(
        prog="a2l experiment tasks",
        description="Plan and run tasks of 3 to 5 skills on Baxter (or --robot) in PyBullet "
        "(PDDL plan, OMPL transits, the learned grasp and press through the C++ step, "
        "replanning when the world disagrees), each from seeded trials without and with an "
        "injected fault; "
        "write metrics.json, trials.csv, report.md and tasks.png.")
    p.add_argument("--out", metavar="DIR", required=True, help="run directory")
    p.add_argument("--tasks", metavar="A,B,...", default=None,
                   help=f"comma-separated tasks (default: all of {','.join(TASKS)})")
    p.add_argument("--trials", type=PositiveInt, default=20, metavar="N",
                   help="trials per task and condition (default 20)")
    p.add_argument("--seed", type=NonNegativeInt, default=DEFAULT_SEED, metavar="S",
                   help=f"first trial seed (default {DEFAULT_SEED})")
    p.add_argument("--workers", type=PositiveInt, default=1, metavar="N",
                   help="local worker processes (default 1)")
    p.add_argument("--faults", choices=("both", "without", "with"), default="both",
                   help="run the trials without and/or with the injected fault (default both)")
    p.add_argument("--planner", choices=("pyperplan", "fast-downward"), default="pyperplan",
                   help="task planner (default pyperplan)")
    p.add_argument("--context_source", choices=("perceived", "ground_truth"),
                   default="perceived", help="where the skills and the planner read the "
                   "scene: the camera (perceived, default) or the simulator's ground truth")
    p.add_argument("--robot", metavar="ROBOT", default=DEFAULT_ROBOT,
                   help="the robot of the task scenes: a built-in robot (baxter, panda...) "
                   "or a robot file; the transits are planned for its arm")
    p.add_argument("--record", metavar="FILE.rrd", default=None,
                   help="write every trial's executed plan steps to a Rerun recording, "
                   "<task>/<fault|no_fault>/rollout/<i>/ (a2l view FILE.rrd)")
    p.add_argument("--no-plots", action="store_true", help="no figure")
    p.add_argument("--quiet", action="store_true", help="no progress bar, no table")
    add_config_option(p)
    exps.add_subcommand("tasks", p, help=TASKS_HELP)
    commands[("experiment", "tasks")] = (p, _cmd_tasks)
