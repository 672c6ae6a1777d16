"""``a2l experiment push``, ``discretization`` and ``sweep``: the framework on the push effects."""

from __future__ import annotations

import argparse
from pathlib import Path

from a2l.cli.args import (
    UsageError,
    check_cluster,
    framework_config,
    nonnegative_int,
    positive_int,
)

#: ``a2l experiment push`` options that set the run's configuration (not allowed with
#: ``--resume``: the interrupted run's ``config.json`` is used), with their config field.
PUSH_CONFIG_OPTIONS = {"scene": "scene", "effects": "n_effects", "seed": "seed",
                        "iterations": "max_iterations", "starts": "n_starts",
                        "heldout_starts": "heldout_starts"}


def _cmd_experiment_push(args: argparse.Namespace) -> int:
    from a2l.experiments.push import run_push_experiment

    if args.resume is not None:
        given = [f"--{o.replace('_', '-')}" for o in PUSH_CONFIG_OPTIONS
                 if getattr(args, o) is not None]
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
        check_cluster(args.cluster)
        if args.acquisition is not None:
            raise UsageError("--acquisition", "not allowed with --resume (the run continues "
                             "with its own config.json)")
        run_push_experiment(resume=resume, workers=args.workers, cluster=args.cluster,
                            quiet=args.quiet)
        return 0
    cfg = framework_config(args, PUSH_CONFIG_OPTIONS)
    if args.acquisition == "noveb" and cfg.scene != "baxter":  # type: ignore[attr-defined]
        raise UsageError("--acquisition", "noveb sees the world through a camera: use "
                         "--scene baxter (the virtual scene has none)")
    if args.out is not None:
        out = Path(args.out)
        if out.exists() and not out.is_dir():
            raise UsageError("--out", f"'{out}' exists and is not a directory")
        if (out / "metrics.json").exists() or any((out / "checkpoints").glob("iter_*")):
            raise UsageError("--out", f"'{out}' already holds a run; continue it with "
                             f"--resume {out}, or choose another directory")
    check_cluster(args.cluster)
    run_push_experiment(cfg, out=args.out, workers=args.workers, cluster=args.cluster,
                        quiet=args.quiet, acquisition=args.acquisition or "random",
                        noveb_evaluations=args.noveb_evaluations)
    return 0


def _cmd_experiment_discretization(args: argparse.Namespace) -> int:
    from a2l.experiments.discretization import run_discretization_study

    options = {"scene": "scene", "effects": "n_effects", "seed": "seed",
               "iterations": "max_iterations"}
    cfg = framework_config(args, options)
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
    cfg = framework_config(args, options)
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


def add_push_parser(exps: argparse._SubParsersAction) -> None:
    """``experiment push``."""
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
    push.add_argument("--seed", type=nonnegative_int, default=None,
                      help="random seed (default 0)")
    push.add_argument("--out", metavar="DIR", default=None,
                      help="run directory (default runs/push-<scene>-<timestamp>)")
    push.add_argument("--workers", type=positive_int, default=1, metavar="N",
                      help="local worker processes for the rollouts (default 1)")
    push.add_argument("--cluster", metavar="ADDRESS", default=None,
                      help="Dask scheduler address (tcp://host:port); rollouts run there")
    push.add_argument("--resume", metavar="DIR", default=None,
                      help="continue the interrupted run in DIR (from its last checkpoint)")
    push.add_argument("--iterations", type=positive_int, default=None, metavar="N",
                      help="iteration cap, iteration 0 included (default 10)")
    push.add_argument("--starts", type=positive_int, default=None, metavar="N",
                      help="start positions around the object (default 8)")
    push.add_argument("--heldout-starts", type=nonnegative_int, default=None, metavar="N",
                      help="held-out start positions each iteration's skill is also scored "
                      "from, never trained from (default 32; 0: none)")
    push.add_argument("--acquisition", choices=("random", "noveb"), default=None,
                      help="iteration 0's interactions: random babbling around the object "
                      "(default) or NovEB over the reachable table, on camera images only "
                      "(PyBullet scene only)")
    push.add_argument("--noveb-evaluations", type=positive_int, default=200, metavar="N",
                      help="NovEB's trajectories with --acquisition noveb (default 200)")
    push.add_argument("--quiet", action="store_true", help="no progress bar, no table")
    push.set_defaults(func=_cmd_experiment_push)


def add_discretization_parser(exps: argparse._SubParsersAction) -> None:
    """``experiment discretization``."""
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
    disc.add_argument("--seed", type=nonnegative_int, default=None,
                      help="random seed (default 0)")
    disc.add_argument("--workers", type=positive_int, default=1, metavar="N",
                      help="local worker processes for the rollouts (default 1)")
    disc.add_argument("--iterations", type=positive_int, default=None, metavar="N",
                      help="iteration cap of each run (default 10)")
    disc.add_argument("--quiet", action="store_true", help="no per-run lines")
    disc.set_defaults(func=_cmd_experiment_discretization)


def add_sweep_parser(exps: argparse._SubParsersAction) -> None:
    """``experiment sweep``."""
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
    sweep.add_argument("--iterations", type=positive_int, default=None, metavar="N",
                       help="iteration cap of each run (default 10)")
    sweep.add_argument("--starts", type=positive_int, default=None, metavar="N",
                       help="start positions around the object (default 8)")
    sweep.add_argument("--workers", type=positive_int, default=1, metavar="N",
                       help="local worker processes (default 1): with at least N seeds "
                       "to run, N seeds at once, each in its own process; with fewer, the "
                       "runs share them as rollout workers")
    sweep.add_argument("--quiet", action="store_true", help="no line per seed")
    sweep.set_defaults(func=_cmd_experiment_sweep)
