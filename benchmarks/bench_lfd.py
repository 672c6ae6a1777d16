"""Learning from demonstration: fit time of the diffeomorphic DS on the 30 LASA shapes, the
C++ velocity query (median, p99.9) and the same queries through the numpy reference."""

from __future__ import annotations

import time

import numpy as np

from a2l import _core
from a2l.experiments.lasa import LasaConfig, lasa_shapes, load_lasa_shape
from a2l.lfd import DiffeoDS
from a2l.lfd.fit import fit_diffeo, mean_demonstration, speed_gain
from a2l.lfd.reference import ref_velocity

TITLE = "Learning from demonstration (diffeomorphic DS: fit, C++ query, numpy reference)"
CFG = LasaConfig()          # the LASA experiment's parameters (K = 150)
REPEATS = 3                 # fits per shape; the shape's time is the median of these
QUERIES = 10_000            # random query points per DS
ROUNDS = 3                  # interleaved timing rounds: with the cutoff, then without


def _fit_times() -> tuple[list[float], list[float], dict[str, DiffeoDS]]:
    times, cpu, fitted = [], [], {}
    for name in lasa_shapes():
        demos, durations = load_lasa_shape(name)
        ref = mean_demonstration(demos)
        runs, runs_cpu = [], []
        for _ in range(REPEATS):
            t0, c0 = time.perf_counter(), time.thread_time()
            res = fit_diffeo(ref, **CFG.fit_parameters())
            runs.append((time.perf_counter() - t0) * 1e3)
            runs_cpu.append((time.thread_time() - c0) * 1e3)
        times.append(float(np.median(runs)))
        cpu.append(float(np.median(runs_cpu)))
        fitted[name] = DiffeoDS.from_maps(res.target, res.centers, res.vectors, res.rhos,
                                          speed_gain(float(np.mean(durations)),
                                                     CFG.arrival))
    return times, cpu, fitted


def _queries(ds: DiffeoDS, rng: np.random.Generator, span: float) -> np.ndarray:
    return ds.target + rng.uniform(-span, span, size=(QUERIES, ds.dim))


def _numpy_per_query_us(ds: DiffeoDS, pts: np.ndarray) -> tuple[float, float]:
    """numpy reference: (vectorised over all points, per point; one point per call)."""
    args = (ds.target, ds.centers, ds.vectors, ds.rhos, ds.speed)
    t0 = time.perf_counter()
    ref_velocity(pts, *args)
    batch = (time.perf_counter() - t0) / len(pts) * 1e6
    one = []
    for p in pts[:200]:
        t0 = time.perf_counter()
        ref_velocity(p, *args)
        one.append(time.perf_counter() - t0)
    return batch, float(np.median(one)) * 1e6


def _time_cutoff(ds: DiffeoDS, pts: np.ndarray) -> tuple[dict[str, float], dict[str, float]]:
    """C++ velocity query times with the negligible-map cutoff (the default, t = 40) and with
    only underflowing maps skipped (t = 746), in :data:`ROUNDS` interleaved rounds (one pass
    each): per variant the median over rounds of the median and of the p99.9 (µs)."""
    under = _core.DiffeoDS(ds.target, ds.centers, ds.vectors, ds.rhos, ds.speed,
                           negligible=_core.DIFFEO_UNDERFLOW)
    runs: dict[str, list[dict[str, float]]] = {"cut": [], "under": []}
    for _ in range(ROUNDS):
        runs["cut"].append(ds.core.time_velocity(pts, 1))
        runs["under"].append(under.time_velocity(pts, 1))
    return tuple({k: float(np.median([r[k] for r in runs[v]])) / 1e3  # type: ignore[return-value]
                  for k in ("median_ns", "p999_ns")} for v in ("cut", "under"))


def _helix_ds() -> DiffeoDS:
    s = np.linspace(0.0, 1.0, 1000)
    x = np.column_stack([30 * np.cos(6 * s) * (1 - s), 30 * np.sin(6 * s) * (1 - s), 20 * s])
    p = CFG.fit_parameters()
    return DiffeoDS.fit(x[::-1] - x[0], K=p["K"], beta=p["beta"], mu=p["mu"],
                        duration=3.0, regularisation=p["regularisation"])


def run() -> str:
    fit_ms, fit_cpu_ms, fitted = _fit_times()
    rng = np.random.default_rng(0)
    rows = []
    subjects = [(f"LASA {n} (d = 2)", fitted[n]) for n in ("Angle", "GShape", "Sshape")]
    subjects.append(("helix (d = 3)", _helix_ds()))
    for label, ds in subjects:
        pts = _queries(ds, rng, 60.0)
        cut, under = _time_cutoff(ds, pts)
        batch, one = _numpy_per_query_us(ds, pts)
        med = cut["median_ns"]
        rows.append(f"| {label} | {ds.n_maps} | {med:.2f} | {cut['p999_ns']:.2f} | "
                    f"{under['median_ns']:.2f} | {under['p999_ns']:.2f} | "
                    f"{batch:.1f} | {one:.0f} | {batch / med:.0f}x | {one / med:.0f}x |")
    f, fc = np.asarray(fit_ms), np.asarray(fit_cpu_ms)
    return "\n".join([
        f"Fit (numpy, fast diffeomorphic matching, K = {CFG.K}, the LASA experiment's "
        f"beta and mu schedules) of the time-aligned mean of each of the {len(f)} LASA shapes "
        f"(1,000 points); per shape the median of {REPEATS} fits; wall time, and the CPU "
        "time of the fitting thread (the same fits; on a shared machine the wall time "
        "includes waiting for a core):",
        "",
        "| time | shapes | median (ms) | p90 (ms) | max (ms) | min (ms) |",
        "|---|---|---|---|---|---|",
        *(f"| {label} | {len(a)} | {np.median(a):.1f} | {np.percentile(a, 90):.1f} | "
          f"{a.max():.1f} | {a.min():.1f} |" for label, a in (("wall", f), ("CPU", fc))),
        "",
        f"Velocity query, {QUERIES:,} random points within ±60 of the target (C++: "
        "`_core.DiffeoDS.time_velocity`, std::chrono around each call; numpy: the "
        "vectorised reference `a2l.lfd.reference.ref_velocity` on all points at once, and "
        "called with one point). C++ with the negligible-map cutoff (the default: a map is "
        "skipped where its weight is below exp(-40), `kDiffeoNegligible`) and without it "
        "(only underflowing weights skipped, `negligible=DIFFEO_UNDERFLOW`), timed in "
        f"{ROUNDS} interleaved rounds of one pass each; each figure is the median over the "
        "rounds. Ratios are against the C++ median with the cutoff:",
        "",
        "| DS | maps | C++ median (µs) | C++ p99.9 (µs) | no cutoff: median (µs) | "
        "no cutoff: p99.9 (µs) | numpy vectorised (µs/point) | "
        "numpy one point (µs) | ratio vectorised | ratio one point |",
        "|---|---|---|---|---|---|---|---|---|---|",
        *rows,
    ])
