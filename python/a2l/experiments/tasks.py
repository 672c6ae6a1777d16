"""``a2l experiment tasks``: planned tasks on Baxter in PyBullet, with and without faults.

Each task is a goal in PDDL reached in the ``task`` scene (button, lamp, grasp block) by
:func:`a2l.planning.execute.execute_task`: perceive, plan (pyperplan by default), then per
plan step an OMPL transit and the learned skill through the C++ step (``grasp``,
``press``), or a scripted primitive (``open-gripper``, ``close-gripper``, ``place``: no place
skill was demonstrated), perceive again, replan on a mismatch.

==========================  ======  ==========================================================
task                        skills   start -> goal; injected fault
==========================  ======  ==========================================================
``light-off-place-right``   3       light on, block mid-centre -> light off, block in the
                                    right-hand area (mid-right); fault: the light is switched
                                    back on right after the press
``tidy-light-on``           5       light off, gripper closed, block close-right -> light on,
                                    block mid-centre, gripper closed; fault: the block is
                                    dropped right after the grasp (the gripper opens)
``light-match``             3-4     light drawn, gripper closed, block mid-right -> light as
                                    drawn for the goal, block close-centre; fault: after
                                    planning (after the first step), the block is moved to
                                    another region
==========================  ======  ==========================================================

A trial is one (task, seed, fault or not): the block's start (its region's centre
± :data:`JITTER` on each axis) and the drawn light values come from ``(seed, task)`` only, so
the trial with and without its fault start alike; the fault's draw from ``(seed, task,
"fault")``. Every trial builds its own scene (0.15 s); each transit's sampler is seeded
from the trial seed, but OMPL's planner and shortener draw from its global generator, seeded
once per process, so a transit path (rarely its outcome) may differ with the worker that ran
the trial. Skills are learned once per run (demonstration seeds ``0 ..``); trial seeds default
to :data:`DEFAULT_SEED` (held out).

Output: ``skills/*.a2lb``, ``config.json``, ``trials.csv`` (one row per trial),
``plans/<task>-<seed>[-fault]/`` (every domain, problem and plan file), ``metrics.json``
(``tasks -> task -> {success_rate, success_rate_with_faults, mean_replans, plan_ms,
transit_ms, wall_s, ...}``), ``tasks.png`` and ``report.md``
(:mod:`a2l.experiments.tasks_report`).
"""

from __future__ import annotations

import os
import shlex
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from a2l.errors import ConfigError
from a2l.experiments.task_trials import (
    JITTER,
    TASKS,
    Played,
    TaskSpec,
    TaskTrial,
    learn_task_skills,
    play_task,
    trial_task,
)
from a2l.progress import print_tables, progress_bar
from a2l.robot import DEFAULT_ROBOT

__all__ = ["DEFAULT_SEED", "JITTER", "TASKS", "Played", "TaskSpec", "TaskTrial",
           "learn_task_skills", "play_task", "record_task_trials", "run_tasks", "trial_task"]

#: First trial seed by default (held out: the demonstrations use 0 .. 2 n_demos - 1).
DEFAULT_SEED = 7000


def _check(tasks: Sequence[str], trials: int, seed: int, workers: int, robot: str) -> None:
    unknown = [t for t in tasks if t not in TASKS]
    if unknown or not tasks:
        raise ConfigError("--tasks", f"unknown task(s) {unknown}; known: {list(TASKS)}")
    if trials < 1:
        raise ConfigError("--trials", f"must be >= 1, got {trials}")
    if workers < 1:
        raise ConfigError("--workers", f"must be >= 1, got {workers}")
    if seed < 16:
        raise ConfigError("--seed", f"trial seeds {seed}.. overlap the demonstration seeds "
                         f"0..15; use a seed >= 16 (default {DEFAULT_SEED})")
    from a2l.errors import A2LError
    from a2l.robot import robot_entry
    from a2l.sim.config import make_config

    try:
        entry = robot_entry(robot)
    except A2LError as exc:
        raise ConfigError("--robot", str(exc)) from None
    if entry.gripper is None:
        raise ConfigError("--robot", f"robot '{entry.name}' has no gripper: the tasks grasp "
                          "their block")
    try:  # every object of its task scene on the table
        make_config("task", robot=robot)
    except A2LError as exc:
        raise ConfigError("--robot", f"robot '{entry.name}', its task scene: {exc}") from None


def run_tasks(out: str | os.PathLike[str], tasks: Sequence[str] | None = None,
              trials: int = 20, seed: int = DEFAULT_SEED, workers: int = 1,
              faults: Sequence[bool] = (False, True), planner: str = "pyperplan",
              quiet: bool = False, plots: bool = True,
              context_source: str = "perceived",
              record: str | os.PathLike[str] | None = None,
              robot: str = DEFAULT_ROBOT) -> dict[str, Any]:
    """Learn the skills, run every trial and write the run directory.

    Parameters
    ----------
    out : path
        Run directory.
    tasks : sequence of str, optional
        Default: every task of :data:`TASKS`.
    trials : int
        Trials per task and fault condition (seeds ``seed .. seed + trials - 1``).
    seed : int
        First trial seed.
    workers : int
        Local worker processes (:class:`a2l.parallel.Executor`).
    faults : sequence of bool
        The conditions run: without (False) and with (True) the task's fault.
    planner : {"pyperplan", "fast-downward"}
    quiet, plots : bool
        No progress bar / no figure.
    context_source : {"perceived", "ground_truth"}
        Where the skills and the planner's state read the scene: the camera (default) or
        the simulator's truth; the report names it.
    record : path, optional
        A Rerun recording (``.rrd``) of every trial (:func:`record_task_trials`).
    robot : str
        The robot of the task scenes (a built-in robot's name or a robot file): the
        transits are planned for its arm. The skills are learned as always
        (:func:`learn_task_skills`: they move relative to the object and name no robot).

    Returns
    -------
    dict
        The content of ``metrics.json``.
    """
    import pandas as pd

    from a2l.atomic import atomic_write_text
    from a2l.experiments.tasks_report import summarise, write_report
    from a2l.parallel import Executor
    from a2l.rundir import make_run_dir, write_json
    from a2l.seeds import seed_record

    names = list(tasks) if tasks else list(TASKS)
    _check(names, trials, seed, workers, robot)
    if context_source not in ("perceived", "ground_truth"):
        raise ConfigError("--context_source", f"must be 'perceived' or 'ground_truth', got "
                          f"{context_source!r}")
    out_path = Path(out)
    if out_path.exists() and not out_path.is_dir():
        raise ConfigError("--out", f"'{out_path}' exists and is not a directory")
    run_dir = make_run_dir("tasks", out_path)
    command = shlex.join(["a2l", "experiment", "tasks", "--out", str(run_dir), "--tasks",
                          ",".join(names), "--trials", str(trials), "--seed", str(seed),
                          "--workers", str(workers), "--planner", planner,
                          "--context_source", context_source]
                         + ([] if robot == DEFAULT_ROBOT else ["--robot", robot])
                         + ([] if list(faults) == [False, True] else
                            ["--faults", "with" if list(faults) == [True] else "without"]))
    config = {"experiment": "tasks", "tasks": {n: {
        "description": TASKS[n].description, "start_region": TASKS[n].start_region,
        "gripper": TASKS[n].gripper, "light": TASKS[n].light, "fault": TASKS[n].fault}
        for n in names}, "trial_seeds": [seed, seed + trials - 1], "faults": list(faults),
        "jitter_m": JITTER, "planner": planner, "context_source": context_source,
        "workers": workers, "robot": robot, "command": command,
        "seed_use": seed_record("tasks", range(seed, seed + trials))}
    write_json(run_dir / "config.json", config)
    t0 = time.perf_counter()
    bundles = learn_task_skills(run_dir / "skills")
    learn_s = time.perf_counter() - t0
    jobs = [TaskTrial(n, s, f, bundles, str(run_dir / "plans"), planner,
                      context_source=context_source, trace=record is not None, robot=robot)
            for n in names for f in faults for s in range(seed, seed + trials)]
    with Executor(workers) as ex, progress_bar("task trials", len(jobs), quiet) as bar:
        rows = ex.map(trial_task, jobs, on_done=bar)
    wall = time.perf_counter() - t0
    if record is not None:
        record_task_trials(record, rows)
    frame = pd.DataFrame(rows)
    atomic_write_text(run_dir / "trials.csv", frame.to_csv(index=False))
    metrics = {"experiment": "tasks", "trial_seeds": config["trial_seeds"],
               "planner": planner, "context_source": context_source,
               "tasks": summarise(frame), "learn_s": learn_s,
               "wall_s": wall, "workers": workers}
    write_json(run_dir / "metrics.json", metrics)
    text = write_report(run_dir, metrics, config, frame, plots=plots)
    if not quiet:
        print_tables(text)
        print(f"results in {run_dir}/ (report.md, metrics.json, trials.csv, tasks.png)")
    return metrics


def record_task_trials(path: str | os.PathLike[str], rows: list[dict[str, Any]]) -> None:
    """Write the trials' executed steps (the ``"trace"`` of each row, taken out) as a Rerun
    recording at `path`: group ``<task>/fault`` or ``<task>/no_fault``, one rollout per
    trial in seed order; a row per executed plan step: the end-effector and the block (and
    the other objects) where the simulator had them after it, the step and how it ended as
    the movement's label; a line with the seed, the goal and how the trial ended."""
    from a2l.rollout.recording import RerunRecorder, record_trajectories

    rec = RerunRecorder(path, name="a2l experiment tasks")
    groups: dict[str, list[dict[str, Any]]] = {}
    for r in rows:
        groups.setdefault(f"{r['task']}/{'fault' if r['fault'] else 'no_fault'}", []).append(r)
    for group, trials in groups.items():
        paths, notes, labels, others = {}, {}, {}, {}
        for r in trials:
            trace, key = r.pop("trace"), f"seed {r['seed']}"
            paths[key] = (np.array([e for _, e, _ in trace]),
                          np.array([o["block"] for _, _, o in trace]))
            labels[key] = [lab for lab, _, _ in trace[1:]]
            others[key] = {n: np.array([o[n] for _, _, o in trace])
                           for n in trace[0][2] if n != "block"}
            notes[key] = (f"{r['task']} seed {r['seed']}{' with its fault' if r['fault'] else ''}"
                          f": {'success' if r['success'] else 'failure'}, goal {r['goal']}, "
                          f"{r['replans']} replan(s)"
                          + (f", fault {r['fault_injected']}" if r["fault_injected"] else ""))
        record_trajectories(rec, paths, notes, object_name="block", group=group,
                            labels=labels, others=others)
    rec.close()
