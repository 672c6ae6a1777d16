"""The ``a2l`` command.

Subcommands
-----------
demo
    The main job (see ``a2l demo --help``).
experiment push
    The A2L push experiment (see ``a2l experiment push --help``).
experiment discretization
    The orientation x distance discretization study.
experiment sweep
    The push experiment over many seeds: iterations to reach score 100.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path


def _cmd_demo(args: argparse.Namespace) -> int:
    from a2l.demo import run_demo

    return run_demo(seed=args.seed, gui=args.gui, out=args.out, iterations=args.iterations,
                    starts=args.starts, workers=args.workers)


class UsageError(Exception):
    """A bad command-line argument found after parsing (exit code 2, no traceback).

    Parameters
    ----------
    argument : str
        The argument at fault (``--resume``...).
    message : str
        What is wrong with it.
    """

    def __init__(self, argument: str, message: str) -> None:
        super().__init__(f"argument {argument}: {message}")
        self.argument = argument


def _positive_int(text: str) -> int:
    """argparse type: an integer >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value}")
    return value


def _nonnegative_int(text: str) -> int:
    """argparse type: an integer >= 0 (seeds)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer >= 0, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected an integer >= 0, got {value}")
    return value


#: ``a2l experiment push`` options that set the run's configuration (not allowed with
#: ``--resume``: the interrupted run's ``config.json`` is used), with their config field.
_PUSH_CONFIG_OPTIONS = {"scene": "scene", "effects": "n_effects", "seed": "seed",
                        "iterations": "max_iterations", "starts": "n_starts"}


def _framework_config(args: argparse.Namespace, options: dict[str, str]) -> object:
    """The FrameworkConfig of the given options (defaults for the others).

    Raises
    ------
    UsageError
        A value out of its domain (the message names the option).
    """
    from a2l.framework import FrameworkConfig

    given = {field: getattr(args, opt) for opt, field in options.items()
             if getattr(args, opt, None) is not None}
    cfg = FrameworkConfig(**given)
    try:
        cfg.validate()
    except ValueError as exc:
        bad = str(exc).split(":", 1)[0]
        opt = next((o for o, f in options.items() if f == bad), bad)
        raise UsageError(f"--{opt}", str(exc)) from None
    return cfg


def _check_cluster(address: str | None) -> None:
    """Fail early, as a usage error, if the Dask scheduler at `address` is unreachable."""
    if address is None:
        return
    from a2l.parallel import Executor

    try:
        Executor(cluster=address).close()
    except ConnectionError as exc:  # the Executor's message names the address
        raise UsageError("--cluster", str(exc)) from None
    except (OSError, ValueError, TypeError) as exc:  # e.g. a malformed address
        raise UsageError("--cluster", f"cannot reach a Dask scheduler at {address!r}: "
                         f"{exc}") from None


def _cmd_experiment_push(args: argparse.Namespace) -> int:
    from a2l.experiments.push import run_push_experiment

    if args.resume is not None:
        given = [f"--{o}" for o in _PUSH_CONFIG_OPTIONS if getattr(args, o) is not None]
        if args.out is not None:
            given.append("--out")
        if given:
            raise UsageError(given[0], "not allowed with --resume (the run continues with "
                             "its own config.json, in its own directory)")
        resume = Path(args.resume)
        if not resume.is_dir():
            raise UsageError("--resume", f"'{resume}' is not a directory")
        if not (resume / "config.json").is_file():
            raise UsageError("--resume", f"'{resume}' holds no config.json: not a push run "
                             "directory")
        _check_cluster(args.cluster)
        run_push_experiment(resume=resume, workers=args.workers, cluster=args.cluster,
                            quiet=args.quiet)
        return 0
    cfg = _framework_config(args, _PUSH_CONFIG_OPTIONS)
    if args.out is not None:
        out = Path(args.out)
        if out.exists() and not out.is_dir():
            raise UsageError("--out", f"'{out}' exists and is not a directory")
        if (out / "metrics.json").exists() or any((out / "checkpoints").glob("iter_*")):
            raise UsageError("--out", f"'{out}' already holds a run; continue it with "
                             f"--resume {out}, or choose another directory")
    _check_cluster(args.cluster)
    run_push_experiment(cfg, out=args.out, workers=args.workers, cluster=args.cluster,
                        quiet=args.quiet)
    return 0


def _cmd_experiment_discretization(args: argparse.Namespace) -> int:
    from a2l.experiments.push import run_discretization_study

    options = {"scene": "scene", "effects": "n_effects", "seed": "seed",
               "iterations": "max_iterations"}
    cfg = _framework_config(args, options)
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise UsageError("--out", f"'{out}' exists and is not a directory")
    run_discretization_study(out=out, base=cfg, workers=args.workers, quiet=args.quiet)
    return 0


def _cmd_experiment_sweep(args: argparse.Namespace) -> int:
    import dataclasses
    import shlex

    from a2l.experiments.sweep import parse_overrides, parse_seeds, run_seed_sweep

    options = {"scene": "scene", "effects": "n_effects", "iterations": "max_iterations",
               "starts": "n_starts"}
    try:
        seeds = parse_seeds(args.seeds)
    except ValueError as exc:
        raise UsageError("--seeds", str(exc)) from None
    try:
        overrides = parse_overrides(args.set)
    except ValueError as exc:
        raise UsageError("--set", str(exc)) from None
    cfg = _framework_config(args, options)
    try:
        dataclasses.replace(cfg, **overrides).validate()  # type: ignore[type-var]
    except (TypeError, ValueError) as exc:
        raise UsageError("--set", str(exc)) from None
    out = Path(args.out) if args.out is not None else None
    if out is not None and out.exists() and not out.is_dir():
        raise UsageError("--out", f"'{out}' exists and is not a directory")
    command = ["a2l", "experiment", "sweep", "--seeds", args.seeds]
    for opt in options:
        if getattr(args, opt) is not None:
            command += [f"--{opt}", str(getattr(args, opt))]
    for item in args.set:
        command += ["--set", item]
    if out is not None:
        command += ["--out", str(out)]
    try:
        run_seed_sweep(cfg, seeds, overrides, out=out, workers=args.workers,  # type: ignore[arg-type]
                       quiet=args.quiet, command=shlex.join(command))
    except ValueError as exc:  # out holds a sweep of another configuration
        raise UsageError("--out", str(exc)) from None
    return 0


def _add_experiment_parsers(sub: argparse._SubParsersAction) -> None:
    """The ``experiment`` subcommand and its experiments."""
    experiment = sub.add_parser("experiment", help="run an A2L experiment (run directory "
                                "with config, metrics, plots, report)")
    exps = experiment.add_subparsers(dest="experiment", required=True, metavar="EXPERIMENT")

    push = exps.add_parser(
        "push", help="the iterative framework on the push effects",
        description="Learn the push effects with the A2L iterative framework (babbling, "
        "skill generation, closed-loop validation through the C++ step) and write the run "
        "directory: config.json, metrics.json, dataset.parquet, skills/push.a2lb, plots, "
        "report.md. Checkpoints after every iteration; --resume DIR continues an "
        "interrupted run.")
    push.add_argument("--scene", choices=("virtual", "baxter"), default=None,
                      help="virtual (kinematic push model) or baxter (PyBullet); "
                      "default virtual")
    push.add_argument("--effects", type=int, choices=(4, 8), default=None,
                      help="push effects to learn (default 4)")
    push.add_argument("--seed", type=_nonnegative_int, default=None,
                      help="random seed (default 0)")
    push.add_argument("--out", metavar="DIR", default=None,
                      help="run directory (default runs/push-<scene>-<timestamp>)")
    push.add_argument("--workers", type=_positive_int, default=1, metavar="N",
                      help="local worker processes for the rollouts (default 1)")
    push.add_argument("--cluster", metavar="ADDRESS", default=None,
                      help="Dask scheduler address (tcp://host:port); rollouts run there")
    push.add_argument("--resume", metavar="DIR", default=None,
                      help="continue the interrupted run in DIR (from its last checkpoint)")
    push.add_argument("--iterations", type=_positive_int, default=None, metavar="N",
                      help="iteration cap, iteration 0 included (default 10)")
    push.add_argument("--starts", type=_positive_int, default=None, metavar="N",
                      help="start positions around the object (default 8)")
    push.add_argument("--quiet", action="store_true", help="no progress bar, no table")
    push.set_defaults(func=_cmd_experiment_push)

    disc = exps.add_parser(
        "discretization", help="orientation x distance discretization study",
        description="Run the push experiment for orientation bins {8, 16, 24, 32} x "
        "distance bins {3, 4, 5}; write a table of final score, iterations and movements "
        "per action, and the default it selects.")
    disc.add_argument("--out", metavar="DIR", required=True, help="study directory")
    disc.add_argument("--scene", choices=("virtual", "baxter"), default=None,
                      help="scene (default virtual)")
    disc.add_argument("--effects", type=int, choices=(4, 8), default=None,
                      help="push effects (default 4)")
    disc.add_argument("--seed", type=_nonnegative_int, default=None,
                      help="random seed (default 0)")
    disc.add_argument("--workers", type=_positive_int, default=1, metavar="N",
                      help="local worker processes for the rollouts (default 1)")
    disc.add_argument("--iterations", type=_positive_int, default=None, metavar="N",
                      help="iteration cap of each run (default 10)")
    disc.add_argument("--quiet", action="store_true", help="no per-run lines")
    disc.set_defaults(func=_cmd_experiment_discretization)

    sweep = exps.add_parser(
        "sweep", help="the push experiment over many seeds: iterations to reach 100",
        description="Run the push experiment once per seed with one configuration and write "
        "how many iterations (iteration 0 included) each seed needed to reach score 100: "
        "metrics.json, report.md (the table of docs/framework.md) and one run directory per "
        "seed. Run again with the same --out to continue an interrupted sweep.")
    sweep.add_argument("--seeds", default="0-29", metavar="LIST",
                       help="seeds, e.g. 0-29 or 0,3,7 (default 0-29)")
    sweep.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE",
                       help="change a FrameworkConfig field, e.g. directed_per_pair=20 "
                       "(repeatable; VALUE read as JSON, else as text)")
    sweep.add_argument("--out", metavar="DIR", default=None,
                       help="sweep directory (default runs/sweep-<timestamp>)")
    sweep.add_argument("--scene", choices=("virtual", "baxter"), default=None,
                       help="scene (default virtual)")
    sweep.add_argument("--effects", type=int, choices=(4, 8), default=None,
                       help="push effects (default 4)")
    sweep.add_argument("--iterations", type=_positive_int, default=None, metavar="N",
                       help="iteration cap of each run (default 10)")
    sweep.add_argument("--starts", type=_positive_int, default=None, metavar="N",
                       help="start positions around the object (default 8)")
    sweep.add_argument("--workers", type=_positive_int, default=1, metavar="N",
                       help="local worker processes for each run's rollouts (default 1)")
    sweep.add_argument("--quiet", action="store_true", help="no line per seed")
    sweep.set_defaults(func=_cmd_experiment_sweep)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``a2l`` command (one sub-parser per subcommand)."""
    parser = argparse.ArgumentParser(
        prog="a2l",
        description="Adaptive Affordance Learning: learn manipulation skills and run them.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    demo = sub.add_parser(
        "demo", help="run the main job: the world, a short A2L push experiment on Baxter, "
        "then the exported skill in the C++ runtime (a2l-run)")
    demo.add_argument("--seed", type=_nonnegative_int, default=0,
                      help="random seed (default 0)")
    demo.add_argument("--gui", action="store_true", help="open the PyBullet GUI (part 1)")
    demo.add_argument("--out", metavar="DIR", default=None,
                      help="run directory of the experiment (default runs/demo-<timestamp>)")
    demo.add_argument("--iterations", type=_positive_int, default=2, metavar="N",
                      help="iterations of the push experiment (default 2)")
    demo.add_argument("--starts", type=_positive_int, default=8, metavar="N",
                      help="start positions of the push experiment (default 8)")
    demo.add_argument("--workers", type=_positive_int, default=None, metavar="N",
                      help="worker processes for the rollouts (default: up to 2)")
    demo.set_defaults(func=_cmd_demo)
    _add_experiment_parsers(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``a2l`` command; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except UsageError as exc:
        parser.exit(2, f"{parser.prog}: error: {exc}\n")
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
