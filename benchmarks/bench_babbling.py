"""The babbling experiment (NovEB and its baselines on Baxter's push scene): evaluations per
second with 1 and 2 local workers, and where an evaluation's time goes (physics and IK of the
movements, camera rendering, the descriptor) beside NovEB's own computation (novelty against
an archive)."""

from __future__ import annotations

import os
import tempfile
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from a2l.acquisition.noveb import NovEB, NovEBConfig, novelty
from a2l.acquisition.protocol import drive
from a2l.acquisition.trajectory import RETURN_REST_S
from a2l.experiments.babbling import run_babbling
from a2l.experiments.babbling_world import EvaluationTask, WorldConfig, _world, evaluate_task

TITLE = "Babbling (NovEB, random and goal babbling on Baxter's push scene)"

#: Evaluations of each timed run (three generations of 20).
N = 60


def _reference_evaluation(scene: Any, cfg: WorldConfig, genotype: np.ndarray) -> None:
    """The evaluation as it was before it was made cheaper: the same waypoints
    at 240 Hz, then every movement retraced physically back to the start before the image
    (the images and descriptor are left out: only the physics differs)."""
    from a2l.acquisition.trajectory import follow_waypoints
    from a2l.skills.repertoire import default_directions

    up = np.array([0.0, 0.0, scene.config.table_z])
    start = np.asarray(cfg.start) + up
    dirs = default_directions()
    scene.reset(eef=start)
    out, clean = follow_waypoints(lambda d: bool(scene.execute(d)), scene.eef_position, dirs,
                                  scene.step_length, start,
                                  cfg.encoding(scene.config.table_z).decode(genotype),
                                  cfg.max_moves)
    if clean:
        for m in reversed(out):
            scene.execute(tuple(int(-s) for s in dirs[m]))
    else:
        follow_waypoints(lambda d: bool(scene.execute(d)), scene.eef_position, dirs,
                         scene.step_length, scene.eef_position(), start[None, :],
                         cfg.max_moves)


def _split(cfg: WorldConfig, n: int = 20) -> dict[str, float]:
    """Where an evaluation's time goes in `cfg`'s world (`n` random genotypes, this
    process): seconds per evaluation (wall and CPU), in movements, in putting the arm back
    and resting, in rendering; movements and physics steps per evaluation."""
    scene = _world(cfg)
    acc = {"move": 0.0, "back": 0.0, "render": 0.0}
    moves = 0
    orig = {k: getattr(scene, k) for k in ("execute", "render", "place_arm", "settle")}

    def timed(key: str, name: str) -> Any:
        def f(*a: Any, **k: Any) -> Any:
            nonlocal moves
            t = time.perf_counter()
            try:
                return orig[name](*a, **k)
            finally:
                acc[key] += time.perf_counter() - t
                moves += name == "execute"
        return f

    for key, name in (("move", "execute"), ("render", "render"), ("back", "place_arm"),
                      ("back", "settle")):
        setattr(scene, name, timed(key, name))
    rng = np.random.default_rng(0)
    genotypes = [rng.random(3 * cfg.n_waypoints) for _ in range(n)]
    tick0 = scene._tick
    t, c = time.perf_counter(), time.process_time()
    for g in genotypes:
        evaluate_task(EvaluationTask(cfg, g))
    total, cpu = time.perf_counter() - t, time.process_time() - c
    ticks = scene._tick - tick0
    for name, f in orig.items():
        setattr(scene, name, f)
    ref_cfg = replace(cfg, time_step=1.0 / 240.0)
    ref = _world(ref_cfg)
    tick0 = ref._tick
    t, c = time.perf_counter(), time.process_time()
    for g in genotypes:
        _reference_evaluation(ref, ref_cfg, g)
    ref_total, ref_cpu = time.perf_counter() - t, time.process_time() - c
    return {"total": total / n, "cpu": cpu / n, "move": acc["move"] / n,
            "back": acc["back"] / n, "render": acc["render"] / n, "moves": moves / n,
            "ticks": ticks / n, "ref_total": ref_total / n, "ref_cpu": ref_cpu / n,
            "ref_ticks": (ref._tick - tick0) / n, "n": n}


def _rate_check(n: int = 40) -> tuple[int, int, int, float, float, float]:
    """The world's 120 Hz physics against 240 Hz on `n` trajectories aimed low at the box:
    trajectories that moved it at each rate, both, the median distance between where the box
    ended at the two rates, and the median push length at each."""
    rng = np.random.default_rng(7)
    genotypes = []
    for _ in range(n):
        g = rng.random(9)
        g[0::3] = 0.2 + 0.7 * g[0::3]   # x over the box's part of the table
        g[1::3] = 0.35 + 0.4 * g[1::3]  # y likewise
        g[2::3] *= 0.15                 # low
        genotypes.append(g)
    ends = {}
    for hz in (240, 120):
        cfg = WorldConfig(scene="push", seed=0, time_step=1.0 / hz)
        ends[hz] = np.array([evaluate_task(EvaluationTask(cfg, g)).displacement["box"]
                             for g in genotypes])
    moved = {hz: np.hypot(*e.T) > 0.01 for hz, e in ends.items()}
    both = moved[240] & moved[120]
    gap = float(np.median(np.linalg.norm(ends[240][both] - ends[120][both], axis=1)))
    return (int(moved[240].sum()), int(moved[120].sum()), int(both.sum()), gap,
            float(np.median(np.hypot(*ends[240][moved[240]].T))),
            float(np.median(np.hypot(*ends[120][moved[120]].T))))


def _novelty_ms(archive: int) -> float:
    """Milliseconds of one NovEB generation's bookkeeping (μ = λ = 20, k = 15, 1024-D
    descriptors) against an archive of `archive` behaviours."""
    rng = np.random.default_rng(0)
    pool = rng.random((40, 1024))
    ref = np.vstack([pool, rng.random((archive, 1024))])
    t = time.perf_counter()
    reps = 5
    for _ in range(reps):
        novelty(pool, ref, 15)
    return 1000 * (time.perf_counter() - t) / reps


def _ask_tell_ms() -> float:
    """Milliseconds of NovEB's ask + tell of one generation (DEAP variation, selection)."""
    s = NovEB(9, 0, 20 * 20, NovEBConfig(mu=20, lambda_=20))
    rng = np.random.default_rng(1)
    t = time.perf_counter()
    drive(s, lambda g: rng.random((len(g), 1024)), batch=20)  # 20 generations
    return 1000 * (time.perf_counter() - t) / 20


def run() -> str:
    cfg = WorldConfig(scene="push", seed=0)
    sp = _split(cfg)
    rows = []
    loads: list[float] = []
    with tempfile.TemporaryDirectory(prefix="a2l-bench-babbling-") as tmp:
        for workers in (1, 2):
            loads.append(os.getloadavg()[0])
            m = run_babbling("noveb", N, 0, "push", Path(tmp) / f"w{workers}", workers=workers,
                             generation_size=20, quiet=True, plots=False)
            t = m["totals"]
            rows.append(f"| NovEB, push, seed 0, {N} evaluations | {workers} | "
                        f"{t['wall_s']:.1f} | {t['evaluations_per_s']:.2f} |")
    per = sp["total"]
    other = per - sp["move"] - sp["back"] - sp["render"]
    m240, m120, both, gap, push240, push120 = _rate_check()
    nov = {a: _novelty_ms(a) for a in (100, 2000)}
    return "\n".join([
        "One evaluation: reset, the genotype's 3 waypoints followed with the scene's "
        "discrete 5 cm movements (at most 16), the arm put back at the start kinematically "
        f"(`place_arm`) and {RETURN_REST_S} s of physics for the objects to come to rest, "
        "one camera image before and one after (160×120, the software renderer), the "
        "32×32 descriptor. `WorldConfig` defaults: movement speed 0.5 m/s, physics at "
        "120 Hz.",
        "",
        "| run | workers | wall (s) | evaluations/s |",
        "|---|---|---|---|",
        *rows,
        "",
        "The 2-worker run starts its worker processes inside the timed run (spawn, imports, "
        "one Baxter scene each: seconds). The machine's 1-minute load average as each run "
        f"started: {loads[0]:.1f} (1 worker) and {loads[1]:.1f} (2 workers), on "
        f"{os.cpu_count()} cores (above the cores: other jobs shared them).",
        "",
        f"Where one evaluation's time goes ({sp['n']:.0f} random genotypes, 1 process): "
        f"**{1000 * per:.0f} ms** wall ({1000 * sp['cpu']:.0f} ms of CPU), "
        f"{sp['moves']:.1f} movements and {sp['ticks']:.0f} physics steps on average.",
        "",
        "| part | ms per evaluation | share |",
        "|---|---|---|",
        f"| movements (IK + physics), {1000 * sp['move'] / max(sp['moves'], 1):.0f} ms each "
        f"| {1000 * sp['move']:.0f} | {sp['move'] / per:.0%} |",
        f"| arm put back + {RETURN_REST_S} s rest (physics) | {1000 * sp['back']:.0f} | "
        f"{sp['back'] / per:.0%} |",
        f"| rendering (2 images) | {1000 * sp['render']:.1f} | {sp['render'] / per:.1%} |",
        f"| reset, descriptor, bookkeeping | {1000 * other:.0f} | {other / per:.0%} |",
        "",
        f"The evaluation before (every movement retraced physically back to the start, "
        f"240 Hz), the same genotypes in the same run: {1000 * sp['ref_total']:.0f} ms wall "
        f"({1000 * sp['ref_cpu']:.0f} ms of CPU), {sp['ref_ticks']:.0f} physics steps: the "
        f"new one is **{sp['ref_total'] / per:.1f}×** cheaper in wall time, "
        f"{sp['ref_cpu'] / sp['cpu']:.1f}× in CPU. A physics step costs about the same in both "
        "(Baxter's 56 links and 19 position motors): the steps are what went.",
        "",
        f"120 Hz against 240 Hz, 40 trajectories aimed low at the box (same genotypes): "
        f"moved it at 240 Hz {m240}, at 120 Hz {m120}, both {both}; where a box moved at "
        f"both rates ended differs by a median {100 * gap:.1f} cm (pushes that turn the box "
        f"diverge); median push {100 * push240:.1f} cm at 240 Hz, {100 * push120:.1f} cm "
        "at 120 Hz.",
        "",
        f"NovEB's own computation per generation of 20 (not per evaluation): novelty of 40 "
        f"behaviours against an archive of 100: {nov[100]:.1f} ms, of 2,000: "
        f"{nov[2000]:.1f} ms; ask + tell with DEAP's operators and selection (archive "
        f"growing): {_ask_tell_ms():.1f} ms. Physics dominates; the full acceptance "
        f"configuration (2,000 evaluations × 5 seeds × 3 methods × 2 scenes = 60,000 "
        f"evaluations) costs about {60000 * sp['cpu'] / 3600:.1f} h of one core (CPU time) "
        "at this rate.",
    ])
