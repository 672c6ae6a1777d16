"""Seed sweep of the push experiment: ``a2l experiment sweep``.

Runs :func:`a2l.experiments.push.run_push_experiment` once per seed with one configuration
and writes how many iterations (iteration 0 included) each seed needed to reach score 100:
the table of ``docs/framework.md``. The sweep directory holds ``config.json`` (the base
configuration, the overrides, the seeds and the command), one push run directory per seed
(``seed_NNN/``), ``metrics.json`` (one row per seed and the summary) and ``report.md``. A
sweep interrupted between seeds continues where it stopped when run again with the same
``--out`` (finished seeds are read back, an unfinished one is resumed).

With several workers, seeds run at once, each in its own worker process with its rollouts
in that process (:func:`seed_run`): a run's skill learning and bookkeeping, serial in its
process, then overlap another seed's, where one run on several workers leaves the workers
waiting for them. A run does not depend on where it runs (the framework's results do not
depend on the number of workers), so the rows are those of the seeds run one by one.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from a2l.atomic import atomic_write_text
from a2l.experiments.push import final_validation, record_validations, run_push_experiment
from a2l.framework import FrameworkConfig
from a2l.framework.presets import preset_of
from a2l.parallel import Executor
from a2l.progress import print_tables
from a2l.rollout.env import LEGACY_SCENES
from a2l.rundir import make_run_dir, read_json, write_json
from a2l.seeds import mark_report, seed_record

__all__ = ["SeedJob", "headline_table", "iterations_to_full_score", "run_seed_sweep",
           "seed_run", "summarize_sweep"]


def iterations_to_full_score(iterations: Sequence[dict[str, Any]]) -> int | None:
    """Iterations run (iteration 0 included) until the first score of 100, or None.

    Parameters
    ----------
    iterations : sequence of dict
        ``metrics.json``'s ``iterations`` (each with ``iteration`` and ``score``).
    """
    for m in iterations:
        if m["score"] >= 100.0:
            return int(m["iteration"]) + 1
    return None


def summarize_sweep(rows: Sequence[dict[str, Any]], within: int = 3) -> dict[str, Any]:
    """Counts and statistics of a sweep's rows (``seed``, ``iterations_to_100``).

    Returns
    -------
    dict
        ``runs``, ``reached`` (runs that reached 100), ``within`` and ``reached_within``
        (those that did within `within` iterations), and ``min``, ``max``, ``median``,
        ``mean`` of the iterations of the runs that reached 100 (None if none did).
    """
    its = np.array([r["iterations_to_100"] for r in rows if r["iterations_to_100"] is not None],
                   dtype=float)
    stats: dict[str, Any] = {"min": None, "max": None, "median": None, "mean": None}
    if its.size:
        stats = {"min": int(its.min()), "max": int(its.max()),
                 "median": float(np.median(its)), "mean": float(its.mean())}
    return {"runs": len(rows), "reached": int(its.size), "within": within,
            "reached_within": int((its <= within).sum()), **stats}


def headline_table(metrics: dict[str, Any]) -> str:
    """One-row Markdown table of a sweep's ``metrics.json``: seeds, the final skills' success
    rate from held-out starts (a false positive is a failure: mean and lowest over the
    seeds), how many seeds reach 100 (and within how many iterations) and the iterations to
    100 (median, range; iteration 0 counted)."""
    s, rows = metrics["summary"], metrics["rows"]
    seeds = [r["seed"] for r in rows]
    its = "—" if s["median"] is None else f"{s['median']:g} ({s['min']}–{s['max']})"
    held = [r["heldout_success"] for r in rows if r.get("heldout_success") is not None]
    rate = (f"{100 * np.mean(held):.1f} % (lowest {100 * min(held):.1f} %)" if held
            else "—")
    return "\n".join([
        "| seeds | held-out success rate (mean, lowest) | reach 100 | within "
        + str(s["within"]) + " iterations | iterations to 100 (median, range) |",
        "|---|---|---|---|---|",
        f"| {seeds[0]}–{seeds[-1]} ({s['runs']}) | {rate} | {s['reached']} of {s['runs']} | "
        f"{s['reached_within']} of {s['runs']} | {its} |"])


def _table(rows: Sequence[dict[str, Any]], summary: dict[str, Any]) -> str:
    cells = [("x" if r["iterations_to_100"] is None else str(r["iterations_to_100"]))
             for r in rows]
    lines = ["| seed | held-out success | iterations to 100 | final score | iterations run |",
             "|---|---|---|---|---|"]
    lines += [f"| {r['seed']} | {_rate(r.get('heldout_success'))} | {c} | "
              f"{r['final_score']:.1f} | {r['iterations_run']} |"
              for r, c in zip(rows, cells, strict=True)]
    held = [r["heldout_success"] for r in rows if r.get("heldout_success") is not None]
    s = summary
    seeds = [r["seed"] for r in rows]
    lines += [
        "",
        f"Seeds {seeds[0]}–{seeds[-1]} ({s['runs']} runs): {s['reached']} of {s['runs']} reach "
        f"100; {s['reached_within']} of {s['runs']} within {s['within']} iterations"
        + ("" if s["median"] is None else
           f"; iterations {s['min']} to {s['max']} (median {s['median']:g}, "
           f"mean {s['mean']:.1f})") + ". \"x\": not within the run's iterations."
        + (f" Held-out success rate (final skill; a false positive is a failure): mean "
           f"{np.mean(held):.1%}, lowest {min(held):.1%}, {sum(h >= 0.98 for h in held)} of "
           f"{len(held)} seeds at 98 % or more." if held else ""),
        "",
        "Iterations per seed, in order: " + ", ".join(cells) + ".",
    ]
    return "\n".join(lines)


def _rate(x: float | None) -> str:
    return "—" if x is None else f"{x:.0%}"


@dataclass(frozen=True)
class SeedJob:
    """One seed of a sweep, as :func:`seed_run` runs it.

    Attributes
    ----------
    config : FrameworkConfig
        The sweep's configuration (its seed is replaced by `seed`).
    seed : int
        The run's seed.
    run_dir : str
        The run's directory.
    workers : int
        Local worker processes for its rollouts, without `executor`.
    executor : a2l.parallel.Executor or None
        Where its rollouts run, shared with the other seeds.
    announce : bool
        Print a line when the run ends.
    """

    config: FrameworkConfig
    seed: int
    run_dir: str
    workers: int = 1
    executor: Executor | None = None
    announce: bool = False


def seed_run(job: SeedJob) -> dict[str, Any]:
    """One seed of a sweep: its run directory's ``metrics.json`` read back when it is
    finished, the run resumed when it was started, else run (quietly, without plots) on
    ``job.executor`` when one is given, else on ``job.workers`` local worker processes;
    with ``job.announce``, a line saying how it ended is printed (by the process that ran
    it, as it ends).

    Returns
    -------
    dict
        The row of the sweep's table: ``seed``, ``iterations_to_100``, ``final_score``,
        ``heldout_success`` (the final skill's success rate from the held-out starts),
        ``iterations_run``, ``wall_s``.
    """
    seed, executor, workers, announce = job.seed, job.executor, job.workers, job.announce
    sub = Path(job.run_dir)
    opts: dict[str, Any] = {"quiet": True, "plots": False}
    opts.update({"executor": executor} if executor is not None else {"workers": workers})
    if (sub / "metrics.json").is_file():
        m = read_json(sub / "metrics.json")
    elif (sub / "config.json").is_file():
        m = run_push_experiment(resume=sub, **opts)
    else:
        m = run_push_experiment(job.config.with_(seed=seed), out=sub, **opts)
    row = {"seed": seed, "iterations_to_100": iterations_to_full_score(m["iterations"]),
           "final_score": float(m["final_score"]), "iterations_run": len(m["iterations"]),
           "heldout_success": m.get("heldout_success"),
           "wall_s": float(m["wall_s"])}
    if announce:
        n = row["iterations_to_100"]
        print(f"seed {seed:3d}: score {row['final_score']:.1f} after "
              f"{row['iterations_run']} iteration(s); "
              f"{'not 100' if n is None else f'100 at iteration {n - 1}'}", flush=True)
    return row


def run_seed_sweep(base: FrameworkConfig | None = None, seeds: Sequence[int] = range(30),
                   overrides: dict[str, Any] | None = None, out: str | Path | None = None,
                   workers: int = 1, quiet: bool = False, command: str | None = None,
                   record: str | Path | None = None) -> dict[str, Any]:
    """Run the push experiment once per seed and tabulate the iterations to score 100.

    Parameters
    ----------
    base : FrameworkConfig, optional
        Everything but the seed (default: the default configuration).
    seeds : sequence of int
        The seeds, in order.
    overrides : dict, optional
        FrameworkConfig fields to change from `base` (``a2l experiment sweep --set``).
    out : path, optional
        Sweep directory (default ``runs/sweep-<timestamp>``); rerunning with the same one
        continues an interrupted sweep (it must hold the same configuration).
    workers : int
        Local worker processes. With as many seeds left to run, that many seeds run at once,
        each in one worker process with its rollouts in that process; with fewer, the
        workers are shared out among them as their rollout workers; 1: everything in this
        process.
    quiet : bool
        No line per seed.
    command : str, optional
        The command line that made the sweep, kept in ``config.json``.
    record : path, optional
        A Rerun recording (``.rrd``) of every seed's final validation, as ``a2l experiment
        push --record`` writes one run's, under ``seed/<seed>/rollout/<i>/``.

    Returns
    -------
    dict
        ``{"rows": [...], "summary": {...}, "run_dir": str}`` (also ``metrics.json``, with
        ``"preset"``, the preset the configuration is, :func:`a2l.framework.presets.preset_of`,
        when it is one).

    Raises
    ------
    ValueError
        An override out of its domain (from FrameworkConfig.validate), no seed, or `out`
        holding a sweep of another configuration.
    """
    seeds = list(seeds)
    if not seeds:
        raise ValueError("seeds: no seed to run")
    cfg0 = (base or FrameworkConfig()).with_(overrides or {})
    run_dir = make_run_dir("sweep", out)
    config = {"experiment": "sweep", "framework": cfg0.to_dict(),
              "overrides": overrides or {}, "seeds": seeds, "command": command,
              "seed_use": seed_record("sweep", seeds)}
    if (run_dir / "config.json").is_file():
        old = read_json(run_dir / "config.json")
        # compared as JSON (what config.json holds); an earlier scene name is the scene
        # and robot it names now
        framework = json.loads(json.dumps(config["framework"]))
        old_framework = old.get("framework")
        if isinstance(old_framework, dict) and old_framework.get("scene") in LEGACY_SCENES:
            scene, robot = LEGACY_SCENES[old_framework["scene"]]
            old_framework = {**old_framework, "scene": scene, "robot": robot}
        if (old_framework, old.get("seeds")) != (framework, seeds):
            raise ValueError(f"'{run_dir}' holds a sweep of another configuration or other "
                             "seeds; choose another --out")
    else:
        write_json(run_dir / "config.json", config)
    subs = {seed: str(run_dir / f"seed_{seed:03d}") for seed in seeds}
    todo = [seed for seed in seeds if not (Path(subs[seed]) / "metrics.json").is_file()]
    at_once = max(1, min(workers, len(todo)))
    if at_once == 1:
        # one run at a time in this process, all on one pool of `workers` rollout workers
        with Executor(workers=workers) as executor:
            rows = [seed_run(SeedJob(cfg0, seed, subs[seed], workers, executor, not quiet))
                    for seed in seeds]
    else:
        # `at_once` runs at a time, each in a worker process of its own (one seed per task)
        per_run = max(1, workers // at_once)
        by_seed = {seed: seed_run(SeedJob(cfg0, seed, subs[seed], 1, None, not quiet))
                   for seed in seeds if seed not in todo}
        with Executor(workers=at_once) as pool:
            ran = pool.map(seed_run, [SeedJob(cfg0, seed, subs[seed], per_run, None, not quiet)
                                      for seed in todo], batches=len(todo))
        by_seed.update(zip(todo, ran, strict=True))
        rows = [by_seed[seed] for seed in seeds]
    if record is not None:
        record_validations(record, {f"seed/{seed}": final_validation(subs[seed])
                                    for seed in seeds}, name="a2l experiment sweep")
    summary = summarize_sweep(rows)
    table = _table(rows, summary)
    preset = preset_of(cfg0.to_dict())
    write_json(run_dir / "metrics.json", {"rows": rows, "summary": summary,
                                          **({"preset": preset} if preset else {})})
    changed = ", ".join(f"`{k} = {v}`" for k, v in (overrides or {}).items()) or "none"
    atomic_write_text(run_dir / "report.md", mark_report(
        "# Seed sweep of the push experiment\n\n"
        f"Scene {cfg0.scene}, {cfg0.discretization.n_effects} effects, "
        f"{cfg0.starts.n_starts} starts, at most "
        f"{cfg0.max_iterations} iterations; changed from the defaults: {changed}.\n"
        + (f"Command: `{command}`\n" if command else "") + "\n" + table + "\n",
        seed_record("sweep", seeds)))
    if not quiet:
        print_tables(table)
        print(f"sweep directory: {run_dir}")
    return {"rows": rows, "summary": summary, "run_dir": str(run_dir)}

