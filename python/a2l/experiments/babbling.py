"""The babbling experiment (thesis chapter 4): NovEB against random motor babbling and
random goal babbling, with the same trajectory encoding and budget, on Baxter's push scene
(one box) or two boxes far apart.

``a2l experiment babbling`` runs one method with one seed and writes a run directory:
``config.json``, ``metrics.json`` (per generation: ``moved_share``, ``distinct_outcomes``,
``archive_size``; and the totals), ``evaluations.parquet`` (one row per evaluation),
``paths.npz`` (end-effector paths), ``visits.png``, ``progress.png`` and ``report.md``.
``a2l experiment babbling-compare`` runs every method over several seeds and writes the
side-by-side plots and the table of means and spreads (:mod:`a2l.experiments.babbling_plots`).

A generation is ``generation_size`` evaluations for every method (NovEB's λ, and μ for its
first one): the batches in which strategies are asked and told.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from a2l.acquisition.goal_babbling import GoalBabbling, RandomTrajectories
from a2l.acquisition.noveb import NovEB, NovEBConfig
from a2l.acquisition.protocol import Strategy, drive
from a2l.atomic import atomic_write_text
from a2l.experiments.babbling_plots import plot_progress, plot_visits
from a2l.experiments.babbling_world import Evaluation, EvaluationTask, WorldConfig, evaluate_task
from a2l.parallel import Executor
from a2l.progress import ProgressBars
from a2l.rundir import command_line, make_run_dir, write_json
from a2l.seeds import mark_report, seed_record
from a2l.skills.effects import effect_name

__all__ = ["METHODS", "make_strategy", "outcome_keys", "record_babbling", "run_babbling"]

#: The methods compared.
METHODS = ("noveb", "random", "goal")

#: An object moved when its displacement on the table exceeds this (m).
MOVED = 0.01
#: Final object positions are binned on a grid of this side (m) for distinct outcomes.
OUTCOME_BIN = 0.05


def make_strategy(method: str, n_genes: int, seed: int, budget: int,
                  generation_size: int) -> Strategy:
    """The strategy of `method` (``noveb``, ``random`` or ``goal``)."""
    if method == "noveb":
        return NovEB(n_genes, seed, budget,
                     NovEBConfig(mu=generation_size, lambda_=generation_size))
    if method == "random":
        return RandomTrajectories(n_genes, seed, budget)
    if method == "goal":
        return GoalBabbling(n_genes, seed, budget, bootstrap=generation_size)
    raise ValueError(f"method: unknown {method!r}; choose one of {list(METHODS)}")


def outcome_keys(ev: Evaluation) -> set[tuple[str, str, int, int]]:
    """The outcomes an evaluation reached: for each object that moved, (object, effect
    class, binned final x, binned final y)."""
    keys = set()
    for name, (dx, dy) in ev.displacement.items():
        if np.hypot(dx, dy) > MOVED:
            effect = effect_name((dx, dy), 4, MOVED)
            x, y = ev.final[name]
            keys.add((name, effect, int(np.floor(x / OUTCOME_BIN)),
                      int(np.floor(y / OUTCOME_BIN))))
    return keys


def _moved(ev: Evaluation) -> bool:
    return any(np.hypot(dx, dy) > MOVED for dx, dy in ev.displacement.values())


def _check_arguments(method: str, evaluations: int, generation_size: int) -> None:
    if method not in METHODS:
        raise ValueError(f"method: unknown {method!r}; choose one of {list(METHODS)}")
    if evaluations < 1 or generation_size < 1:
        raise ValueError(f"evaluations and generation_size must be >= 1, got {evaluations}, "
                         f"{generation_size}")


def _write_config(run_dir: Path, method: str, evaluations: int, seed: int, scene: str,
                  generation_size: int, wcfg: WorldConfig) -> str:
    """Write ``config.json``; return the command line that reruns the run."""
    command = command_line(
        ["a2l", "experiment", "babbling", "--method", method, "--evaluations", evaluations,
         "--seed", seed, "--scene", scene, "--generation-size", generation_size, "--out",
         run_dir], wcfg, skip=("scene", "seed"), prefix="world.")
    write_json(run_dir / "config.json", {
        "experiment": "babbling", "method": method, "evaluations": evaluations, "seed": seed,
        "scene": scene, "generation_size": generation_size, "world": asdict(wcfg),
        "command": command, "seed_use": seed_record("babbling", [seed])})
    return command


def _evaluation_row(index: int, generation: int, g: np.ndarray,
                    e: Evaluation) -> dict[str, Any]:
    """The row of ``evaluations.parquet`` of evaluation `e` of genotype `g`."""
    return {"evaluation": index, "generation": generation,
            "genotype": [float(v) for v in g], "moved": _moved(e),
            "moves": e.moves,
            **{f"d{n}": float(np.hypot(*d)) for n, d in e.displacement.items()},
            **{f"{a}_{n}": float(v) for n, xy in e.final.items()
               for a, v in zip("xy", xy, strict=True)}}


class _Babble:
    """What a babbling run accumulates, batch after batch: the evaluations' rows and paths,
    the outcomes reached, the generations' metrics and the time spent evaluating."""

    def __init__(self, strategy: Strategy, world: WorldConfig, label: str,
                 evaluations: int) -> None:
        self.strategy, self.world, self.label, self.evaluations = (strategy, world, label,
                                                                   evaluations)
        self.records: list[dict[str, Any]] = []
        self.paths: list[np.ndarray] = []
        self.reached: set[tuple[str, str, int, int]] = set()
        self.generations: list[dict[str, Any]] = []
        self.eval_s = 0.0

    def evaluate(self, executor: Executor, asked: Sequence[np.ndarray]) -> list[Evaluation]:
        t = time.perf_counter()
        evs: list[Evaluation] = executor.map(evaluate_task,
                                             [EvaluationTask(self.world, g) for g in asked])
        self.eval_s += time.perf_counter() - t
        return evs

    def tally(self, bars: ProgressBars, asked: Sequence[np.ndarray],
              evs: Sequence[Evaluation]) -> None:
        records, reached, generations = self.records, self.reached, self.generations
        moved = 0
        for g, e in zip(asked, evs, strict=True):
            reached.update(outcome_keys(e))
            moved += _moved(e)
            records.append(_evaluation_row(len(records), len(generations), g, e))
            self.paths.append(e.path)
        strategy = self.strategy
        archive = len(strategy.archive) if isinstance(strategy, NovEB) else None
        generations.append({
            "generation": len(generations), "evaluations": len(records),
            "moved_share": moved / len(evs),
            "moved_share_so_far": float(np.mean([r["moved"] for r in records])),
            "distinct_outcomes": len(reached), "archive_size": archive})
        bars.update(self.label, len(records), self.evaluations,
                    f"moved {generations[-1]['moved_share_so_far']:.0%}, "
                    f"outcomes {len(reached)}")

    def run(self, generation_size: int, workers: int, cluster: str | None,
            quiet: bool) -> None:
        with Executor(workers=workers, cluster=cluster) as executor, \
                ProgressBars(quiet) as bars:
            bars.update(self.label, 0, self.evaluations)
            drive(self.strategy, lambda asked: self.evaluate(executor, asked),
                  generation_size, told=lambda evs: np.array([e.descriptor for e in evs]),
                  on_batch=lambda asked, evs: self.tally(bars, asked, evs))


def _totals(babble: _Babble, df: pd.DataFrame, wall: float) -> dict[str, Any]:
    """The ``totals`` of ``metrics.json``."""
    records, eval_s, strategy = babble.records, babble.eval_s, babble.strategy
    totals = {"evaluations": len(records), "moved": int(df["moved"].sum()),
              "moved_share": float(df["moved"].mean()),
              "distinct_outcomes": len(babble.reached),
              "archive_size": babble.generations[-1]["archive_size"],
              "movements": int(df["moves"].sum()), "wall_s": wall,
              "evaluations_per_s": len(records) / eval_s if eval_s > 0 else float("nan")}
    if isinstance(strategy, NovEB):
        totals["threshold"] = strategy.threshold.value
    return totals


def _record_run(record: str | Path, run_dir: Path) -> None:
    from a2l.rollout.recording import RerunRecorder

    rec = RerunRecorder(record, name="a2l experiment babbling")
    record_babbling(rec, run_dir)
    rec.close()


def _write_report(run_dir: Path, method: str, scene: str, seed: int, n: int,
                  totals: dict[str, Any], wall: float, workers: int, command: str) -> None:
    atomic_write_text(run_dir / "report.md", mark_report("\n".join([
        f"# Babbling: {method} on {scene} (seed {seed}, {n} evaluations)", "",
        f"Evaluations that moved an object: **{totals['moved']}** "
        f"({totals['moved_share']:.1%}); distinct outcomes: "
        f"**{totals['distinct_outcomes']}**"
        + (f"; archive: {totals['archive_size']}" if totals["archive_size"] is not None
           else "") + f". Wall time {wall:.0f} s ({totals['evaluations_per_s']:.2f} "
        f"evaluations/s, {workers} worker(s)).", "",
        "![end-effector positions visited](visits.png)", "",
        "![moved share and distinct outcomes](progress.png)", "",
        f"Rerun: `{command}`.", ""]), seed_record("babbling", [seed])))


def run_babbling(method: str, evaluations: int, seed: int, scene: str = "push",
                 out: str | Path | None = None, workers: int = 1, cluster: str | None = None,
                 generation_size: int = 20, quiet: bool = False, plots: bool = True,
                 world: WorldConfig | None = None,
                 record: str | Path | None = None) -> dict[str, Any]:
    """Run one babbling method and write its run directory.

    Parameters
    ----------
    method : {"noveb", "random", "goal"}
        The strategy.
    evaluations : int
        Budget (trajectories played).
    seed : int
        Seed of the strategy and of the scene.
    scene : {"push", "two_objects"}
        The world.
    out : path, optional
        Run directory (default ``runs/babbling-<method>-<scene>-<timestamp>``).
    workers : int
        Local worker processes for the evaluations.
    cluster : str, optional
        Dask scheduler address; evaluations run there.
    generation_size : int
        Evaluations per generation (asked and told together).
    quiet : bool
        No progress bar.
    plots : bool
        Write the PNG plots.
    world : WorldConfig, optional
        The world's parameters (`scene` and `seed` override its own).
    record : path, optional
        A Rerun recording (``.rrd``) of every evaluation (:func:`record_babbling`).

    Returns
    -------
    dict
        The content of ``metrics.json`` plus ``run_dir``.
    """
    _check_arguments(method, evaluations, generation_size)
    wcfg = replace(world or WorldConfig(), scene=scene, seed=seed)
    run_dir = make_run_dir(f"babbling-{method}-{scene}", out)
    command = _write_config(run_dir, method, evaluations, seed, scene, generation_size, wcfg)
    n_genes = 3 * wcfg.n_waypoints
    strategy = make_strategy(method, n_genes, seed, evaluations, generation_size)
    babble = _Babble(strategy, wcfg, f"{method} on {scene}", evaluations)
    t0 = time.perf_counter()
    babble.run(generation_size, workers, cluster, quiet)
    wall = time.perf_counter() - t0
    records, paths = babble.records, babble.paths
    df = pd.DataFrame(records)
    df.to_parquet(run_dir / "evaluations.parquet", index=False)
    np.savez_compressed(run_dir / "paths.npz", *paths)
    totals = _totals(babble, df, wall)
    metrics = {"experiment": "babbling", "method": method, "scene": scene, "seed": seed,
               "generation_size": generation_size, "generations": babble.generations,
               "totals": totals, "workers": workers, "cluster": cluster}
    write_json(run_dir / "metrics.json", metrics)
    if record is not None:
        _record_run(record, run_dir)
    if plots:
        plot_visits({method: paths}, wcfg, run_dir / "visits.png")
        plot_progress({method: [metrics]}, run_dir / "progress.png")
    _write_report(run_dir, method, scene, seed, len(records), totals, wall, workers, command)
    if not quiet:
        print(f"{method} on {scene}, seed {seed}: moved {totals['moved_share']:.1%} of "
              f"{len(records)} evaluations, {len(babble.reached)} distinct outcomes; "
              f"run directory: {run_dir}")
    return {**metrics, "run_dir": str(run_dir)}


def record_babbling(recorder: Any, run_dir: str | Path, group: str = "") -> int:
    """Log the evaluations of babbling run `run_dir` (its ``paths.npz``,
    ``evaluations.parquet`` and ``config.json``) to `recorder`
    (:class:`a2l.rollout.recording.RerunRecorder`), one rollout each under `group`: the
    end-effector path played, the objects where they stood before (their homes) and after
    (the experimenter's measurement; nothing between: the run keeps only those), and a line
    saying the generation and what moved.

    Returns
    -------
    int
        The number of evaluations logged.
    """
    from a2l.experiments.babbling_world import object_homes
    from a2l.rollout.recording import record_trajectories
    from a2l.rundir import read_json
    from a2l.sim import make_config

    run_dir = Path(run_dir)
    wcfg = WorldConfig(**read_json(run_dir / "config.json")["world"])
    sim = make_config("push", robot=wcfg.robot, object_jitter=0.0,
                      context_source="ground_truth")
    homes = object_homes(wcfg, sim)
    z = sim.table_z + sim.box_size[2] / 2
    df = pd.read_parquet(run_dir / "evaluations.parquet")
    with np.load(run_dir / "paths.npz") as npz:
        paths = [npz[k] for k in npz.files]
    trajectories, others, notes = {}, {}, {}
    for row, path in zip(df.itertuples(index=False), paths, strict=True):
        key = f"evaluation {row.evaluation}"
        objs = {}
        for name, (hx, hy) in homes.items():
            o = np.full((len(path), 3), np.nan)
            o[0] = (hx, hy, z)
            fx, fy = getattr(row, f"x_{name}", np.nan), getattr(row, f"y_{name}", np.nan)
            if len(path) > 1 or np.isfinite(fx):
                o[-1] = (fx, fy, z)  # NaN (not shown) in runs that kept no final position
            objs[name] = o
        first = next(iter(homes))
        trajectories[key] = (path, objs.pop(first))
        others[key] = objs
        moved = ", ".join(f"{n} {getattr(row, f'd{n}'):.3f} m" for n in homes)
        notes[key] = f"{key} (generation {row.generation}): {row.moves} movements; " \
                     f"moved {moved}"
    return record_trajectories(recorder, trajectories, notes, object_name=next(iter(homes)),
                               group=group, others=others)
