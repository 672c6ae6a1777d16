"""``a2l experiment panda-gym``: push skills learned inside panda-gym's ``PandaPush-v3`` and
judged on its own episodes (:mod:`a2l.experiments.panda_gym`; the extra ``a2l[gym]``).

Every field of :class:`a2l.experiments.panda_gym.PandaGymConfig` is an option
(``--seed``, ``--eval_seed``, ``--eval_episodes``, ``--budget``...); ``--set part.field=VALUE``
changes a field of the framework's configuration over the experiment's settings.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from jsonargparse import Namespace

from a2l.cli.args import UsageError, check_out, check_record, parse_overrides
from a2l.cli.parser import Parser, add_config_fields, config_from
from a2l.experiments.panda_gym import PandaGymConfig


def _cmd_panda_gym(ns: Namespace) -> int:
    # imported here: parsing does not load Gymnasium, panda-gym and the framework's stack
    from a2l.experiments.panda_gym import framework_config, run_panda_gym

    cfg = config_from(ns, PandaGymConfig)
    overrides = parse_overrides(ns.set)
    try:
        framework_config(cfg, overrides)
    except (TypeError, ValueError) as exc:
        raise UsageError("--set", str(exc)) from None
    out = Path(ns.out) if ns.out is not None else None
    check_out(out, "config.json")
    if ns.record is not None:
        check_record(Path(ns.record))
    try:
        import panda_gym  # noqa: F401
    except ImportError:
        raise UsageError("--task", "panda-gym is not installed: install the extra a2l[gym] "
                         "(pip install 'a2l[gym]')") from None
    run_panda_gym(cfg, out=out, overrides=overrides, quiet=ns.quiet, record=ns.record)
    return 0


def _panda_gym_parser() -> Parser:
    p = Parser(prog="a2l experiment panda-gym", description=(
        "Learn the push skills inside panda-gym's PandaPush-v3 with the A2L iterative "
        "framework (its robot, physics and cube; every env.step counted), then chain them "
        "towards the goal on --eval_episodes of its own episodes (its reset distribution "
        "from --eval_seed, its is_success, its 50-step limit with the approach included). "
        "Writes config.json, metrics.json (success_rate, env_steps_learning, "
        "steps_per_episode, the learning curve), episodes.csv, learning_curve.png, "
        "report.md and skills/push.a2lb. Needs the extra a2l[gym]."))
    add_config_fields(p, PandaGymConfig)
    p.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE",
                   help="change a field of the framework's configuration over the "
                   "experiment's settings, e.g. directed.per_pair=20 (repeatable; VALUE read "
                   "as JSON, else as text)")
    p.add_argument("--out", metavar="DIR", default=None,
                   help="run directory (default runs/panda-gym-<task>-<timestamp>)")
    p.add_argument("--record", metavar="FILE.rrd", default=None,
                   help="write the evaluation episodes to a Rerun recording (a2l view "
                   "FILE.rrd): the end-effector and cube paths, the goal, the effect of each "
                   "movement")
    p.add_argument("--quiet", action="store_true", help="no progress bar, no summary line")
    return p


def add_panda_gym_parser(exps: Any, commands: dict[tuple[str, ...], Any]) -> None:
    """Register ``experiment panda-gym``."""
    parser = _panda_gym_parser()
    exps.add_subcommand("panda-gym", parser, help="push skills learned and judged inside "
                        "panda-gym's PandaPush-v3 (the extra a2l[gym])")
    commands[("experiment", "panda-gym")] = (parser, _cmd_panda_gym)
