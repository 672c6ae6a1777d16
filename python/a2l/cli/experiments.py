"""``a2l experiment``: the sub-parser of every experiment; ``lasa`` and ``babbling`` here."""

from __future__ import annotations

import argparse
from pathlib import Path

from a2l.cli import lfd, push, tasks
from a2l.cli.args import UsageError, check_cluster, nonnegative_int, positive_int


def _cmd_experiment_lasa(args: argparse.Namespace) -> int:
    from a2l.experiments.lasa import LasaConfig, lasa_shapes, run_lasa_experiment

    shapes = None
    if args.shapes:
        shapes = [s.strip() for s in args.shapes.split(",") if s.strip()]
        unknown = [s for s in shapes if s not in lasa_shapes()]
        if unknown or not shapes:
            raise UsageError("--shapes", f"unknown shape(s) {unknown}; known: "
                             f"{', '.join(lasa_shapes())}")
    try:
        arrival = {} if args.arrival is None else {"arrival": args.arrival}
        direction = {} if args.direction is None else {"direction": args.direction}
        cfg = LasaConfig(K=args.K, beta=args.beta, mu=args.mu, n_starts=args.starts,
                         seed=args.seed, **arrival, **direction)
        cfg.validate()
    except ValueError as exc:
        raise UsageError("--K/--beta/--mu/--arrival/--direction", str(exc)) from None
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise UsageError("--out", f"'{out}' exists and is not a directory")
    run_lasa_experiment(cfg, out=out, shapes=shapes, workers=args.workers, quiet=args.quiet)
    return 0


def _add_lasa_parser(exps: argparse._SubParsersAction) -> None:
    lasa = exps.add_parser(
        "lasa", help="the diffeomorphic DS on the LASA handwriting benchmark",
        description="Fit one diffeomorphic DS per LASA shape (fast diffeomorphic matching) "
        "and compare it with a DMP and the linear DS: DTW, swept error area, velocity RMSE, "
        "fit and query time, convergence from random starts. Writes config.json, "
        "metrics.json, report.md, lasa.png and one DS bundle per shape.")
    lasa.add_argument("--out", metavar="DIR", required=True, help="run directory")
    lasa.add_argument("--shapes", metavar="A,B,...", default=None,
                      help="comma-separated shape names (default: all 30)")
    lasa.add_argument("--K", type=positive_int, default=150, help="maps (default 150)")
    lasa.add_argument("--beta", type=float, default=None,
                      help="fraction of the largest error one map corrects (default: the "
                      "original implementation's schedule, 1/3 -> 0.9 over the maps)")
    lasa.add_argument("--mu", type=float, default=None,
                      help="safety factor of the invertibility bound (default: a schedule "
                      "0.8 -> 0.65 over the maps)")
    lasa.add_argument("--arrival", type=float, default=None, metavar="F",
                      help="fraction of its line-space distance a reproduction has left at the "
                      "demonstrations' end: sets the DS's speed (default 0.001)")
    lasa.add_argument("--direction", choices=("auto", "to_line", "to_demo"), default=None,
                      help="which way the maps are fitted: to_line (the demonstration onto "
                      "the line: explicit velocity queries), to_demo (the paper's: the line "
                      "onto the demonstration, queries solve K scalar equations) or auto "
                      "(to_line unless its fit leaves a large error; default)")
    lasa.add_argument("--starts", type=positive_int, default=10_000, metavar="N",
                      help="random starts per shape for the convergence test (default 10000)")
    lasa.add_argument("--seed", type=nonnegative_int, default=0,
                      help="seed of the random starts (default 0)")
    lasa.add_argument("--workers", type=positive_int, default=1, metavar="N",
                      help="local worker processes, one shape each (default 1)")
    lasa.add_argument("--quiet", action="store_true", help="no progress bar, no table")
    lasa.set_defaults(func=_cmd_experiment_lasa)


def _cmd_experiment_babbling(args: argparse.Namespace) -> int:
    from a2l.experiments.babbling import run_babbling

    if args.out is not None:
        out = Path(args.out)
        if out.exists() and not out.is_dir():
            raise UsageError("--out", f"'{out}' exists and is not a directory")
        if (out / "metrics.json").exists():
            raise UsageError("--out", f"'{out}' already holds a run; choose another directory")
    check_cluster(args.cluster)
    run_babbling(args.method, args.evaluations, args.seed, args.scene, out=args.out,
                 workers=args.workers, cluster=args.cluster,
                 generation_size=args.generation_size, quiet=args.quiet)
    return 0


def _cmd_experiment_babbling_compare(args: argparse.Namespace) -> int:
    from a2l.experiments.babbling_compare import run_babbling_compare

    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise UsageError("--out", f"'{out}' exists and is not a directory")
    check_cluster(args.cluster)
    run_babbling_compare(args.scene, args.evaluations, list(range(args.seeds)), out=out,
                         methods=tuple(args.methods), workers=args.workers,
                         cluster=args.cluster, generation_size=args.generation_size,
                         quiet=args.quiet)
    return 0


def _add_babbling_parsers(exps: argparse._SubParsersAction) -> None:
    """``experiment babbling`` and ``experiment babbling-compare``."""
    bab = exps.add_parser(
        "babbling", help="one exploration method on Baxter's push scenes",
        description="Explore with NovEB (novelty-driven evolutionary babbling, on camera "
        "images only), random motor babbling or random goal babbling, with the same "
        "trajectory encoding and budget; write the run directory: config.json, "
        "metrics.json (per generation: moved_share, distinct_outcomes, archive_size), "
        "evaluations.parquet, paths.npz, visits.png, progress.png, report.md.")
    cmp_ = exps.add_parser(
        "babbling-compare", help="every exploration method over several seeds",
        description="Run the babbling experiment for each method and seed (<out>/<method>-"
        "s<seed>; finished runs are reused) and write the side-by-side plots and the table "
        "of means and spreads over seeds.")
    bab.add_argument("--method", choices=("noveb", "random", "goal"), required=True,
                     help="exploration method")
    cmp_.add_argument("--methods", nargs="+", choices=("noveb", "random", "goal"),
                      default=["noveb", "random", "goal"], help="methods (default all three)")
    bab.add_argument("--seed", type=nonnegative_int, default=0, help="random seed (default 0)")
    cmp_.add_argument("--seeds", type=positive_int, default=5, metavar="N",
                      help="seeds 0 .. N-1 (default 5)")
    bab.add_argument("--out", metavar="DIR", default=None,
                     help="run directory (default runs/babbling-<method>-<scene>-<timestamp>)")
    cmp_.add_argument("--out", metavar="DIR", required=True, help="comparison directory")
    for p in (bab, cmp_):
        p.add_argument("--evaluations", type=positive_int, default=2000, metavar="N",
                       help="trajectories played per run (default 2000)")
        p.add_argument("--scene", choices=("push", "two_objects"), default="push",
                       help="one box, or two boxes far apart (default push)")
        p.add_argument("--generation-size", type=positive_int, default=20, metavar="N",
                       help="evaluations per generation (NovEB's mu and lambda; default 20)")
        p.add_argument("--workers", type=positive_int, default=1, metavar="N",
                       help="local worker processes for the evaluations (default 1)")
        p.add_argument("--cluster", metavar="ADDRESS", default=None,
                       help="Dask scheduler address (tcp://host:port); evaluations run there")
        p.add_argument("--quiet", action="store_true", help="no progress bar")
    bab.set_defaults(func=_cmd_experiment_babbling)
    cmp_.set_defaults(func=_cmd_experiment_babbling_compare)


def add_experiment_parsers(sub: argparse._SubParsersAction) -> None:
    """The ``experiment`` subcommand and its experiments."""
    experiment = sub.add_parser("experiment", help="run an A2L experiment (run directory "
                                "with config, metrics, plots, report)")
    exps = experiment.add_subparsers(dest="experiment", required=True, metavar="EXPERIMENT")
    lfd.add_lfd_skills_parser(exps)
    lfd.add_parametrization_parser(exps)
    lfd.add_perturbations_parser(exps)
    tasks.add_tasks_parser(exps)

    push.add_push_parser(exps)
    push.add_discretization_parser(exps)
    _add_lasa_parser(exps)
    _add_babbling_parsers(exps)

    push.add_sweep_parser(exps)
