"""``a2l experiment perturbations``: demonstrated skills under perturbations.

Every skill of :data:`a2l.lfd.library.SKILLS` is demonstrated (demonstration seeds
``0 .. n_demos - 1``), learned (:func:`a2l.lfd.library.learn_recipe`) and run in closed loop
on Baxter in PyBullet from held-out trial seeds (default ``5000 .. 5049``: no demonstration,
no tuning and no other experiment used them), under four conditions:

- ``none``: no perturbation;
- ``move_object``: mid-action, the object is teleported 3-5 cm in a random direction on the
  table;
- ``hold``: mid-action, the end-effector is held for 1-2 s: the skill goes on commanding
  movements, the arm does not move (:meth:`a2l.sim.Scene.perturb` ``"hold"``, one movement's
  time per commanded movement);
- ``toggle_light``: mid-action, the light is switched. A skill that does not depend on the
  light must do exactly what it did without the toggle; the light-dependent grasp must do
  what its demonstration under the new state did (grasp with the light off, move away and
  wait with it on).

Each condition runs twice: the context skill (the compiled table, ``mode="table"``) and the
DS alone (``mode="ds"``). A trial task is one (skill, mode, seed): it runs ``none`` first;
the perturbed runs replay it (same seed, same start: the runs are identical up to the
perturbation, which the task checks) and perturb after movement ``m``, ``m`` drawn from the
trial's seed between one and two thirds of the unperturbed run's movements. Every
perturbation draw comes from ``(seed, condition)`` only, so results do not depend on the
workers (one, two or a Dask cluster give the same metrics). The trial itself:
:mod:`a2l.experiments.perturbation_trials`.

Scenes: a skill runs in its recipe's scene if that scene has a light, else in the scene
with the same object and a lamp (``push`` -> ``press``: the box and a button with its lamp;
``grasp`` -> ``grasp_light``), so the toggle really switches a light; every condition of a
skill uses the same scene. Context from the camera by default (``context_source``, as
:func:`make_skill_scene`), or from the ground truth; the report names it.

Effect tests: the recipe's, except ``pressed`` (counted from the button's presses, since the
toggle itself switches the light) and the light-dependent skill (the test of the effect its
demonstrations produced under the light state now seen).

Output: ``skills/*.a2lb``, ``config.json``, ``trials.csv`` (one row per run),
``trajectories.npz``, ``metrics.json`` (``skills -> skill -> condition -> {context, ds,
mean_steps, ...}``), ``report.md`` and one plot per skill and condition
(:mod:`a2l.experiments.perturbation_report`).
"""

from __future__ import annotations

import io
import os
import shlex
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from a2l.errors import ConfigError
from a2l.experiments.perturbation_trials import (
    CONDITIONS,
    HOLD_RANGE,
    MODES,
    MOVE_RANGE,
    WINDOW,
    Perturbation,
    PerturbationTrial,
    draw_perturbation,
    skill_scene,
    trial_task,
)
from a2l.lfd.config import LfDConfig
from a2l.progress import print_tables, progress_bar
from a2l.robot import DEFAULT_ROBOT
from a2l.rundir import command_line

__all__ = ["CONDITIONS", "DEFAULT_SEED", "HOLD_RANGE", "MODES", "MOVE_RANGE", "Perturbation",
           "PerturbationTrial", "demonstration_seeds", "draw_perturbation", "run_perturbations",
           "skill_cfg", "trial_task"]

#: First trial seed by default (held out: demonstrations use 0 .. n_demos - 1,
#: ``a2l experiment lfd-skills`` 1040 ...).
DEFAULT_SEED = 5000


@dataclass(frozen=True)
class _LearnTask:
    """One skill to learn, as a worker learns it (:func:`_learn`).

    Attributes
    ----------
    skill : str
        The skill (:data:`a2l.lfd.library.SKILLS`).
    out_dir : str
        Where its bundle goes.
    config : LfDConfig
        Its configuration (:func:`skill_cfg`).
    robot : str
        The robot it is learned for (a built-in name or a robot file).
    """

    skill: str
    out_dir: str
    config: LfDConfig
    robot: str = DEFAULT_ROBOT


def _learn(task: _LearnTask) -> dict[str, Any]:
    """Learn one skill: its entry of ``metrics.json``'s ``learning`` (``skill``,
    ``bundle``, ``rows``, ``seconds``)."""
    from a2l.lfd.library import learn_recipe

    t0 = time.perf_counter()
    learned = learn_recipe(task.skill, task.out_dir, task.config, robot=task.robot)
    return {"skill": task.skill, "bundle": str(learned.bundle), "rows": int(learned.rows),
            "seconds": time.perf_counter() - t0}


def _record(path: str | os.PathLike[str], rows: Sequence[dict[str, Any]],
            trajectories: dict[str, np.ndarray]) -> None:
    """Write the trials' paths as a Rerun recording at `path` (one rollout per trial)."""
    from a2l.rollout.recording import RerunRecorder, record_trajectories

    paths, notes = {}, {}
    for r in rows:
        name = f"{r['skill']}/{r['condition']}/{r['mode']}/{r['seed']}"
        paths[name] = (trajectories[f"{name}/eef"], trajectories[f"{name}/obj"])
        notes[name] = f"{name}: {'success' if r['success'] else 'failure'} ({r['stop']})"
    rec = RerunRecorder(path, "a2l perturbations")
    record_trajectories(rec, paths, notes)
    rec.close()


def skill_cfg(name: str, cfg: LfDConfig | None = None) -> LfDConfig:
    """The configuration skill `name` is learned and run with: `cfg`, else the recipe's
    own (``SkillRecipe.config``), else :data:`a2l.lfd.config.DEFAULT`."""
    from a2l.lfd.library import skill_config

    return skill_config(name, cfg)


def demonstration_seeds(cfgs: dict[str, LfDConfig]) -> list[int]:
    """``[0, last]``: the seeds the demonstrations may use (a skill with two behaviours
    demonstrates each ``n_demos`` times: ``2 n_demos`` seeds, counted for every skill)."""
    return [0, 2 * max(c.n_demos for c in cfgs.values()) - 1]


def _check(skills: Sequence[str], conditions: Sequence[str], trials: int, seed: int,
           workers: int, cfg: LfDConfig | None) -> None:
    """Raise ValueError naming the first bad argument."""
    from a2l.lfd.library import SKILLS

    unknown = [s for s in skills if s not in SKILLS]
    if unknown or not skills:
        raise ConfigError("--skills", f"unknown skill(s) {unknown}; known: {sorted(SKILLS)}")
    bad = [c for c in conditions if c not in CONDITIONS]
    if bad or not conditions:
        raise ConfigError("--conditions", f"unknown condition(s) {bad}; known: {list(CONDITIONS)}")
    if trials < 1:
        raise ConfigError("--trials", f"must be >= 1, got {trials}")
    if workers < 1:
        raise ConfigError("--workers", f"must be >= 1, got {workers}")
    last = demonstration_seeds({n: skill_cfg(n, cfg) for n in skills})[1]
    if seed <= last:
        raise ConfigError("--seed", f"trial seeds {seed}.. overlap the demonstration seeds "
                         f"0..{last}; use a seed > {last} (default {DEFAULT_SEED})")


def run_perturbations(out: str | os.PathLike[str], skills: Sequence[str] | None = None,
                      trials: int = 50, seed: int = DEFAULT_SEED, workers: int = 1,
                      cluster: str | None = None, conditions: Sequence[str] = CONDITIONS,
                      cfg: LfDConfig | None = None, bundles: dict[str, str] | None = None,
                      quiet: bool = False, plots: bool = True,
                      command: str | None = None,
                      context_source: str = "perceived",
                      record: str | os.PathLike[str] | None = None,
                      robot: str = DEFAULT_ROBOT) -> dict[str, Any]:
    """Learn the skills, run every trial under every condition and write the run directory.

    Parameters
    ----------
    out : path
        Run directory.
    skills : sequence of str, optional
        Default: every skill of :data:`a2l.lfd.library.SKILLS`.
    trials : int
        Trials (seeds ``seed .. seed + trials - 1``) per skill, condition and mode.
    seed : int
        First trial seed (above the demonstration seeds, :func:`demonstration_seeds`).
    workers, cluster
        Where trials run (:class:`a2l.parallel.Executor`).
    conditions : sequence of str
        Subset of :data:`CONDITIONS`.
    cfg : LfDConfig, optional
        The pipeline's configuration for every skill (default: each skill's own,
        :func:`skill_cfg`).
    bundles : dict of str to path, optional
        Already learned bundles (skill -> path): not learned again.
    quiet, plots : bool
        No progress bar / no figures.
    command : str, optional
        The command line recorded in the report.
    context_source : {"perceived", "ground_truth"}
        Where the skills read the context: the camera (default) or the simulator's truth.
    record : path, optional
        A Rerun recording (``.rrd``) of every trial, one rollout each, named
        ``skill/condition/mode/seed`` with how it ended (``a2l view FILE``).
    robot : str
        The robot the skills are learned for and tried on: a built-in name (default
        ``baxter``) or a robot file (:func:`a2l.robot.robot_entry`); the scenes put the
        objects at its work point. The perturbations' sizes are the thesis' (not scaled).

    Returns
    -------
    dict
        The content of ``metrics.json``.
    """
    from a2l.atomic import atomic_write_bytes, atomic_write_text
    from a2l.experiments.perturbation_report import summarise, write_report
    from a2l.lfd.library import SKILLS
    from a2l.parallel import Executor
    from a2l.rundir import make_run_dir, write_json
    from a2l.seeds import seed_record

    names = list(skills) if skills else list(SKILLS)
    conds = [c for c in CONDITIONS if c in conditions] if conditions else []
    _check(names, list(conditions), trials, seed, workers, cfg)
    if context_source not in ("perceived", "ground_truth"):
        raise ConfigError("--context_source", f"must be 'perceived' or 'ground_truth', got "
                          f"{context_source!r}")
    cfgs = {n: skill_cfg(n, cfg) for n in names}
    out_path = Path(out)
    if out_path.exists() and not out_path.is_dir():
        raise ConfigError("--out", f"'{out_path}' exists and is not a directory")
    run_dir = make_run_dir("perturbations", out_path)
    seeds = list(range(seed, seed + trials))
    scenes = {n: skill_scene(SKILLS[n]) for n in names}
    command = command or shlex.join(
        ["a2l", "experiment", "perturbations", "--out", str(run_dir), "--skills",
         ",".join(names), "--trials", str(trials), "--seed", str(seed), "--workers",
         str(workers)] + (["--cluster", cluster] if cluster else [])
        + ([] if conds == list(CONDITIONS) else ["--conditions", ",".join(conds)])
        + ["--context_source", context_source]
        + ([] if robot == DEFAULT_ROBOT else ["--robot", robot]))
    if cfg is not None:  # the skills' configuration given: its every field on the command
        command = command_line(shlex.split(command), cfg, prefix="lfd.")
    config = {"experiment": "perturbations", "skills": names, "conditions": conds,
              "modes": list(MODES), "trial_seeds": [seeds[0], seeds[-1]],
              "demonstration_seeds": demonstration_seeds(cfgs), "scenes": scenes,
              "window": list(WINDOW), "move_m": list(MOVE_RANGE), "hold_s": list(HOLD_RANGE),
              "lfd": {n: c.to_json() for n, c in cfgs.items()}, "workers": workers,
              "cluster": cluster, "command": command, "context_source": context_source,
              "robot": robot, "seed_use": seed_record("perturbations", seeds)}
    write_json(run_dir / "config.json", config)
    t0 = time.perf_counter()
    with Executor(workers, cluster) as ex:
        todo = [n for n in names if not bundles or n not in bundles]
        learned = ex.map(_learn, [_LearnTask(n, str(run_dir / "skills"), cfgs[n], robot)
                                  for n in todo])
        learning = {r["skill"]: r for r in learned}
        paths = {**{n: str(b) for n, b in (bundles or {}).items() if n in names},
                 **{r["skill"]: r["bundle"] for r in learned}}
        tasks = [PerturbationTrial(n, paths[n], m, s, scenes[n], tuple(conds), cfgs[n],
                                   context_source, robot)
                 for n in names for m in MODES for s in seeds]
        with progress_bar("perturbation trials", len(tasks), quiet) as bar:
            results = ex.map(trial_task, tasks, on_done=bar)
    rows = [r for chunk in results for r in chunk]
    wall = time.perf_counter() - t0
    trajectories = {f"{r['skill']}/{r['condition']}/{r['mode']}/{r['seed']}/{k}": r.pop(k)
                    for r in rows for k in ("eef", "obj")}
    buf = io.BytesIO()
    np.savez_compressed(buf, **trajectories)
    atomic_write_bytes(run_dir / "trajectories.npz", buf.getvalue())
    frame = pd.DataFrame(rows)
    atomic_write_text(run_dir / "trials.csv", frame.to_csv(index=False))
    metrics = {"experiment": "perturbations", "trial_seeds": config["trial_seeds"],
               "demonstration_seeds": config["demonstration_seeds"], "scenes": scenes,
               "context_source": context_source, "robot": robot,
               "skills": summarise(frame), "learning": learning, "wall_s": wall,
               "workers": workers}
    write_json(run_dir / "metrics.json", metrics)
    if record is not None:
        _record(record, rows, trajectories)
    text = write_report(run_dir, metrics, config, frame, trajectories, plots=plots)
    if not quiet:
        print_tables(text)
        print(f"results in {run_dir}/ (report.md, metrics.json, trials.csv, plots)")
    return metrics
