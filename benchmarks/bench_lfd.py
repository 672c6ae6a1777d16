"""Learning from demonstration: fit time of the diffeomorphic DS on the 30 LASA shapes, the
C++ velocity query (median, p99.9, and what the tail is made of) and the same queries through
the numpy reference; both directions of the maps (``to_demo``: the paper's, a query solves K
scalar equations; ``to_line``: the maps fitted from the demonstration onto the line by the
pullback fit, a query is one forward sweep and a d x d solve), and the fit time of ``auto``
(the LASA default: both fitted, the smaller mean fit error kept). Queries are timed at points
where the maps act (uniform in each demonstration's bounding box) and, as before, in a box of
±60 around the target."""

from __future__ import annotations

import time
from itertools import product

import numpy as np

from a2l import _core
from a2l.experiments.lasa import LasaConfig, lasa_shapes, load_lasa_shape
from a2l.lfd import DiffeoDS
from a2l.lfd.fit import DIRECTIONS, fit_diffeo, mean_demonstration, speed_gain
from a2l.lfd.reference import ref_velocity

TITLE = "Learning from demonstration (diffeomorphic DS: fit, C++ query, numpy reference)"
CFG = LasaConfig()          # the LASA experiment's parameters (K = 150)
REPEATS = 3                 # fits per shape; the shape's time is the median of these
QUERIES = 10_000            # random query points per DS
ROUNDS = 3                  # interleaved timing rounds: with the cutoff, then without
PER_POINT = 5               # timings per point for the per-point (algorithmic) tail


def _fit_times(direction: str) -> tuple[list[float], list[float], dict[str, DiffeoDS]]:
    times, cpu, fitted = [], [], {}
    params = {**CFG.fit_parameters(), "direction": direction}
    for name in lasa_shapes():
        demos, durations = load_lasa_shape(name)
        ref = mean_demonstration(demos)
        runs, runs_cpu = [], []
        for _ in range(REPEATS):
            t0, c0 = time.perf_counter(), time.thread_time()
            res = fit_diffeo(ref, **params)
            runs.append((time.perf_counter() - t0) * 1e3)
            runs_cpu.append((time.thread_time() - c0) * 1e3)
        times.append(float(np.median(runs)))
        cpu.append(float(np.median(runs_cpu)))
        fitted[name] = DiffeoDS.from_maps(res.target, res.centers, res.vectors, res.rhos,
                                          speed_gain(float(np.mean(durations)),
                                                     CFG.arrival), direction=res.direction)
    return times, cpu, fitted


def _queries(ds: DiffeoDS, rng: np.random.Generator, span: float) -> np.ndarray:
    return ds.target + rng.uniform(-span, span, size=(QUERIES, ds.dim))


def _box_queries(demos: list[np.ndarray], rng: np.random.Generator) -> np.ndarray:
    """:data:`QUERIES` points, an equal share uniform in each demonstration's bounding box."""
    per = QUERIES // len(demos)
    return np.vstack([rng.uniform(d.min(axis=0), d.max(axis=0), size=(per, d.shape[1]))
                      for d in demos])


def _numpy_per_query_us(ds: DiffeoDS, pts: np.ndarray) -> tuple[float, float]:
    """numpy reference: (vectorised over all points, per point; one point per call)."""
    args = (ds.target, ds.centers, ds.vectors, ds.rhos, ds.speed, ds.direction)
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
                           negligible=_core.DIFFEO_UNDERFLOW, direction=ds.direction)
    runs: dict[str, list[dict[str, float]]] = {"cut": [], "under": []}
    for _ in range(ROUNDS):
        runs["cut"].append(ds.core.time_velocity(pts, 1))
        runs["under"].append(under.time_velocity(pts, 1))
    return tuple({k: float(np.median([r[k] for r in runs[v]])) / 1e3  # type: ignore[return-value]
                  for k in ("median_ns", "p999_ns")} for v in ("cut", "under"))


def _tail(ds: DiffeoDS, pts: np.ndarray) -> tuple[float, float, float]:
    """What the tail is made of (µs): the p99.9 over the points of each point's own median of
    :data:`PER_POINT` timings (a preemption hits one of them, not the median: the tail the
    work itself has), and the median and p99.9 of one point queried :data:`QUERIES` times
    (the same work every call: its spread is the machine's, not the algorithm's)."""
    own = [ds.core.time_velocity(pts[i:i + 1], PER_POINT)["median_ns"] for i in range(len(pts))]
    same = ds.core.time_velocity(np.repeat(pts[:1], len(pts), axis=0), 1)
    return (float(np.percentile(own, 99.9)) / 1e3, same["median_ns"] / 1e3,
            same["p999_ns"] / 1e3)


def _helix() -> np.ndarray:
    s = np.linspace(0.0, 1.0, 1000)
    x = np.column_stack([30 * np.cos(6 * s) * (1 - s), 30 * np.sin(6 * s) * (1 - s), 20 * s])
    return x[::-1] - x[0]


def _helix_ds(direction: str) -> DiffeoDS:
    p = CFG.fit_parameters()
    return DiffeoDS.fit(_helix(), K=p["K"], beta=p["beta"], mu=p["mu"],
                        duration=3.0, regularisation=p["regularisation"], direction=direction)


def run() -> str:
    fits = {d: _fit_times(d) for d in (*DIRECTIONS, "auto")}
    auto_demo = sorted(n for n, ds in fits["auto"][2].items() if ds.direction == "to_demo")
    rng = np.random.default_rng(0)
    rows = []
    for label, name in [(f"LASA {n} (d = 2)", n) for n in ("Angle", "GShape", "Sshape")] + [
            ("helix (d = 3)", None)]:
        demos = load_lasa_shape(name)[0] if name else [_helix()]
        dss = {d: fits[d][2][name] if name else _helix_ds(d) for d in DIRECTIONS}
        # the same points for both directions
        where = {"demo boxes": _box_queries(demos, rng),
                 "±60 of target": _queries(dss[DIRECTIONS[0]], rng, 60.0)}
        for (direction, ds), (place, pts) in product(dss.items(), where.items()):
            cut, under = _time_cutoff(ds, pts)
            own, same_med, same_p999 = _tail(ds, pts)
            batch, one = _numpy_per_query_us(ds, pts)
            med = cut["median_ns"]
            rows.append(f"| {label} | {direction} | {place} | {ds.n_maps} | {med:.2f} | "
                        f"{cut['p999_ns']:.2f} | {own:.2f} | {same_med:.2f} / {same_p999:.2f} | "
                        f"{under['median_ns']:.2f} | {under['p999_ns']:.2f} | "
                        f"{batch:.1f} | {one:.0f} | {batch / med:.0f}x | {one / med:.0f}x |")
    fit_rows = []
    for direction in (*DIRECTIONS, "auto"):
        f, fc = np.asarray(fits[direction][0]), np.asarray(fits[direction][1])
        fit_rows += [f"| {direction} | {label} | {len(a)} | {np.median(a):.1f} | "
                     f"{np.percentile(a, 90):.1f} | {a.max():.1f} | {a.min():.1f} |"
                     for label, a in (("wall", f), ("CPU", fc))]
    n_shapes = len(fits[DIRECTIONS[0]][0])
    return "\n".join([
        f"Fit (numpy, fast diffeomorphic matching, K = {CFG.K}, the LASA experiment's "
        f"beta and mu schedules) of the time-aligned mean of each of the {n_shapes} LASA "
        f"shapes (1,000 points), in both directions and with `auto` (the LASA default; it "
        f"fits both and keeps the smaller mean fit error: `to_line` on "
        f"{n_shapes - len(auto_demo)} shapes, `to_demo` on {', '.join(auto_demo) or 'none'}); "
        "per shape the median of "
        f"{REPEATS} fits; "
        "wall time, and the CPU time of the fitting thread (the same fits; on a shared "
        "machine the wall time includes waiting for a core):",
        "",
        "| direction | time | shapes | median (ms) | p90 (ms) | max (ms) | min (ms) |",
        "|---|---|---|---|---|---|---|",
        *fit_rows,
        "",
        f"Velocity query at {QUERIES:,} random points **where the maps act** (`demo boxes`: "
        "an equal share uniform in each demonstration's bounding box; the helix: its curve's "
        "box) and, for comparison, within ±60 of the target; the same points for both "
        "directions (C++: `_core.DiffeoDS.time_velocity`, std::chrono around each "
        "call; numpy: the vectorised reference `a2l.lfd.reference.ref_velocity` on all points "
        "at once, and called with one point). `to_demo`: the maps carry the line onto the "
        "demonstration, a query undoes them (K scalar solves, Halley in a bracket); "
        "`to_line`: the maps are fitted from the demonstration onto the line (pullback fit), "
        "a query applies "
        "them (K exps, no iteration) and solves one d x d system. C++ with the "
        "negligible-map cutoff (the default: a map is skipped where its weight is below "
        "exp(-40), `kDiffeoNegligible`) and without it (only underflowing weights skipped, "
        f"`negligible=DIFFEO_UNDERFLOW`), timed in {ROUNDS} interleaved rounds of one pass "
        "each; each figure is the median over the rounds. **Per-point p99.9**: the p99.9 "
        f"over the points of each point's median of {PER_POINT} timings (a preemption hits "
        "one timing, not the median: the tail of the work itself). **One point repeated**: "
        f"median / p99.9 of one point queried {QUERIES:,} times (the same work each call: "
        "its spread is the machine's). Ratios are against the C++ median with the cutoff:",
        "",
        "| DS | direction | points | maps | C++ median (µs) | C++ p99.9 (µs) | "
        "per-point p99.9 (µs) | "
        "one point repeated: median / p99.9 (µs) | no cutoff: median (µs) | "
        "no cutoff: p99.9 (µs) | numpy vectorised (µs/point) | "
        "numpy one point (µs) | ratio vectorised | ratio one point |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
        *rows,
    ])
