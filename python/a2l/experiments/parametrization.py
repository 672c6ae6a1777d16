"""``a2l experiment parametrization``: the thesis' parametrization study for demonstrated skills.

For each skill studied (push right; grasp when its recipe is registered) and each cell of
grid resolution x movement step x orientation bins x distance bins x smoothing, the skill is
learned from its scripted demonstrations with that :class:`~a2l.lfd.config.LfDConfig` and run
in closed loop from ``trials`` trial set-ups (seeds ``seed ...``, default 500: tuning seeds,
apart from the held-out 1000+ of ``a2l experiment lfd-skills``). A cell's figures: success
rate and movements per action (mean movements of the successful runs).

The default it selects: the cell with the highest mean success rate over the skills, then
the fewest movements per action, then the smallest table (orientation x distance bins), then
the coarsest grid (fastest learning). That default is :data:`a2l.lfd.config.DEFAULT`, which
every skill without a configuration of its own uses; the report says whether each studied
skill's configuration (:func:`a2l.lfd.library.skill_config`) is the selected one.

Output: ``cells.csv``, ``metrics.json``, ``report.md``, ``parametrization.png``.
"""

from __future__ import annotations

import itertools
import os
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from a2l.errors import ConfigError
from a2l.experiments.lfd_skills import (
    LfdTrial,
    check_package,
    learned_for,
    package_dir,
    resolve_scene,
    trial_task,
)
from a2l.lfd.config import LfDConfig
from a2l.progress import progress_bar
from a2l.robot import DEFAULT_ROBOT

__all__ = ["DEFAULT_GRID", "GRID_FIELDS", "ParametrizationCell", "cell_fields", "cell_task",
           "run_parametrization", "select_default"]

#: The command-line option of each grid dimension (``a2l experiment parametrization``).
GRID_OPTIONS = {"resolution": "--resolutions", "step": "--steps", "n_orient": "--orients",
                "n_dist": "--dists", "smoothing": "--smoothing"}

#: The LfDConfig field of each grid dimension, by its dotted name (:meth:`LfDConfig.with_`).
GRID_FIELDS = {"resolution": "resolution", "step": "discretization.step",
               "n_orient": "discretization.n_orient", "n_dist": "discretization.n_dist",
               "smoothing": "smoothing"}

#: The discretization fields a cell's row of ``cells.csv`` holds beside the others.
_CELL_DISCRETIZATION = ("step", "n_orient", "n_dist", "dist_low", "dist_high")

#: The full study's values (``--resolutions`` ... override them).
DEFAULT_GRID: dict[str, tuple[Any, ...]] = {
    "resolution": (0.005, 0.01, 0.02),
    "step": (0.02, 0.03, 0.05),
    "n_orient": (8, 16, 24, 32),
    "n_dist": (3, 4, 5),
    "smoothing": (False, True),
}


@dataclass(frozen=True)
class ParametrizationCell:
    """One skill in one cell of the grid, as a worker learns and tries it
    (:func:`cell_task`).

    Attributes
    ----------
    skill : str
        The skill (:data:`a2l.lfd.library.SKILLS`).
    cell : int
        The cell's index in the grid (``cell`` of ``cells.csv``; its bundle goes to
        ``cell<NNN>/``).
    config : LfDConfig
        The skill's configuration with the cell's values.
    seeds : tuple of int
        Trial seeds.
    scene : {"bullet", "virtual"}
        Where the trials run (:class:`a2l.experiments.lfd_skills.LfdTrial`).
    out_dir : str
        The skill's directory of learned bundles.
    package : str
        The a2l directory of the process that made the task (default: this one's); a
        worker that imported another refuses to run it.
    keep_runs : bool
        The result then holds the trials with their runs (``"trials"``,
        :func:`a2l.experiments.lfd_skills.trial_task`'s) and the ``"bundle"``, to record.
    robot : str
        The robot of scene ``bullet`` (a built-in name or a robot file), which the skill is
        learned for.
    """

    skill: str
    cell: int
    config: LfDConfig
    seeds: tuple[int, ...]
    scene: str
    out_dir: str
    package: str = field(default_factory=package_dir)
    keep_runs: bool = False
    robot: str = DEFAULT_ROBOT


def cell_task(task: ParametrizationCell) -> dict[str, Any]:
    """Learn one skill with one cell's configuration and run its trials (in a worker): the
    cell's row of ``cells.csv`` (plus its trials and bundle with ``task.keep_runs``).

    Raises
    ------
    RuntimeError
        The worker imported another copy of a2l than the parent (``task.package``).
    """
    from a2l.lfd.library import learn_recipe

    check_package(task.package)
    cfg = task.config
    t0 = time.perf_counter()
    learned = learn_recipe(task.skill, Path(task.out_dir) / f"cell{task.cell:03d}", cfg,
                           robot=learned_for(task.scene, task.robot))
    learn_s = time.perf_counter() - t0
    runs = [trial_task(LfdTrial(task.skill, str(learned.bundle), s, task.scene, "table", cfg,
                                task.package, keep_run=task.keep_runs, robot=task.robot))
            for s in task.seeds]
    ok = [r for r in runs if r["success"]]
    stops: dict[str, int] = {}
    for r in runs:
        if not r["success"]:
            stops[r["stop"]] = stops.get(r["stop"], 0) + 1
    return {"skill": task.skill, "cell": task.cell, **cell_fields(cfg.to_json()),
            "success_rate": len(ok) / len(runs),
            "movements_per_action": float(np.mean([r["movements"] for r in ok]))
            if ok else float("nan"),
            "rows": learned.rows, "table_cells": int(np.prod(learned.table.shape)),
            "learn_s": learn_s, "failures": ";".join(f"{k}:{v}" for k, v in stops.items()),
            **({"trials": runs, "bundle": str(learned.bundle)} if task.keep_runs else {})}


def cell_fields(cfg: dict[str, Any]) -> dict[str, Any]:
    """A cell's configuration (:meth:`LfDConfig.to_json`) as the flat columns of
    ``cells.csv``: its fields, the discretization's bins and step among them."""
    disc = cfg["discretization"]
    out: dict[str, Any] = {}
    for k, v in cfg.items():
        if k == "discretization":
            out.update({n: disc[n] for n in _CELL_DISCRETIZATION})
        else:
            out[k] = v
    return out


def _record(path: str | os.PathLike[str], results: Sequence[Any]) -> None:
    """Every cell's trials (their runs and bundle taken out of `results`) as one Rerun
    recording, group ``<skill>/cell<NNN>``."""
    from a2l.experiments.lfd_skills import record_trials
    from a2l.lfd.library import SKILLS
    from a2l.rollout.recording import RerunRecorder
    from a2l.skills.runner import CppSkillRunner

    rec = RerunRecorder(path, name="a2l experiment parametrization")
    for r in results:
        skill = CppSkillRunner(r.pop("bundle")).skill
        record_trials(rec, r.pop("trials"), skill, SKILLS[r["skill"]].object_name,
                      group=f"{r['skill']}/cell{r['cell']:03d}")
    rec.close()


def select_default(cells: pd.DataFrame) -> dict[str, Any]:
    """The selected cell's parameters (see the module docstring for the rule)."""
    keys = list(DEFAULT_GRID)
    g = cells.groupby(keys, as_index=False).agg(
        success_rate=("success_rate", "mean"),
        movements_per_action=("movements_per_action", "mean"))
    g["table"] = g.n_orient * g.n_dist
    g["mpa"] = g.movements_per_action.fillna(np.inf)
    g = g.sort_values(["success_rate", "mpa", "table", "resolution"],
                      ascending=[False, True, True, False], kind="mergesort")
    best = g.iloc[0]
    out = {k: best[k].item() if hasattr(best[k], "item") else best[k] for k in keys}
    out["smoothing"] = bool(out["smoothing"])
    out["success_rate"] = float(best.success_rate)
    out["movements_per_action"] = float(best.movements_per_action)
    return out


def _plot(cells: pd.DataFrame, chosen: dict[str, Any], path: Path) -> None:
    """Success rate over orientation x distance bins, one panel per step, at the chosen
    resolution and smoothing (mean over the skills)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sub = cells[(cells.resolution == chosen["resolution"])
                & (cells.smoothing == chosen["smoothing"])]
    steps = sorted(sub.step.unique())
    fig, axes = plt.subplots(1, len(steps), figsize=(4 * len(steps), 3.4), squeeze=False)
    for ax, step in zip(axes[0], steps, strict=True):
        m = sub[sub.step == step].pivot_table(index="n_dist", columns="n_orient",
                                             values="success_rate", aggfunc="mean")
        im = ax.imshow(m.to_numpy(), vmin=0, vmax=1, cmap="viridis", origin="lower")
        ax.set_xticks(range(len(m.columns)), [str(c) for c in m.columns])
        ax.set_yticks(range(len(m.index)), [str(i) for i in m.index])
        ax.set_xlabel("orientation bins")
        ax.set_ylabel("distance bins")
        ax.set_title(f"step {step * 100:.0f} cm")
        for (i, j), v in np.ndenumerate(m.to_numpy()):
            ax.text(j, i, f"{v:.2f}", ha="center", va="center", fontsize=8,
                    color="white" if v < 0.6 else "black")
    fig.colorbar(im, ax=axes[0].tolist(), label="success rate")
    fig.suptitle(f"resolution {chosen['resolution'] * 100:g} cm, smoothing "
                 f"{'on' if chosen['smoothing'] else 'off'}")
    import io

    from a2l.atomic import atomic_write_bytes

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    plt.close(fig)
    atomic_write_bytes(path, buf.getvalue())


def _write_config(run_dir: Path, names: list[str], trials: int, seed: int, scene: str,
                  workers: int, values: dict[str, Sequence[Any]], base: LfDConfig | None,
                  seeds: list[int], robot: str = DEFAULT_ROBOT) -> None:
    """Write the study's ``config.json``, with the command that reruns it."""
    from a2l.rundir import command_line, write_json
    from a2l.seeds import seed_record

    words = ["a2l", "experiment", "parametrization", "--out", run_dir, "--skills",
             ",".join(names), "--trials", trials, "--seed", seed, "--scene", scene,
             "--workers", workers, *(["--robot", robot] if scene == "bullet" else [])]
    for key, option in GRID_OPTIONS.items():
        words += [option, ",".join(("on" if v else "off") if key == "smoothing" else str(v)
                                   for v in values[key])]
    write_json(run_dir / "config.json", {
        "experiment": "parametrization", "skills": names, "trials": trials, "seed": seed,
        "scene": scene, "robot": learned_for(scene, robot), "workers": workers,
        "grid": {k: list(v) for k, v in values.items()},
        "base": None if base is None else base.to_json(),
        "command": command_line(words, base, prefix="lfd."),
        "seed_use": seed_record("parametrization", seeds)})


def _report_lines(cells: pd.DataFrame, chosen: dict[str, Any], own: dict[str, Any],
                  agrees: bool, names: list[str], scene: str, n_cells: int, trials: int,
                  seeds: list[int], wall_s: float) -> list[str]:
    """``report.md``'s lines: the selection, the skills' own configurations and a row per
    cell (best first within a skill)."""
    lines = [f"# Parametrization study ({', '.join(names)}; {scene})", "",
             f"{n_cells} cells x {trials} trials (seeds {seeds[0]}-{seeds[-1]}); "
             f"{wall_s:.0f} s.", "",
             "Selected (highest mean success, then fewest movements per action, then "
             f"smallest table, then coarsest grid): {chosen}.",
             f"The skills' configurations (a2l.lfd.library.skill_config: DEFAULT unless a "
             f"recipe has its own) are {own}: "
             + ("the same." if agrees else "**different**: not what this run selects."),
             "", "![success over bins](parametrization.png)", "",
             "| skill | resolution (cm) | step (cm) | orient | dist | smoothing | success | "
             "movements/action | rows | failures |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in cells.sort_values(["skill", "success_rate"], ascending=[True, False]).itertuples():
        lines.append(f"| {r.skill} | {r.resolution * 100:g} | {r.step * 100:g} | "
                     f"{r.n_orient} | {r.n_dist} | {'on' if r.smoothing else 'off'} | "
                     f"{r.success_rate:.2f} | {r.movements_per_action:.1f} | {r.rows} | "
                     f"{r.failures or '-'} |")
    return lines


def run_parametrization(out: str | os.PathLike[str], skills: Sequence[str] | None = None,
                        grid: dict[str, Sequence[Any]] | None = None, trials: int = 20,
                        seed: int = 500, scene: str | None = None, workers: int = 1,
                        base: LfDConfig | None = None, quiet: bool = False,
                        record: str | os.PathLike[str] | None = None,
                        robot: str = DEFAULT_ROBOT) -> dict[str, Any]:
    """The study (see the module docstring); returns the metrics written to
    ``metrics.json``. A cell's configuration is the skill's own
    (:func:`a2l.lfd.library.skill_config`, or `base`) with the cell's five values. With
    `record`, every cell's trials go to one Rerun recording (``.rrd``), group
    ``<skill>/cell<NNN>`` (the ``cell`` of ``cells.csv``), as ``lfd-skills --record``
    records its trials. `robot` (a built-in name or a robot file): the robot of scene
    ``"bullet"`` (:func:`a2l.experiments.lfd_skills.resolve_scene`)."""
    from a2l.atomic import atomic_write_text
    from a2l.lfd.library import SKILLS, skill_config
    from a2l.parallel import Executor
    from a2l.rundir import make_run_dir, write_json
    from a2l.seeds import mark_report, seed_record

    names = list(skills or [n for n in ("push_right", "grasp") if n in SKILLS])
    unknown = [n for n in names if n not in SKILLS]
    if unknown:
        raise ConfigError("--skills", f"unknown skill(s) {unknown}; known: {sorted(SKILLS)}")
    scene = resolve_scene(scene, robot)
    values = {**DEFAULT_GRID, **(grid or {})}
    combos = list(itertools.product(*(values[k] for k in DEFAULT_GRID)))
    run_dir = make_run_dir("parametrization", out)
    seeds = list(range(seed, seed + trials))
    _write_config(run_dir, names, trials, seed, scene, workers, values, base, seeds, robot)
    tasks = []
    for name in names:
        for i, combo in enumerate(combos):
            cfg = skill_config(name, base).with_(
                {GRID_FIELDS[k]: v for k, v in zip(DEFAULT_GRID, combo, strict=True)})
            tasks.append(ParametrizationCell(name, i, cfg, tuple(seeds), scene,
                                             str(run_dir / "skills" / name), package_dir(),
                                             record is not None, robot))
    t0 = time.perf_counter()
    # long cells first: the small steps take the most movements
    order = sorted(range(len(tasks)), key=lambda k: tasks[k].config.step)
    with Executor(workers) as ex, progress_bar("cells", len(tasks), quiet) as bar:
        done = ex.map(cell_task, [tasks[k] for k in order], on_done=bar)
    results = [None] * len(tasks)
    for k, r in zip(order, done, strict=True):
        results[k] = r
    if record is not None:
        _record(record, results)
    cells = pd.DataFrame(results)
    atomic_write_text(run_dir / "cells.csv", cells.to_csv(index=False))
    chosen = select_default(cells)
    own = {n: {k: cell_fields(skill_config(n, base).to_json())[k] for k in DEFAULT_GRID}
           for n in names}
    agrees = all(all(c[k] == chosen[k] for k in DEFAULT_GRID) for c in own.values())
    metrics = {"skills": names, "scene": scene,
               "robot": learned_for(scene, robot), "trial_seeds": [seeds[0], seeds[-1]],
               "grid": {k: list(v) for k, v in values.items()}, "cells": len(combos),
               "selected": chosen, "skill_configs": own,
               "default_is_selected": agrees, "wall_s": time.perf_counter() - t0}
    write_json(run_dir / "metrics.json", metrics)
    _plot(cells, chosen, run_dir / "parametrization.png")
    lines = _report_lines(cells, chosen, own, agrees, names, scene, len(combos), trials,
                          seeds, metrics["wall_s"])
    atomic_write_text(run_dir / "report.md", mark_report(
        "\n".join(lines) + "\n", seed_record("parametrization", seeds)))
    if not quiet:
        print("\n".join(lines[:6]))
        print(f"results in {run_dir}/ (report.md, metrics.json, cells.csv, "
              "parametrization.png)")
    return metrics
