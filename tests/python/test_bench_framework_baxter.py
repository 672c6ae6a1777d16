"""The Baxter run's time breakdown (benchmarks/bench_framework_baxter.py) times what it says
on a tiny camera run, and puts every timed function back."""

from __future__ import annotations

import importlib.util
from pathlib import Path

from a2l.experiments import push
from a2l.experiments.push import run_push_experiment
from a2l.framework import FrameworkConfig, loop
from a2l.sim.bullet.motion import MotionMixin
from a2l.sim.perception import Camera

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_framework_baxter.py"


def _bench():  # noqa: ANN202
    spec = importlib.util.spec_from_file_location("bench_framework_baxter", BENCH)
    assert spec and spec.loader
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_breakdown_times_phases_physics_and_rendering(tmp_path: Path) -> None:
    bench = _bench()
    before = (loop.acquire, push.plot_scores, MotionMixin._sim_step, Camera.render)
    cfg = FrameworkConfig(
        scene="bullet",
        max_iterations=1,
        seed=0,
        discretization={"n_effects": 4},
        starts={"n_starts": 2},
        babbling={"try_cap": 6},
        heldout={"n_starts": 0},
    )
    with bench.breakdown() as b, bench.dropped() as count:
        run_push_experiment(cfg, tmp_path / "run", workers=1, quiet=True)
    assert (loop.acquire, push.plot_scores, MotionMixin._sim_step, Camera.render) == before
    assert b.calls["acquire"] == 1 and b.calls["generate_skill"] == 1
    assert b.calls["plots"] >= 3 and b.seconds["plots"] > 0
    physics, rendering = b.calls["physics (PyBullet steps)"], b.calls[
        "rendering (PyBullet TinyRenderer)"]
    assert physics > 10 * rendering > 0  # ~55 steps a movement, about one frame
    assert b.seconds["acquire"] > b.seconds["physics (PyBullet steps)"] * 0.5
    # one worker: every try sent is told (nothing asked ahead)
    assert count["sent"] == count["told"] == 6 and count["given_up"] == 0
