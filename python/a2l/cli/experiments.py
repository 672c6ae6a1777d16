"""``a2l experiment``: the sub-parser of every experiment; ``lasa`` and ``babbling`` here."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from jsonargparse import Namespace
from jsonargparse.typing import NonNegativeInt, PositiveInt

from a2l.cli import lfd, panda_gym, push, tasks
from a2l.cli.args import UsageError, check_cluster, check_out, check_record, comma_list
from a2l.cli.parser import Parser, add_config_fields, add_config_option, config_from
from a2l.experiments.babbling_world import WorldConfig
from a2l.experiments.lasa import LasaConfig
from a2l.robot import DEFAULT_ROBOT


def _cmd_experiment_lasa(args: Namespace) -> int:
    # imported here: parsing does not load the LASA data and the fit
    from a2l.experiments.lasa import lasa_shapes, run_lasa_experiment

    shapes = comma_list(args.shapes)
    if args.shapes is not None:
        unknown = [s for s in shapes or [] if s not in lasa_shapes()]
        if unknown or not shapes:
            raise UsageError("--shapes", f"unknown shape(s) {unknown}; known: "
                             f"{', '.join(lasa_shapes())}")
    cfg = config_from(args, LasaConfig)
    try:
        cfg.validate()
    except ValueError as exc:
        raise UsageError(f"--{str(exc).split()[0]}", str(exc)) from None
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise UsageError("--out", f"'{out}' exists and is not a directory")
    if args.record is not None:
        check_record(Path(args.record))
    run_lasa_experiment(cfg, out=out, shapes=shapes, workers=args.workers, quiet=args.quiet,
                        record=args.record)
    return 0


def _lasa_parser() -> Parser:
    lasa = Parser(
        prog="a2l experiment lasa",
        description="Fit one diffeomorphic DS per LASA shape (fast diffeomorphic matching) "
        "and compare it with a DMP and the linear DS: DTW, swept error area, velocity RMSE, "
        "fit and query time, convergence from random starts. Writes config.json, "
        "metrics.json, report.md, lasa.png and one DS bundle per shape. Every LasaConfig "
        "field is an option (--starts: --n_starts).")
    add_config_fields(lasa, LasaConfig)
    lasa.add_argument("--out", metavar="DIR", required=True, help="run directory")
    lasa.add_argument("--shapes", metavar="A,B,...", default=None,
                      help="comma-separated shape names (default: all 30)")
    lasa.add_argument("--workers", type=PositiveInt, default=1, metavar="N",
                      help="local worker processes, one shape each (default 1)")
    lasa.add_argument("--record", metavar="FILE.rrd", default=None,
                      help="write each shape's demonstrations and the DS paths from their "
                      "starts, over time, to a Rerun recording (a2l view FILE.rrd)")
    lasa.add_argument("--quiet", action="store_true", help="no progress bar, no table")
    lasa.aliases = {"--starts": "--n_starts"}  # type: ignore[attr-defined]
    return lasa


def _cmd_experiment_babbling(args: Namespace) -> int:
    # imported here: parsing and --help do not load this command's stack
    from a2l.experiments.babbling import run_babbling

    check_out(None if args.out is None else Path(args.out), "metrics.json")
    if args.record is not None:
        check_record(Path(args.record))
    check_cluster(args.cluster)
    world = config_from(args.world, WorldConfig)
    run_babbling(args.method, args.evaluations, args.seed, args.scene, out=args.out,
                 workers=args.workers, cluster=args.cluster,
                 generation_size=args.generation_size, quiet=args.quiet, world=world,
                 record=args.record)
    return 0


def _cmd_experiment_babbling_compare(args: Namespace) -> int:
    # imported here: parsing and --help do not load this command's stack
    from a2l.experiments.babbling_compare import run_babbling_compare

    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise UsageError("--out", f"'{out}' exists and is not a directory")
    if args.record is not None:
        check_record(Path(args.record))
    check_cluster(args.cluster)
    seeds = list(range(args.first_seed, args.first_seed + args.seeds))
    run_babbling_compare(args.scene, args.evaluations, seeds, out=out,
                         methods=tuple(args.methods), workers=args.workers,
                         cluster=args.cluster, generation_size=args.generation_size,
                         quiet=args.quiet, record=args.record, robot=args.robot)
    return 0


def _babbling_parsers() -> tuple[Parser, Parser]:
    """``experiment babbling`` and ``experiment babbling-compare``."""
    bab = Parser(
        prog="a2l experiment babbling",
        description="Explore with NovEB (novelty-driven evolutionary babbling, on camera "
        "images only), random motor babbling or random goal babbling, with the same "
        "trajectory encoding and budget; write the run directory: config.json, "
        "metrics.json (per generation: moved_share, distinct_outcomes, archive_size), "
        "evaluations.parquet, paths.npz, visits.png, progress.png, report.md.")
    cmp_ = Parser(
        prog="a2l experiment babbling-compare",
        description="Run the babbling experiment for each method and seed (<out>/<method>-"
        "s<seed>; finished runs are reused) and write the side-by-side plots and the table "
        "of means and spreads over seeds.")
    bab.add_argument("--method", choices=("noveb", "random", "goal"), required=True,
                     help="exploration method")
    cmp_.add_argument("--methods", nargs="+", choices=("noveb", "random", "goal"),
                      default=["noveb", "random", "goal"], help="methods (default all three)")
    bab.add_argument("--seed", type=NonNegativeInt, default=0, help="random seed (default 0)")
    cmp_.add_argument("--seeds", type=PositiveInt, default=5, metavar="N",
                      help="seeds F .. F+N-1, F = --first-seed (default 5)")
    cmp_.add_argument("--first-seed", type=NonNegativeInt, default=0, metavar="F",
                      help="first seed (default 0; evaluation seeds from 1000: "
                      "docs/seeds.md)")
    bab.add_argument("--out", metavar="DIR", default=None,
                     help="run directory (default runs/babbling-<method>-<scene>-<timestamp>)")
    cmp_.add_argument("--out", metavar="DIR", required=True, help="comparison directory")
    for p in (bab, cmp_):
        p.add_argument("--evaluations", type=PositiveInt, default=2000, metavar="N",
                       help="trajectories played per run (default 2000)")
        p.add_argument("--scene", choices=("push", "two_objects"), default="push",
                       help="one box, or two boxes far apart (default push)")
        p.add_argument("--generation-size", type=PositiveInt, default=20, metavar="N",
                       help="evaluations per generation (NovEB's mu and lambda; default 20)")
        p.add_argument("--workers", type=PositiveInt, default=1, metavar="N",
                       help="local worker processes for the evaluations (default 1)")
        p.add_argument("--cluster", metavar="ADDRESS", default=None,
                       help="Dask scheduler address (tcp://host:port); evaluations run there")
        p.add_argument("--quiet", action="store_true", help="no progress bar")
    bab.add_argument("--record", metavar="FILE.rrd", default=None,
                     help="write every evaluation to a Rerun recording: the end-effector "
                     "path, the objects before and after (a2l view FILE.rrd)")
    cmp_.add_argument("--robot", default=DEFAULT_ROBOT, metavar="NAME|FILE",
                      help="the robot: a built-in name (baxter, pr2, ...) or a robot file; the "
                      "world is placed at its work point")
    cmp_.add_argument("--record", metavar="FILE.rrd", default=None,
                      help="write every run's evaluations to one Rerun recording, "
                      "<method>-s<seed>/rollout/<i>/ (a2l view FILE.rrd)")
    add_config_fields(bab, WorldConfig, skip={"scene", "seed"}, nested_key="world")
    bab.aliases = {"--robot": "--world.robot"}  # type: ignore[attr-defined]
    return bab, cmp_


def add_experiment_parsers(sub: Any, commands: dict[tuple[str, ...], Any]) -> None:
    """The ``experiment`` subcommand and its experiments (parser and handler of each in
    `commands`)."""
    experiment = Parser(prog="a2l experiment", description="run an A2L experiment (run "
                        "directory with config, metrics, plots, report)")
    sub.add_subcommand("experiment", experiment, help="run an A2L experiment (run directory "
                       "with config, metrics, plots, report)")
    exps = experiment.add_subcommands(metavar="EXPERIMENT")
    lfd.add_lfd_parsers(exps, commands)
    tasks.add_tasks_parser(exps, commands)
    push.add_push_parsers(exps, commands)
    panda_gym.add_panda_gym_parser(exps, commands)
    bab, cmp_ = _babbling_parsers()
    for name, parser, handler, help_ in (
            ("lasa", _lasa_parser(), _cmd_experiment_lasa,
             "the diffeomorphic DS on the LASA handwriting benchmark"),
            ("babbling", bab, _cmd_experiment_babbling,
             "one exploration method on Baxter's push scenes"),
            ("babbling-compare", cmp_, _cmd_experiment_babbling_compare,
             "every exploration method over several seeds")):
        add_config_option(parser)
        exps.add_subcommand(name, parser, help=help_)
        commands[("experiment", name)] = (parser, handler)
