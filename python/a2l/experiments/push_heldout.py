"""A push run's skill from its held-out starts again, with the run's execution settings or
another fallback, clearance rule (or its bar), revisit rule or step cap (``a2l experiment
heldout``): the paired comparison of the step's answers on one skill, and its misses
explained (:mod:`a2l.experiments.push_misses`).

The rollouts are the framework's held-out validation
(:func:`a2l.framework.validation.validate_heldout`) on a copy of the run's bundle whose
``skill.fallback`` (or ``skill.clearance``, ``skill.clearance_ratio``,
``skill.avoid_revisits``, ``skill.step_cap``) is replaced; the run directory itself is not
written to.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

from a2l.acquisition.interactions import rollouts_table
from a2l.atomic import atomic_write_text
from a2l.errors import ConfigError
from a2l.experiments.push import record_validations
from a2l.experiments.push_misses import miss_causes, miss_table, misses_markdown, plot_misses
from a2l.framework.config import FrameworkConfig
from a2l.framework.rules import bundle_with_rules
from a2l.framework.scoring import heldout_metrics
from a2l.framework.validation import validate_heldout
from a2l.parallel import Executor
from a2l.rundir import write_json
from a2l.seeds import mark_report, seed_record

__all__ = ["rerun_heldout"]


def rerun_heldout(run_dir: str | Path, out: str | Path, iteration: int | None = None,
                  fallback: str | None = None, workers: int = 1,
                  record: str | Path | None = None,
                  clearance: float | None = None,
                  avoid_revisits: bool | None = None,
                  clearance_ratio: float | None = None,
                  step_cap: int | None = None,
                  align: float | None = None) -> dict[str, Any]:
    """Run the skill of push run `run_dir` from the run's held-out starts again and write
    `out`: ``metrics.json`` (:func:`~a2l.framework.scoring.heldout_metrics`),
    ``heldout.parquet``, ``heldout_misses.csv``, ``heldout_misses.png`` and ``report.md``.

    Parameters
    ----------
    run_dir : path
        A push run directory (``config.json`` and ``skills/``).
    out : path
        Where to write (created; not inside `run_dir`'s checkpoints).
    iteration : int, optional
        The skill of this iteration (``skills/iter_NNN.a2lb``); default the final one
        (``skills/push.a2lb``).
    fallback : {"none", "nearest", "approach"}, optional
        The step's answer in a cell without data; default the bundle's own.
    workers : int
        Local worker processes for the rollouts.
    record : path, optional
        A Rerun recording (``.rrd``) of the held-out rollouts, one rollout each, as ``a2l
        experiment push --record`` writes a validation's.
    clearance : float, optional
        The step's clearance rule (m; 0: off); default the bundle's own.
    avoid_revisits : bool, optional
        The step's revisit rule on or off; default the bundle's own.
    clearance_ratio : float, optional
        The clearance rule's bar in (0, 1]; default the bundle's own.
    step_cap : int, optional
        Most movements a run may take; default the bundle's own.
    align : float, optional
        The step's alignment rule (m; 0: off); default the bundle's own.

    Returns
    -------
    dict
        The metrics written, with the step's settings it ran (``"fallback"``,
        ``"clearance"``, ``"clearance_ratio"``, ``"avoid_revisits"``, ``"step_cap"``),
        ``"bundle"`` and ``"wall_s"``.
    """
    run_dir, out = Path(run_dir), Path(out)
    cfg_path = run_dir / "config.json"
    if not cfg_path.is_file():
        raise ConfigError("run", f"'{run_dir}' holds no config.json: not a push run directory")
    cfg = FrameworkConfig.from_dict(json.loads(cfg_path.read_text())["framework"])
    src = run_dir / "skills" / ("push.a2lb" if iteration is None else f"iter_{iteration:03d}.a2lb")
    if not src.is_file():
        raise ConfigError("iteration", f"'{src}' does not exist")
    changes = {"fallback": fallback, "clearance": clearance, "clearance_ratio": clearance_ratio,
               "avoid_revisits": avoid_revisits, "step_cap": step_cap, "align": align}
    changes = {k: v for k, v in changes.items() if v is not None}
    cfg = cfg.with_({f"skill.{k}": v for k, v in changes.items()})  # names a bad value
    out.mkdir(parents=True, exist_ok=True)
    bundle = out / "skill.a2lb"
    spec = bundle_with_rules(src, bundle, **changes)
    t0 = time.perf_counter()
    with Executor(workers=workers) as ex:
        held = validate_heldout(cfg, ex, bundle)
    wall = time.perf_counter() - t0
    frame = rollouts_table(held)
    frame.to_parquet(out / "heldout.parquet", index=False)
    if record is not None:
        record_validations(record, {"": (frame, bundle)}, name="a2l experiment heldout")
    it = -1 if iteration is None else iteration
    table = miss_table(cfg, frame, bundle)
    metrics = {**heldout_metrics(cfg, it, held), "heldout_miss_causes": miss_causes(table),
               "run": str(run_dir), "bundle": str(src), "fallback": spec.fallback,
               "clearance": spec.clearance, "clearance_ratio": spec.clearance_ratio,
               "avoid_revisits": spec.avoid_revisits, "step_cap": spec.step_cap,
               "align": spec.align, "wall_s": wall}
    write_json(out / "metrics.json", metrics)
    atomic_write_text(out / "heldout_misses.csv", table.to_csv(index=False))
    if not table.empty:
        plot_misses(cfg, frame, table, out / "heldout_misses.png")
    rates = ", ".join(f"{e} {v:.1%}" for e, v in metrics["heldout_success_rate"].items())
    text = "\n".join([
        f"# Held-out starts again: {src} (fallback `{spec.fallback}`, clearance "
        f"{spec.clearance:g} m at a bar of {spec.clearance_ratio:g}, alignment "
        f"{spec.align:g} m, revisit rule "
        f"{'on' if spec.avoid_revisits else 'off'}, step cap {spec.step_cap})", "",
        f"Run `{run_dir}` ({cfg.scene} scene, {cfg.discretization.n_effects} effects, "
        f"seed {cfg.seed}); "
        f"{cfg.heldout.n_starts} held-out starts x {cfg.discretization.n_effects} effects.", "",
        f"Success rate from the held-out starts: **{metrics['heldout_success']:.1%}** "
        f"({rates}); held-out score {metrics['heldout_score']:.1f}; {wall:.0f} s.", "",
        *misses_markdown(table, len(frame)),
    ]) + "\n"
    atomic_write_text(out / "report.md", mark_report(text, seed_record("heldout", [cfg.seed])))
    return metrics
