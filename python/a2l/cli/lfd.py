"""``a2l experiment lfd-skills``, ``parametrization`` and ``perturbations``: the demonstrated
skills (a2l.lfd) learned and run by the experiments of a2l.experiments."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from jsonargparse import Namespace

from a2l.cli.args import UsageError, check_record, comma_list
from a2l.cli.parser import Parser, add_config_fields, add_config_option, config_from
from a2l.errors import ConfigError
from a2l.experiments.lfd_skills import DEFAULT_SEED as LFD_FIRST_SEED
from a2l.experiments.lfd_skills import SCENES
from a2l.experiments.perturbations import CONDITIONS, DEFAULT_SEED
from a2l.lfd.config import DEFAULT, LfDConfig
from a2l.robot import DEFAULT_ROBOT
from a2l.rollout.env import LEGACY_SCENES


def lfd_config(args: Namespace) -> LfDConfig | None:
    """The LfDConfig of the ``--lfd.*`` options: None (each skill's own configuration) when
    none differs from :data:`a2l.lfd.config.DEFAULT`."""
    try:
        cfg = config_from(args.lfd, LfDConfig)
    except ConfigError as exc:  # <field>: ... (a part's: discretization.<field>)
        raise UsageError(f"--lfd.{exc.field.split(',')[0]}", exc.message) from None
    return None if cfg == DEFAULT else cfg


def run_args(args: Namespace) -> tuple[Path, list[str] | None]:
    """The run directory and the skills of an experiment's command line, checked
    (``--out`` not a file, ``--trials`` and ``--workers`` >= 1, ``--seed`` >= 0)."""
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise UsageError("--out", f"'{out}' exists and is not a directory")
    for opt, v in (("--trials", args.trials), ("--workers", args.workers)):
        if v < 1:
            raise UsageError(opt, f"must be >= 1, got {v}")
    if args.seed < 0:
        raise UsageError("--seed", f"must be >= 0, got {args.seed}")
    return out, comma_list(args.skills)


def _cmd_lfd_skills(args: Namespace) -> int:
    # imported here: parsing and --help do not load this command's stack
    from a2l.experiments.lfd_skills import run_lfd_skills

    out, skills = run_args(args)
    if args.record is not None:
        check_record(Path(args.record))
    run_lfd_skills(out, skills, args.trials, args.seed, args.scene, args.mode,
                   args.workers, cfg=lfd_config(args), quiet=args.quiet,
                   context_source=args.context_source, record=args.record, robot=args.robot)
    return 0


def _lfd_skills_parser() -> Parser:
    """Register ``a2l experiment lfd-skills``."""
    p = Parser(
        prog="a2l experiment lfd-skills",
        description="Learn each demonstrated skill from its scripted demonstrations "
        "(vector field -> dataset -> Bayesian network -> compiled table) and run it in closed "
        "loop through the C++ step from held-out trial seeds; write report.md, "
        "metrics.json, trials.csv and the bundles.")
    p.add_argument("--out", required=True, help="run directory")
    p.add_argument("--skills", default=None,
                   help="comma-separated skill names (default: the push skills)")
    p.add_argument("--trials", type=int, default=20, help="trials per skill (default 20)")
    p.add_argument("--seed", type=int, default=LFD_FIRST_SEED, help=f"first trial seed "
                   f"(default {LFD_FIRST_SEED}, the first evaluation seed: docs/seeds.md)")
    add_robot_options(p)
    p.add_argument("--mode", choices=("table", "ds"), default="table")
    p.add_argument("--context_source", choices=("perceived", "ground_truth"),
                   default="perceived", help="where the skills read the context: the camera "
                   "(perceived, default) or the simulator's ground truth")
    p.add_argument("--workers", type=int, default=1, help="worker processes (default 1)")
    p.add_argument("--record", default=None, metavar="FILE.rrd",
                   help="write a Rerun recording of every trial, <skill>/rollout/<i>/ "
                   "(a2l view FILE.rrd)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    add_config_fields(p, LfDConfig, nested_key="lfd")
    return p


def _floats(text: str, what: str) -> tuple[float, ...]:
    try:
        vals = tuple(float(v) for v in text.split(",") if v.strip())
    except ValueError:
        raise UsageError(what, f"expected comma-separated numbers, got {text!r}") from None
    if not vals or any(not v > 0 for v in vals):
        raise UsageError(what, f"expected positive numbers, got {text!r}")
    return vals


def _ints(text: str, what: str) -> tuple[int, ...]:
    vals = _floats(text, what)
    if any(v != int(v) for v in vals):
        raise UsageError(what, f"expected integers, got {text!r}")
    return tuple(int(v) for v in vals)


def grid_of(args: Namespace) -> dict[str, Sequence[Any]]:
    """The grid values of ``a2l experiment parametrization``'s options (those given)."""
    grid: dict[str, Sequence[Any]] = {}
    if args.resolutions:
        grid["resolution"] = _floats(args.resolutions, "--resolutions")
    if args.steps:
        grid["step"] = _floats(args.steps, "--steps")
    if args.orients:
        grid["n_orient"] = _ints(args.orients, "--orients")
    if args.dists:
        grid["n_dist"] = _ints(args.dists, "--dists")
    if args.smoothing:
        sm = [s.strip() for s in args.smoothing.split(",") if s.strip()]
        if not sm or any(s not in ("on", "off") for s in sm):
            raise UsageError("--smoothing", f"expected on and/or off, got {args.smoothing!r}")
        grid["smoothing"] = tuple(s == "on" for s in sm)
    return grid


def add_robot_options(p: Parser, scene: bool = True) -> None:
    """``--robot`` (and with `scene`, ``--scene``) of the experiments on demonstrated
    skills."""
    p.add_argument("--robot", default=DEFAULT_ROBOT, metavar="NAME|FILE",
                   help="the robot the skills are learned for and tried on: a built-in name "
                   "(baxter, panda, ...) or a robot file")
    if scene:
        p.add_argument("--scene", choices=(*SCENES, *LEGACY_SCENES), default=None,
                       help="the recipes' PyBullet scenes on --robot (bullet, the default), "
                       "or the virtual scene; baxter, their earlier name on Baxter, is "
                       "bullet with --robot baxter")


def _cmd_parametrization(args: Namespace) -> int:
    # imported here: parsing and --help do not load this command's stack
    from a2l.experiments.parametrization import run_parametrization

    grid = grid_of(args)
    out, skills = run_args(args)
    if args.record is not None:
        check_record(Path(args.record))
    run_parametrization(out, skills, grid, args.trials, args.seed, args.scene,
                        args.workers, base=lfd_config(args), quiet=args.quiet,
                        record=args.record, robot=args.robot)
    return 0


def _parametrization_parser() -> Parser:
    """Register ``a2l experiment parametrization``."""
    p = Parser(
        prog="a2l experiment parametrization",
        description="For each cell of grid resolution x movement step x orientation bins x "
        "distance bins x smoothing, learn the skill from its demonstrations and run it from "
        "tuning seeds; write the table, the selected default, report.md and a plot. Values "
        "are comma-separated lists (defaults: the full study).")
    p.add_argument("--out", required=True, help="run directory")
    p.add_argument("--skills", default=None,
                   help="comma-separated skills (default: push_right, and grasp if registered)")
    p.add_argument("--resolutions", default=None, help="grid spacings in m (0.005,0.01,0.02)")
    p.add_argument("--steps", default=None, help="movement steps in m (0.02,0.03,0.05)")
    p.add_argument("--orients", default=None, help="orientation bins (8,16,24,32)")
    p.add_argument("--dists", default=None, help="distance bins (3,4,5)")
    p.add_argument("--smoothing", default=None, help="off,on (default both)")
    p.add_argument("--trials", type=int, default=20, help="trials per cell (default 20)")
    p.add_argument("--seed", type=int, default=500, help="first trial seed (default 500)")
    add_robot_options(p)
    p.add_argument("--workers", type=int, default=1, help="worker processes (default 1)")
    p.add_argument("--record", default=None, metavar="FILE.rrd",
                   help="write every cell's trials to one Rerun recording, "
                   "<skill>/cell<NNN>/rollout/<i>/ (a2l view FILE.rrd)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    add_config_fields(p, LfDConfig, nested_key="lfd")
    return p


def _cmd_perturbations(args: Namespace) -> int:
    # imported here: parsing and --help do not load this command's stack
    from a2l.experiments.perturbations import run_perturbations

    if args.record is not None:
        check_record(Path(args.record))
    run_perturbations(args.out, comma_list(args.skills), args.trials, args.seed,
                      args.workers, args.cluster, comma_list(args.conditions) or CONDITIONS,
                      cfg=lfd_config(args), quiet=args.quiet, plots=not args.no_plots,
                      context_source=args.context_source, record=args.record,
                      robot=args.robot)
    return 0


def _perturbations_parser() -> Parser:
    """Register ``a2l experiment perturbations``."""
    p = Parser(
        prog="a2l experiment perturbations",
        description="Learn each demonstrated skill, then run it on held-out trial seeds "
        "without perturbation and with the object moved 3-5 cm, the end-effector held 1-2 s "
        "and the light switched mid-action, each as the context skill (table) and as the DS "
        "alone; write metrics.json, trials.csv, report.md and trajectory plots.")
    p.add_argument("--out", required=True, help="run directory")
    p.add_argument("--skills", default=None,
                   help="comma-separated skill names (default: every registered skill)")
    p.add_argument("--conditions", default=None,
                   help=f"comma-separated subset of {','.join(CONDITIONS)} (default: all)")
    p.add_argument("--trials", type=int, default=50,
                   help="trials per skill, condition and mode (default 50)")
    p.add_argument("--seed", type=int, default=DEFAULT_SEED,
                   help=f"first trial seed (default {DEFAULT_SEED}; held out from the "
                   "demonstration seeds 0..n_demos-1)")
    p.add_argument("--workers", type=int, default=1, help="worker processes (default 1)")
    p.add_argument("--cluster", default=None,
                   help="address of a Dask scheduler (tcp://host:8786); overrides --workers")
    p.add_argument("--context_source", choices=("perceived", "ground_truth"),
                   default="perceived", help="where the skills read the context: the camera "
                   "(perceived, default) or the simulator's ground truth")
    add_robot_options(p, scene=False)
    p.add_argument("--no-plots", action="store_true", help="no trajectory plots")
    p.add_argument("--record", default=None, metavar="FILE.rrd",
                   help="write a Rerun recording of every trial, one rollout each "
                   "(a2l view FILE.rrd)")
    p.add_argument("--quiet", action="store_true", help="no progress bar, no table")
    add_config_fields(p, LfDConfig, nested_key="lfd")
    return p


def add_lfd_parsers(exps: Any, commands: dict[tuple[str, ...], Any]) -> None:
    """Register ``experiment lfd-skills``, ``parametrization`` and ``perturbations``. Every
    LfDConfig field is an option ``--lfd.<field>``: given, it replaces each skill's own
    configuration by DEFAULT with the values given."""
    for name, make, handler, help_ in (
            ("lfd-skills", _lfd_skills_parser, _cmd_lfd_skills,
             "demonstrated skills: learn, then run on held-out seeds"),
            ("parametrization", _parametrization_parser, _cmd_parametrization,
             "grid x step x bins x smoothing study of demonstrated skills"),
            ("perturbations", _perturbations_parser, _cmd_perturbations,
             "demonstrated skills under perturbations: context skill vs DS")):
        parser = make()
        add_config_option(parser)
        exps.add_subcommand(name, parser, help=help_)
        commands[("experiment", name)] = (parser, handler)
