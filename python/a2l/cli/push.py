"""``a2l experiment push``, ``discretization`` and ``sweep``: the framework on the push effects.

Every field of every part of :class:`a2l.framework.FrameworkConfig` is a flag of the three
commands (``--discretization.n_effects 8``, ``--learning.fixed_parents distance,orientation``;
``sweep`` sets ``seed`` itself), or a key of ``--config FILE``; the configuration is
validated, variable names included, before any run directory is made. A flag of the flat
configuration of earlier versions (``--n_orient``) is read as its name now, with a warning
(so the commands recorded by earlier runs still run).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from jsonargparse import Namespace
from jsonargparse.typing import PositiveInt

from a2l.cli.args import (
    UsageError,
    check_cluster,
    check_out,
    check_record,
    parse_overrides,
    parse_seeds,
)
from a2l.cli.parser import Parser, add_config_fields, add_config_option, config_from
from a2l.framework.config import (
    FALLBACK_RULES,
    FLAT_NAMES,
    PRESETS,
    FrameworkConfig,
    field_paths,
)
from a2l.rollout.env import ROBOT_SCENES
from a2l.rundir import command_line

#: Short names of some FrameworkConfig flags, still accepted.
ALIASES = {"--effects": "--discretization.n_effects", "--iterations": "--max_iterations",
           "--starts": "--starts.n_starts"}

#: The flags of the flat configuration of earlier versions, by their name now.
RENAMED = {f"--{old}": f"--{new}" for old, new in FLAT_NAMES.items()}


def framework_config(ns: Namespace) -> FrameworkConfig:
    """The validated FrameworkConfig of a command's flags (ConfigError naming the field)."""
    return config_from(ns, FrameworkConfig)


def changed_fields(cfg: FrameworkConfig, base: FrameworkConfig) -> list[str]:
    """The dotted names of the fields whose value differs between `cfg` and `base`."""
    def value(c: FrameworkConfig, path: str) -> Any:
        head, _, rest = path.partition(".")
        return getattr(getattr(c, head), rest) if rest else getattr(c, head)

    return [p for p in field_paths(FrameworkConfig) if value(cfg, p) != value(base, p)]


def _cmd_push(ns: Namespace) -> int:
    # imported here: parsing (and refusing a bad option) does not load the framework's stack
    from a2l.experiments.push import run_push_experiment

    if ns.resume is not None:
        changed = [f"--{p}" for p in changed_fields(config_from(ns, FrameworkConfig),
                                                     FrameworkConfig())]
        changed += [o for o, v in (("--out", ns.out), ("--acquisition", ns.acquisition),
                                   ("--record", ns.record)) if v is not None]
        if changed:
            raise UsageError(changed[0], "not allowed with --resume (the run continues with "
                             "its own config.json, in its own directory)")
        resume = Path(ns.resume)
        if not resume.is_dir():
            raise UsageError("--resume", f"'{resume}' is not a directory")
        if not (resume / "config.json").is_file():
            raise UsageError("--resume", f"'{resume}' holds no config.json: not a push run "
                             "directory")
        check_cluster(ns.cluster)
        run_push_experiment(resume=resume, workers=ns.workers, cluster=ns.cluster,
                            quiet=ns.quiet)
        return 0
    cfg = framework_config(ns)
    if ns.acquisition == "noveb" and cfg.scene not in ROBOT_SCENES:
        raise UsageError("--acquisition", "noveb sees the world through a camera: use "
                         "--scene bullet (the virtual scene has none)")
    check_out(None if ns.out is None else Path(ns.out), "metrics.json", "checkpoints/iter_*",
              resume=True)
    if ns.record is not None:
        check_record(Path(ns.record))
    check_cluster(ns.cluster)
    run_push_experiment(cfg, out=ns.out, workers=ns.workers, cluster=ns.cluster,
                        quiet=ns.quiet, acquisition=ns.acquisition or "random",
                        noveb_evaluations=ns.noveb_evaluations, record=ns.record)
    return 0


def _cmd_discretization(ns: Namespace) -> int:
    # imported here: parsing and --help do not load this command's stack
    from a2l.experiments.discretization import run_discretization_study

    cfg = framework_config(ns)
    out = Path(ns.out)
    check_out(out)
    if ns.record is not None:
        check_record(Path(ns.record))
    run_discretization_study(out=out, base=cfg, workers=ns.workers, quiet=ns.quiet,
                             record=ns.record)
    return 0


def _cmd_sweep(ns: Namespace) -> int:
    # imported here: parsing and --help do not load this command's stack
    from a2l.experiments.sweep import run_seed_sweep

    seeds = parse_seeds(ns.seeds)
    overrides = parse_overrides(ns.set)
    cfg = framework_config(ns)
    try:
        cfg.with_(overrides)
    except (TypeError, ValueError) as exc:
        raise UsageError("--set", str(exc)) from None
    out = Path(ns.out) if ns.out is not None else None
    check_out(out)
    if ns.record is not None:
        check_record(Path(ns.record))
    words = ["a2l", "experiment", "sweep", "--seeds", ns.seeds]
    for item in ns.set:
        words += ["--set", item]
    if out is not None:
        words += ["--out", str(out)]
    try:
        run_seed_sweep(cfg, seeds, overrides, out=out, workers=ns.workers, quiet=ns.quiet,
                       command=command_line(words, cfg, skip=("seed",)), record=ns.record)
    except ValueError as exc:  # out holds a sweep of another configuration
        raise UsageError("--out", str(exc)) from None
    return 0


def _push_parser() -> Parser:
    p = Parser(prog="a2l experiment push", description=(
        "Learn the push effects with the A2L iterative framework (babbling, skill "
        "generation, closed-loop validation through the C++ step) and write the run "
        "directory: config.json, metrics.json, dataset.parquet, skills/push.a2lb, plots, "
        "report.md. Checkpoints after every iteration; --resume DIR continues an "
        "interrupted run. Every field of every part of FrameworkConfig is an option, "
        "--part.field (--effects, --iterations, --starts: --discretization.n_effects, "
        "--max_iterations, --starts.n_starts)."))
    add_config_fields(p, FrameworkConfig)
    p.add_argument("--out", metavar="DIR", default=None,
                   help="run directory (default runs/push-<scene>-<timestamp>)")
    p.add_argument("--workers", type=PositiveInt, default=1, metavar="N",
                   help="local worker processes for the rollouts (default 1)")
    p.add_argument("--cluster", metavar="ADDRESS", default=None,
                   help="Dask scheduler address (tcp://host:port); rollouts run there")
    p.add_argument("--resume", metavar="DIR", default=None,
                   help="continue the interrupted run in DIR (from its last checkpoint)")
    p.add_argument("--acquisition", choices=("random", "noveb"), default=None,
                   help="iteration 0's interactions: random babbling around the object "
                   "(default) or NovEB over the reachable table, on camera images only "
                   "(PyBullet scene only)")
    p.add_argument("--noveb-evaluations", type=PositiveInt, default=200, metavar="N",
                   help="NovEB's trajectories with --acquisition noveb (default 200)")
    p.add_argument("--record", metavar="FILE.rrd", default=None,
                   help="write the final validation's rollouts to a Rerun recording "
                   "(a2l view FILE.rrd)")
    p.add_argument("--quiet", action="store_true", help="no progress bar, no table")
    return p


def _discretization_parser() -> Parser:
    p = Parser(prog="a2l experiment discretization", description=(
        "Run the push experiment for orientation bins {8, 16, 24, 32} x distance bins "
        "{3, 4, 5}; write a table of final score, iterations and movements per action, and "
        "the default it selects. Every field of every part of FrameworkConfig is an option "
        "(the base configuration)."))
    add_config_fields(p, FrameworkConfig)
    p.add_argument("--out", metavar="DIR", required=True, help="study directory")
    p.add_argument("--workers", type=PositiveInt, default=1, metavar="N",
                   help="local worker processes for the rollouts (default 1)")
    p.add_argument("--record", metavar="FILE.rrd", default=None,
                   help="write every combination's final validation to one Rerun recording "
                   "(o<O>-d<D>/rollout/<i>/; a2l view FILE.rrd)")
    p.add_argument("--quiet", action="store_true", help="no per-run lines")
    return p


def _sweep_parser() -> Parser:
    p = Parser(prog="a2l experiment sweep", description=(
        "Run the push experiment once per seed with one configuration and write how many "
        "iterations (iteration 0 included) each seed needed to reach score 100: "
        "metrics.json, report.md (the table of docs/framework.md) and one run directory "
        "per seed. Run again with the same --out to continue an interrupted sweep. Every "
        "field of every part of FrameworkConfig but seed is an option (the base "
        "configuration)."))
    add_config_fields(p, FrameworkConfig, skip={"seed"})
    p.add_argument("--seeds", default="0-29", metavar="LIST",
                   help="seeds, e.g. 0-29 or 0,3,7 (default 0-29)")
    p.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE",
                   help="change a FrameworkConfig field, e.g. directed.per_pair=20; recorded "
                   "as the sweep's overrides (repeatable; VALUE read as JSON, else as text)")
    p.add_argument("--out", metavar="DIR", default=None,
                   help="sweep directory (default runs/sweep-<timestamp>)")
    p.add_argument("--workers", type=PositiveInt, default=1, metavar="N",
                   help="local worker processes (default 1): with at least N seeds to run, "
                   "N seeds at once, each in its own process; with fewer, the runs share "
                   "them as rollout workers")
    p.add_argument("--record", metavar="FILE.rrd", default=None,
                   help="write every seed's final validation to one Rerun recording "
                   "(seed/<seed>/rollout/<i>/; a2l view FILE.rrd)")
    p.add_argument("--quiet", action="store_true", help="no line per seed")
    return p


def _cmd_heldout(ns: Namespace) -> int:
    # imported here: parsing and --help do not load this command's stack
    from a2l.experiments.push_heldout import rerun_heldout

    if ns.record is not None:
        check_record(Path(ns.record))
    run = Path(ns.run)
    if not (run / "config.json").is_file():
        raise UsageError("RUN", f"'{run}' holds no config.json: not a push run directory")
    out = Path(ns.out)
    if out.exists() and not out.is_dir():
        raise UsageError("--out", f"'{out}' exists and is not a directory")
    m = rerun_heldout(run, out, iteration=ns.iteration, fallback=ns.fallback,
                      workers=ns.workers, record=ns.record, clearance=ns.clearance,
                      avoid_revisits=ns.avoid_revisits, clearance_ratio=ns.clearance_ratio,
                      step_cap=ns.step_cap, align=ns.align)
    if not ns.quiet:
        print(f"held-out success {m['heldout_success']:.1%} ("
              + ", ".join(f"{e} {v:.0%}" for e, v in m["heldout_success_rate"].items())
              + f"); fallback {m['fallback']}, clearance {m['clearance']:g} m (bar "
              + f"{m['clearance_ratio']:g}), revisit rule "
              + ("on" if m["avoid_revisits"] else "off") + "; misses "
              f"explained in {out / 'report.md'}")
    return 0


def _heldout_parser() -> Parser:
    p = Parser(prog="a2l experiment heldout", description=(
        "Run a push run's skill from the run's held-out starts again, with its own "
        "execution settings or another fallback (--fallback), and write metrics.json, "
        "heldout.parquet, heldout_misses.csv, heldout_misses.png and report.md (every miss "
        "with its cause, read from its trajectory) to --out. The run directory is not "
        "written to."))
    p.add_argument("run", metavar="RUN", help="a push run directory")
    p.add_argument("--out", metavar="DIR", required=True, help="output directory")
    p.add_argument("--iteration", type=int, default=None, metavar="N",
                   help="the skill of iteration N (skills/iter_NNN.a2lb; default the final "
                   "skills/push.a2lb)")
    p.add_argument("--fallback", choices=FALLBACK_RULES, default=None,
                   help="the step's answer in a cell without data (default the bundle's)")
    p.add_argument("--clearance", type=float, default=None, metavar="M",
                   help="the step's clearance rule in m, 0 off (default the bundle's)")
    p.add_argument("--clearance_ratio", type=float, default=None, metavar="R",
                   help="the clearance rule's bar in (0, 1] (default the bundle's)")
    p.add_argument("--align", type=float, default=None, metavar="M",
                   help="the step's alignment rule in m, 0 off (default the bundle's)")
    p.add_argument("--step_cap", type=PositiveInt | None, default=None, metavar="N",
                   help="most movements a run may take (default the bundle's)")
    p.add_argument("--avoid_revisits", type=bool | None, default=None,
                   help="the step's revisit rule, true or false (default the bundle's)")
    p.add_argument("--workers", type=PositiveInt, default=1, metavar="N",
                   help="local worker processes for the rollouts (default 1)")
    p.add_argument("--record", metavar="FILE.rrd", default=None,
                   help="write the held-out rollouts to a Rerun recording (a2l view FILE.rrd)")
    p.add_argument("--quiet", action="store_true", help="no summary line")
    return p


def add_push_parsers(exps: Any, commands: dict[tuple[str, ...], Any]) -> None:
    """Register ``experiment push``, ``discretization``, ``sweep`` and ``heldout``."""
    for name, make, handler, help_ in (
            ("push", _push_parser, _cmd_push, "the iterative framework on the push effects"),
            ("discretization", _discretization_parser, _cmd_discretization,
             "orientation x distance discretization study"),
            ("sweep", _sweep_parser, _cmd_sweep,
             "the push experiment over many seeds: iterations to reach 100")):
        parser = make()
        parser.aliases = ALIASES
        parser.renamed = RENAMED
        parser.presets = PRESETS
        parser.add_argument("--preset", choices=list(PRESETS), default=None,
                            help="a named configuration, in place: options after it override "
                            "it (thesis: the thesis' loop and representation, the baseline)")
        add_config_option(parser)
        exps.add_subcommand(name, parser, help=help_)
        commands[("experiment", name)] = (parser, handler)
    parser = _heldout_parser()
    add_config_option(parser)
    exps.add_subcommand("heldout", parser, help="a push run's skill from its held-out starts "
                        "again (another fallback), every miss explained")
    commands[("experiment", "heldout")] = (parser, _cmd_heldout)
