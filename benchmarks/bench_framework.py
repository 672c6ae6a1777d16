"""The A2L iterative framework: wall time of the whole push experiment with 1 and 2 local
workers (virtual scene: one run, and a seed sweep for a run of over a minute; the Baxter
scene), measured fairly, and where the time of a run goes.

Worker scaling: per scene, the runs are made in the interleaved order 1, 2, 2, 1 workers,
:data:`REPEATS` times, after one warm-up run of each worker count (not counted); every timed
run is bare (no instrumentation), so the two worker counts are measured alike, and a change
of the machine's load during the section touches both. Every run is reported, and per scene
the median over the blocks of each block's ratio (the two 1-worker walls over the two
2-worker walls). The phase breakdown comes from separate instrumented runs, not timed for the
ratio."""

from __future__ import annotations

import os
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from a2l.experiments.push import run_push_experiment
from a2l.experiments.sweep import run_seed_sweep
from a2l.framework import FrameworkConfig, loop, validation
from a2l.parallel import Executor
from a2l.rollout.env import SceneEnv
from a2l.rundir import read_json

TITLE = "Iterative framework (push experiment: workers, Baxter iteration)"

#: The Baxter run: 4 starts, 2 iterations (the second one extends the dataset), the
#: scene's default budgets (a fresh config: ``directed_try_cap`` is per scene); 8 held-out
#: starts (the default 32 would make held-out rollouts most of this short run).
BAXTER = {"scene": "baxter", "seed": 0, "max_iterations": 2, "discretization": {"n_effects": 4},
          "starts": {"n_starts": 4}, "heldout": {"n_starts": 8}}

#: Seeds of the virtual scaling run (``a2l experiment sweep``, one push experiment each):
#: about a minute with 1 worker on the idle machine. With 2 workers the sweep ends when its
#: last seed does, the other process idle meanwhile: the more seeds, the smaller that share.
SCALING_SEEDS = tuple(range(8))

#: Blocks of the interleaved order per scene (each block: 1, 2, 2, 1 workers); the
#: environment's ``A2L_BENCH_FRAMEWORK_REPEATS`` sets another count (the section says which).
REPEATS = int(os.environ.get("A2L_BENCH_FRAMEWORK_REPEATS", "2"))

#: The order of the worker counts within a block.
ORDER = (1, 2, 2, 1)


class _Instrument:
    """In this process (workers=1 runs): counts the discrete movements and the time spent in
    them, and the movements and time of each framework phase."""

    PHASES = ("acquire", "extend", "generate_skill", "validate", "validate_heldout")
    TASKS = ("babble_task", "directed_outcome_task", "validate_task", "heldout_task")
    #: The module whose global each phase and task is looked up in when the loop runs.
    HOME = {"acquire": loop, "extend": loop, "generate_skill": loop, "validate": loop,
            "validate_heldout": loop, "babble_task": loop, "directed_outcome_task": loop,
            "validate_task": validation, "heldout_task": validation}

    def __init__(self) -> None:
        self.moves = 0
        self.move_s = 0.0
        self.phase_moves = dict.fromkeys(self.PHASES, 0)
        self.phase_s = dict.fromkeys(self.PHASES, 0.0)
        self.tasks = 0
        self.maps = 0
        self._orig: dict[str, Any] = {}

    def __enter__(self) -> _Instrument:
        orig_execute = SceneEnv.execute
        self._orig["execute"] = orig_execute

        def execute(env: SceneEnv, direction: tuple[int, int, int]) -> bool:
            t = time.perf_counter()
            try:
                return orig_execute(env, direction)
            finally:
                self.moves += 1
                self.move_s += time.perf_counter() - t

        SceneEnv.execute = execute  # type: ignore[method-assign]
        orig_submit = Executor.submit
        self._orig["submit"] = orig_submit

        def submit(ex: Executor, *args: Any, **kwargs: Any) -> Any:
            self.maps += 1
            return orig_submit(ex, *args, **kwargs)

        Executor.submit = submit  # type: ignore[method-assign]
        for name in self.PHASES:
            self._orig[name] = getattr(self.HOME[name], name)
            setattr(self.HOME[name], name, self._timed(name, self._orig[name]))
        for name in self.TASKS:
            self._orig[name] = getattr(self.HOME[name], name)
            setattr(self.HOME[name], name, self._counted(self._orig[name]))
        return self

    def _counted(self, fn: Callable[..., Any]) -> Callable[..., Any]:
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            self.tasks += 1
            return fn(*args, **kwargs)

        return wrapper

    def _timed(self, name: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            t, m = time.perf_counter(), self.moves
            try:
                return fn(*args, **kwargs)
            finally:
                self.phase_s[name] += time.perf_counter() - t
                self.phase_moves[name] += self.moves - m

        return wrapper

    def __exit__(self, *exc: object) -> None:
        SceneEnv.execute = self._orig["execute"]  # type: ignore[method-assign]
        Executor.submit = self._orig["submit"]  # type: ignore[method-assign]
        for name in (*self.PHASES, *self.TASKS):
            setattr(self.HOME[name], name, self._orig[name])


def _run(cfg: FrameworkConfig, workers: int, root: Path, name: str) -> tuple[dict[str, Any],
                                                                               float]:
    t = time.perf_counter()
    m = run_push_experiment(cfg, root / name, workers=workers, quiet=True)
    return m, time.perf_counter() - t


def _training(m: dict[str, Any]) -> list[dict[str, Any]]:
    """The iterations' metrics but wall times (the held-out ones included)."""
    return [{k: v for k, v in it.items() if k not in ("wall_s", "heldout_wall_s")}
            for it in m["iterations"]]


def _seeds_run(workers: int, root: Path, tag: str) -> tuple[list[dict[str, Any]], float]:
    """``a2l experiment sweep --seeds`` :data:`SCALING_SEEDS` ``--workers`` `workers` on the
    virtual scene, 4 effects (:func:`run_seed_sweep`; 2 workers: 2 seeds at once, each in
    a worker process of its own): (each seed's ``metrics.json``, total wall time, the
    worker processes' start included)."""
    t = time.perf_counter()
    sweep = run_seed_sweep(
        FrameworkConfig(scene="virtual", discretization={"n_effects": 4}),
        SCALING_SEEDS,
        out=root / f"sweep-{tag}",
        workers=workers,
        quiet=True,
    )
    wall = time.perf_counter() - t
    return [read_json(Path(sweep["run_dir"]) / f"seed_{s:03d}" / "metrics.json")
            for s in SCALING_SEEDS], wall


def _interleaved(make: Callable[[int, str], tuple[Any, float]], label: str
                 ) -> dict[str, Any]:
    """Run `make(workers, tag)` (a run's result and its wall time) in :data:`REPEATS` blocks
    of :data:`ORDER`; every run's wall and the machine's 1-minute load average as it
    started, the median block ratio (1-worker walls over 2-worker walls) and whether every
    run's result equals the first one's."""
    runs: list[dict[str, Any]] = []
    results = []
    for block in range(REPEATS):
        for k, workers in enumerate(ORDER):
            load = os.getloadavg()[0]
            result, wall = make(workers, f"{label}-b{block}-{k}w{workers}")
            results.append(result)
            runs.append({"block": block, "workers": workers, "wall": wall, "load": load})
    ratios = []
    for block in range(REPEATS):
        w = [r for r in runs if r["block"] == block]
        ratios.append(sum(r["wall"] for r in w if r["workers"] == 1)
                      / sum(r["wall"] for r in w if r["workers"] == 2))
    return {"runs": runs, "ratios": ratios, "median": statistics.median(ratios),
            "same": all(r == results[0] for r in results)}


def _runs_table(name: str, m: dict[str, Any]) -> list[str]:
    """Rows of the every-run table of one scene."""
    return [f"| {name} | {r['block'] + 1} | {r['workers']} | {r['wall']:.1f} | "
            f"{r['load']:.1f} |" for r in m["runs"]]


def _iterations(m: dict[str, Any]) -> str:
    return ", ".join(f"{it['wall_s']:.1f}" for it in m["iterations"])


def _restore_drift(repeats: int = 4, seed: int = 0) -> float:
    """Largest distance (m) between the box positions after the same movements from the same
    restored start, when other random episodes ran in between (Baxter push scene, public
    ``a2l.sim`` API, the framework's reset: object at home, no jitter)."""
    import numpy as np

    from a2l.sim import make_scene

    rng = np.random.default_rng(seed)
    ends = []
    with make_scene("push", seed=seed, object_jitter=0.0) as scene:
        home = np.asarray(scene.ground_truth()["objects"]["box"], dtype=float)
        for _ in range(repeats):
            scene.reset(eef=home + [-0.15, 0.0, 0.0], objects={"box": home[:2].copy()})
            for _ in range(4):  # the box in front: +x pushes it
                scene.execute((1, 0, 0))
            ends.append(np.asarray(scene.ground_truth()["objects"]["box"], dtype=float))
            # another episode in between: random movements from a random start on the circle
            a = rng.uniform(0, 2 * np.pi)
            scene.reset(eef=home + [0.2 * np.cos(a), 0.2 * np.sin(a), 0.0],
                        objects={"box": home[:2].copy()})
            planar = [(dx, dy, 0) for dx in (-1, 0, 1) for dy in (-1, 0, 1) if dx or dy]
            for k in rng.integers(0, len(planar), 6):
                scene.execute(planar[int(k)])
    e = np.asarray(ends)
    return float(np.linalg.norm(e[:, None, :] - e[None, :, :], axis=-1).max())


def _phases(ins: _Instrument) -> list[str]:
    return [f"| `{name}` | {ins.phase_s[name]:.1f} | {ins.phase_moves[name]:,} |"
            for name in _Instrument.PHASES]


def run() -> str:
    cfg = FrameworkConfig(scene="virtual", seed=0, discretization={"n_effects": 4})
    bcfg = FrameworkConfig(**BAXTER)
    with tempfile.TemporaryDirectory(prefix="a2l-bench-fw-") as tmp:
        root = Path(tmp)
        warm = [_run(cfg, w, root, f"warm-w{w}")[1] for w in (1, 2)]

        def one(c: FrameworkConfig) -> Callable[[int, str], tuple[Any, float]]:
            def make(workers: int, tag: str) -> tuple[Any, float]:
                m, wall = _run(c, workers, root, tag)
                return _training(m), wall
            return make

        def sweep(workers: int, tag: str) -> tuple[Any, float]:
            ms, wall = _seeds_run(workers, root, tag)
            return [_training(m) for m in ms], wall

        scenes = {"virtual, 4 effects, seed 0": _interleaved(one(cfg), "v"),
                  f"virtual sweep, seeds {SCALING_SEEDS[0]}-{SCALING_SEEDS[-1]}":
                  _interleaved(sweep, "s"),
                  f"Baxter, 4 effects, {bcfg.starts.n_starts} starts, seed 0":
                  _interleaved(one(bcfg), "b")}
        # the phase breakdown: instrumented runs of their own, not in the ratios
        with _Instrument() as ins:
            m1, wall1 = _run(cfg, 1, root, "ins-v")
        with _Instrument() as bins:
            mb, wallb = _run(bcfg, 1, root, "ins-b")
        m2, _ = _run(cfg, 2, root, "ins-v2")
    drift = _restore_drift()
    ms_per_move = 1000 * bins.move_s / max(bins.moves, 1)
    per_move_us = 1e6 * ins.move_s / max(ins.moves, 1)
    rollout_s = sum(ins.phase_s[p]
                    for p in ("acquire", "extend", "validate", "validate_heldout"))
    overhead_ms = 1000 * (rollout_s - ins.move_s) / max(ins.tasks, 1)
    est_h = ins.phase_moves["extend"] * ms_per_move / 1000 / 3600
    summary = [f"| {name} | {len(m['runs'])} | "
               f"{', '.join(f'{r:.2f}' for r in m['ratios'])} | **{m['median']:.2f}** | "
               f"{m['same']} |" for name, m in scenes.items()]
    lines = [
        "Whole push experiment (`run_push_experiment`: every iteration, bundles, plots, "
        "report), default `FrameworkConfig` (8 starts, at most 10 iterations) in the virtual "
        f"scene; on Baxter {bcfg.starts.n_starts} starts, {bcfg.max_iterations} iterations, "
        f"{bcfg.heldout.n_starts} held-out starts; and `a2l experiment sweep --seeds "
        f"{SCALING_SEEDS[0]}-{SCALING_SEEDS[-1]} --workers N` (`run_seed_sweep`: the same "
        "experiment per seed, without plots; with 2 workers two seeds run at once, each in a "
        "worker process of its own with its rollouts in that process, so one seed's serial "
        "skill learning overlaps the other's rollouts; the sweep ends with its last seed). "
        "Local worker processes started with `spawn`, their start inside the timed run.",
        "",
        f"Measured fairly: per scene, {REPEATS} block{'s' if REPEATS != 1 else ''} of the "
        "interleaved order "
        f"{', '.join(map(str, ORDER))} workers, after one warm-up run with 1 and one with 2 "
        f"workers (virtual, not counted: {warm[0]:.1f} s and {warm[1]:.1f} s); every timed "
        "run bare (the same code path, no instrumentation). A block's ratio is its two "
        "1-worker walls over its two 2-worker walls (above 1: 2 workers are faster); the "
        "load is the machine's 1-minute load average as the run started (2 cores: above 2, "
        "other jobs shared them, and a ratio measured then tells less).",
        "",
        "| scene | runs | ratio per block | median ratio | same metrics, every run |",
        "|---|---|---|---|---|",
        *summary,
        "",
        "Every run:",
        "",
        "| scene | block | workers | wall (s) | load |",
        "|---|---|---|---|---|",
        *(row for name, m in scenes.items() for row in _runs_table(name, m)),
        "",
        "Where a 1-worker run spends its time (an instrumented run of its own: the "
        "framework's phases, all iterations; `extend` holds the effect-directed babbling):",
        "",
        "| phase | time (s) | discrete movements |",
        "|---|---|---|",
        *_phases(ins),
        "",
        f"{ins.moves:,} movements took {ins.move_s:.1f} s ({per_move_us:.0f} µs each) of "
        f"the 1-worker run's {wall1:.1f} s (its `metrics.json` counts "
        f"{m1['iterations'][-1]['robot_movements_total']:,}: `robot_movements_total`, "
        f"{m2['iterations'][-1]['robot_movements_total']:,} with 2 workers). The rollout "
        f"phases ran {ins.tasks:,} rollouts "
        f"(tasks) in {ins.maps} submissions (`Executor.submit`; a round of effect-directed "
        "babbling for all stuck pairs is one), "
        f"each rollout costing {overhead_ms:.3f} ms beyond its movements (Python: the "
        "scene wrapper's positions, arrays, the result object); skill learning and the "
        "run's bookkeeping are serial. With workers, rollouts travel in batches "
        f"({Executor.BATCHES_PER_SLOT} per worker and submission, one round trip each), and "
        f"the babbling rounds are submitted {loop.AHEAD} ahead (`drive_ahead`: the workers "
        "run the next round while the main process collects one; what a strategy was asked "
        "past its end is dropped, so the results are those of one round at a time); the "
        "main process stays busy too (learning, collecting results), so two workers on two "
        "cores cannot give twice the speed on the virtual scene's small tasks.",
        "",
        f"**Baxter scene** (PyBullet, C++ IK), 4 effects, {bcfg.starts.n_starts} starts, seed 0, "
        f"1 worker, {len(mb['iterations'])} iterations, the scene's default budgets "
        f"(`directed.try_cap` {bcfg.directed.try_cap}), {bcfg.heldout.n_starts} held-out "
        "starts (their rollouts are the `validate_heldout` phase, not in the iteration's "
        "wall):",
        "",
        "| iteration | wall (s) | score | held-out score | held-out wall (s) | dataset rows |",
        "|---|---|---|---|---|---|",
        *(f"| {it['iteration']} | {it['wall_s']:.1f} | {it['score']:.1f} | "
          f"{it['heldout_score']:.1f} | {it['heldout_wall_s']:.1f} | "
          f"{it['dataset_size']:,} |" for it in mb["iterations"]),
        "",
        "| phase | time (s) | discrete movements |",
        "|---|---|---|",
        *_phases(bins),
        "",
        f"{bins.moves:,} movements at {ms_per_move:.0f} ms each; the whole instrumented "
        f"run took {wallb:.1f} s with the scene's start-up, bundles and plots (its scaling: "
        "the table above). PyBullet's restored start state after "
        "different earlier episodes, measured here: after the same 4 movements from the same "
        f"restored start, with random episodes in between, the box ends up to "
        f"{drift * 1000:.2f} mm elsewhere"
        + (". The worker runs can differ through it, since which worker runs which rollout "
           "depends on timing." if drift > 0 else
           ": restoring is exact, so the worker count cannot change a rollout through it.")
        + " For comparison, the "
        "virtual scene's budget (`directed_try_cap` 2,000) made its extensions execute "
        f"{ins.phase_moves['extend']:,} movements: at the Baxter scene's rate, about "
        f"{est_h:.1f} hours. The whole Baxter run with the demo's budget (8 starts, 32 "
        "held-out starts), end to end, before and after the changes that cut its time: the "
        "next section (`benchmarks/bench_framework_baxter.py`).",
    ]
    return "\n".join(lines)
