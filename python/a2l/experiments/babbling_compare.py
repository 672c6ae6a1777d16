"""The babbling comparison: every exploration method over several seeds, side by side
(:func:`run_babbling_compare`), with means, spreads and the plots of each method."""

from __future__ import annotations

import shlex
from pathlib import Path
from typing import Any

import numpy as np

from a2l.atomic import atomic_write_text
from a2l.experiments.babbling import record_babbling, run_babbling
from a2l.experiments.babbling_plots import plot_progress, plot_visits, summary_table
from a2l.experiments.babbling_world import WorldConfig
from a2l.progress import print_tables
from a2l.robot import DEFAULT_ROBOT
from a2l.rundir import make_run_dir, read_json, write_json
from a2l.seeds import mark_report, seed_record

__all__ = ["run_babbling_compare"]


def run_babbling_compare(scene: str, evaluations: int, seeds: list[int],
                         out: str | Path | None = None, methods: tuple[str, ...] = (
                             "noveb", "random", "goal"), workers: int = 1,
                         cluster: str | None = None, generation_size: int = 20,
                         quiet: bool = False, record: str | Path | None = None,
                         robot: str = DEFAULT_ROBOT) -> dict[str, Any]:
    """Every method with every seed (``<out>/<method>-s<seed>``; a finished run is reused),
    then the side-by-side plots and the table of means and spreads; with `record`, every
    run's evaluations in one Rerun recording (``.rrd``), group ``<method>-s<seed>``
    (:func:`a2l.experiments.babbling.record_babbling`). `robot`: the world's robot
    (:class:`~a2l.experiments.babbling_world.WorldConfig`), a built-in name or a robot file.

    Returns
    -------
    dict
        ``{"runs": {method: [totals per seed]}, "table": str}`` (also ``metrics.json``).
    """
    root = make_run_dir(f"babbling-compare-{scene}", out)
    write_json(root / "config.json", {
        "experiment": "babbling-compare", "scene": scene, "robot": robot,
        "evaluations": evaluations, "seeds": list(seeds), "methods": list(methods),
        "generation_size": generation_size,
        "command": shlex.join(
            ["a2l", "experiment", "babbling-compare", "--scene", scene, "--robot", robot,
             "--evaluations",
             str(evaluations), "--seeds", str(len(seeds)), "--first-seed", str(seeds[0]),
             "--methods", *methods, "--generation-size", str(generation_size), "--out",
             str(root)]) if list(seeds) == list(range(seeds[0], seeds[0] + len(seeds)))
        else None,
        "seed_use": seed_record("babbling-compare", seeds)})
    runs: dict[str, list[dict[str, Any]]] = {}
    paths: dict[str, list[np.ndarray]] = {}
    world = None
    for method in methods:
        for seed in seeds:
            sub = root / f"{method}-s{seed}"
            if (sub / "metrics.json").is_file():
                m = read_json(sub / "metrics.json")
            else:
                m = run_babbling(method, evaluations, seed, scene, sub, workers=workers,
                                 cluster=cluster, generation_size=generation_size,
                                 quiet=quiet, world=WorldConfig(robot=robot))
            runs.setdefault(method, []).append(m)
            if seed == seeds[0]:
                cfg = read_json(sub / "config.json")
                world = WorldConfig(**cfg["world"])
                with np.load(sub / "paths.npz") as z:
                    paths[method] = [z[k] for k in z.files]
    assert world is not None
    if record is not None:
        from a2l.rollout.recording import RerunRecorder

        rec = RerunRecorder(record, name="a2l experiment babbling-compare")
        for method in methods:
            for seed in seeds:
                record_babbling(rec, root / f"{method}-s{seed}", group=f"{method}-s{seed}")
        rec.close()
    plot_visits(paths, world, root / "visits.png")
    plot_progress(runs, root / "progress.png")
    table = summary_table(runs)
    write_json(root / "metrics.json", {
        "scene": scene, "robot": robot, "evaluations": evaluations, "seeds": list(seeds),
        "runs": {k: [m["totals"] for m in v] for k, v in runs.items()}})
    atomic_write_text(root / "report.md", mark_report("\n".join([
        f"# Babbling methods compared on {scene}, robot {robot} ({evaluations} evaluations, "
        f"seeds {', '.join(map(str, seeds))})", "",
        "Mean ± standard deviation over seeds (min–max).", "", table, "",
        f"![end-effector positions visited, seed {seeds[0]}](visits.png)", "",
        "![moved share and distinct outcomes](progress.png)", ""]),
        seed_record("babbling-compare", seeds)))
    if not quiet:
        print_tables(table)
        print(f"run directory: {root}")
    return {"runs": {k: [m["totals"] for m in v] for k, v in runs.items()}, "table": table,
            "run_dir": str(root)}
