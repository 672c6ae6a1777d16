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


def _cmd_demo_record(args: argparse.Namespace) -> int:
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
    if args.keys is not None:
        keys = [k for k in args.keys.split(",") if k.strip()]
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


def _add_demo_record_parser(sub: argparse._SubParsersAction) -> None:
    rec = sub.add_parser(
        "demo-record", help="record demonstrations by teleoperation in the PyBullet GUI",
        description="Move Baxter's end-effector with the keyboard in the PyBullet GUI and "
        "record demonstrations (the part-1 demonstration format, relative to the object). "
        "Keys: arrows = x/y, Page Up/Down = z (1 cm steps), Space = gripper, Return = "
        "start/stop recording, q = save and quit.")
    rec.add_argument("--scene", choices=("grasp", "grasp_light", "press", "push"),
                     required=True, help="the scene to demonstrate in")
    rec.add_argument("--out", metavar="FILE", required=True,
                     help="demonstration file to write (.csv or .parquet)")
    rec.add_argument("--seed", type=_nonnegative_int, default=0, help="scene seed (default 0)")
    rec.add_argument("--step", type=float, default=0.01, metavar="M",
                     help="length of one move (default 0.01 m)")
    rec.add_argument("--start", metavar="DX,DY,DZ", default=None,
                     help="start the end-effector here relative to the object (m; default: "
                     "the neutral pose)")
    rec.add_argument("--keys", metavar="CMD,CMD,...", default=None,
                     help="no GUI: run these commands instead of reading the keyboard "
                     "(forward, back, left, right, up, down, gripper, record, quit; "
                     "'down*5' repeats)")
    rec.set_defaults(func=_cmd_demo_record)


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
                        "iterations": "max_iterations", "starts": "n_starts",
                        "heldout_starts": "heldout_starts"}


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
        given = [f"--{o.replace('_', '-')}" for o in _PUSH_CONFIG_OPTIONS
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
        _check_cluster(args.cluster)
        if args.acquisition is not None:
            raise UsageError("--acquisition", "not allowed with --resume (the run continues "
                             "with its own config.json)")
        run_push_experiment(resume=resume, workers=args.workers, cluster=args.cluster,
                            quiet=args.quiet)
        return 0
    cfg = _framework_config(args, _PUSH_CONFIG_OPTIONS)
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
    _check_cluster(args.cluster)
    run_push_experiment(cfg, out=args.out, workers=args.workers, cluster=args.cluster,
                        quiet=args.quiet, acquisition=args.acquisition or "random",
                        noveb_evaluations=args.noveb_evaluations)
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
        cfg = LasaConfig(K=args.K, beta=args.beta, mu=args.mu, n_starts=args.starts,
                         seed=args.seed)
        cfg.validate()
    except ValueError as exc:
        raise UsageError("--K/--beta/--mu", str(exc)) from None
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
    lasa.add_argument("--K", type=_positive_int, default=150, help="maps (default 150)")
    lasa.add_argument("--beta", type=float, default=None,
                      help="fraction of the largest error one map corrects (default: the "
                      "original implementation's schedule, 1/3 -> 0.9 over the maps)")
    lasa.add_argument("--mu", type=float, default=None,
                      help="safety factor of the invertibility bound (default: a schedule "
                      "0.8 -> 0.65 over the maps)")
    lasa.add_argument("--starts", type=_positive_int, default=10_000, metavar="N",
                      help="random starts per shape for the convergence test (default 10000)")
    lasa.add_argument("--seed", type=_nonnegative_int, default=0,
                      help="seed of the random starts (default 0)")
    lasa.add_argument("--workers", type=_positive_int, default=1, metavar="N",
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
    _check_cluster(args.cluster)
    run_babbling(args.method, args.evaluations, args.seed, args.scene, out=args.out,
                 workers=args.workers, cluster=args.cluster,
                 generation_size=args.generation_size, quiet=args.quiet)
    return 0


def _cmd_experiment_babbling_compare(args: argparse.Namespace) -> int:
    from a2l.experiments.babbling_plots import run_babbling_compare

    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise UsageError("--out", f"'{out}' exists and is not a directory")
    _check_cluster(args.cluster)
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
    bab.add_argument("--seed", type=_nonnegative_int, default=0, help="random seed (default 0)")
    cmp_.add_argument("--seeds", type=_positive_int, default=5, metavar="N",
                      help="seeds 0 .. N-1 (default 5)")
    bab.add_argument("--out", metavar="DIR", default=None,
                     help="run directory (default runs/babbling-<method>-<scene>-<timestamp>)")
    cmp_.add_argument("--out", metavar="DIR", required=True, help="comparison directory")
    for p in (bab, cmp_):
        p.add_argument("--evaluations", type=_positive_int, default=2000, metavar="N",
                       help="trajectories played per run (default 2000)")
        p.add_argument("--scene", choices=("push", "two_objects"), default="push",
                       help="one box, or two boxes far apart (default push)")
        p.add_argument("--generation-size", type=_positive_int, default=20, metavar="N",
                       help="evaluations per generation (NovEB's mu and lambda; default 20)")
        p.add_argument("--workers", type=_positive_int, default=1, metavar="N",
                       help="local worker processes for the evaluations (default 1)")
        p.add_argument("--cluster", metavar="ADDRESS", default=None,
                       help="Dask scheduler address (tcp://host:port); evaluations run there")
        p.add_argument("--quiet", action="store_true", help="no progress bar")
    bab.set_defaults(func=_cmd_experiment_babbling)
    cmp_.set_defaults(func=_cmd_experiment_babbling_compare)


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
    from a2l.experiments import lfd_skills, parametrization, perturbations

    lfd_skills.add_parser(exps)
    parametrization.add_parser(exps)
    perturbations.add_parser(exps)

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
    push.add_argument("--heldout-starts", type=_nonnegative_int, default=None, metavar="N",
                      help="held-out start positions each iteration's skill is also scored "
                      "from, never trained from (default 32; 0: none)")
    push.add_argument("--acquisition", choices=("random", "noveb"), default=None,
                      help="iteration 0's interactions: random babbling around the object "
                      "(default) or NovEB over the reachable table, on camera images only "
                      "(PyBullet scene only)")
    push.add_argument("--noveb-evaluations", type=_positive_int, default=200, metavar="N",
                      help="NovEB's trajectories with --acquisition noveb (default 200)")
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
    _add_lasa_parser(exps)
    _add_babbling_parsers(exps)

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
    _add_demo_record_parser(sub)
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
