"""The babbling experiment (NovEB and its baselines on Baxter's push scene): evaluations per
second with 1 and 2 local workers, and where an evaluation's time goes (physics and IK of the
movements, camera rendering, the descriptor) beside NovEB's own computation (novelty against
an archive)."""

from __future__ import annotations

import tempfile
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

from a2l.acquisition.noveb import NovEB, NovEBConfig, novelty
from a2l.experiments.babbling import run_babbling
from a2l.experiments.babbling_world import WorldConfig, _world, evaluate_task

TITLE = "Babbling (NovEB, random and goal babbling on Baxter's push scene)"

#: Evaluations of each timed run (one NovEB generation of 10, then another).
N = 20


def _split() -> tuple[float, float, float, float, int]:
    """Seconds per evaluation in all, in movements, in rendering; movements per evaluation;
    evaluations timed (random genotypes, this process)."""
    cfg = WorldConfig(scene="push", seed=0)
    scene = _world(cfg)
    move_s = render_s = 0.0
    moves = 0
    orig_execute, orig_render = scene.execute, scene.render

    def execute(d: tuple[int, int, int]) -> object:
        nonlocal move_s, moves
        t = time.perf_counter()
        try:
            return orig_execute(d)
        finally:
            move_s += time.perf_counter() - t
            moves += 1

    def render(camera: int = 0) -> object:
        nonlocal render_s
        t = time.perf_counter()
        try:
            return orig_render(camera)
        finally:
            render_s += time.perf_counter() - t

    scene.execute, scene.render = execute, render  # type: ignore[method-assign]
    rng = np.random.default_rng(0)
    n = 10
    t = time.perf_counter()
    for _ in range(n):
        evaluate_task((asdict(cfg), rng.random(9)))
    total = time.perf_counter() - t
    scene.execute, scene.render = orig_execute, orig_render  # type: ignore[method-assign]
    return total / n, move_s / n, render_s / n, moves / n, n


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
    s = NovEB(9, 0, 10**6, NovEBConfig(mu=20, lambda_=20))
    rng = np.random.default_rng(1)
    t = time.perf_counter()
    for _ in range(20):
        g = s.ask(20)
        s.tell(g, rng.random((len(g), 1024)))
    return 1000 * (time.perf_counter() - t) / 20


def run() -> str:
    per_eval, move_s, render_s, moves, n = _split()
    rows = []
    with tempfile.TemporaryDirectory(prefix="a2l-bench-babbling-") as tmp:
        for workers in (1, 2):
            m = run_babbling("noveb", N, 0, "push", Path(tmp) / f"w{workers}", workers=workers,
                             generation_size=10, quiet=True, plots=False)
            t = m["totals"]
            rows.append(f"| NovEB, push, seed 0, {N} evaluations | {workers} | "
                        f"{t['wall_s']:.1f} | {t['evaluations_per_s']:.2f} |")
    other = per_eval - move_s - render_s
    nov = {a: _novelty_ms(a) for a in (100, 2000)}
    return "\n".join([
        "One evaluation: reset, the genotype's 3 waypoints followed with discrete movements "
        "(at most 16 out, retraced back), one camera image before and one after (160×120, "
        "the software renderer), the 32×32 descriptor. `WorldConfig` defaults (movement "
        "speed 0.5 m/s).",
        "",
        "| run | workers | wall (s) | evaluations/s |",
        "|---|---|---|---|",
        *rows,
        "",
        "The 2-worker run starts its worker processes inside the timed run (spawn, imports, "
        "one Baxter scene each: seconds) and shares the machine's two cores with the other "
        "jobs running then: over 20 evaluations it does not pay back.",
        "",
        f"Where one evaluation's time goes ({n} random genotypes, 1 process): "
        f"**{per_eval:.2f} s** in all, {moves:.0f} movements on average.",
        "",
        "| part | ms per evaluation | share |",
        "|---|---|---|",
        f"| movements (IK + physics), {1000 * move_s / max(moves, 1):.0f} ms each | "
        f"{1000 * move_s:.0f} | {move_s / per_eval:.0%} |",
        f"| rendering (2 images) | {1000 * render_s:.1f} | {render_s / per_eval:.1%} |",
        f"| reset, descriptor, bookkeeping | {1000 * other:.0f} | {other / per_eval:.0%} |",
        "",
        f"NovEB's own computation per generation of 20 (not per evaluation): novelty of 40 "
        f"behaviours against an archive of 100: {nov[100]:.1f} ms, of 2,000: "
        f"{nov[2000]:.1f} ms; ask + tell with DEAP's operators and selection (archive "
        f"growing): {_ask_tell_ms():.1f} ms. Physics dominates; the full acceptance "
        f"configuration (2,000 evaluations × 5 seeds × 3 methods × 2 scenes = 60,000 "
        f"evaluations) costs about {60000 * per_eval / 3600:.0f} h of one core at this rate.",
    ])
