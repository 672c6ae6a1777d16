"""Held-out evaluation: the held-out starts, their own seed
stream, and the rollouts from them deciding nothing; plus the framework's batched driving
of effect-directed pairs and the ground-truth scene of :func:`make_env`."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from a2l.acquisition.protocol import drive, drive_ahead
from a2l.errors import ConfigError
from a2l.framework import FrameworkConfig, run_framework
from a2l.framework.loop import phase_seed
from a2l.framework.validation import heldout_task
from a2l.framework.waypoints import (
    EffectDirected,
    Missed,
    directed_outcome_task,
    directed_task,
)
from a2l.parallel import Executor
from a2l.rollout.env import make_env


def test_heldout_offsets_lie_in_their_ring_at_uniform_angles() -> None:
    cfg = FrameworkConfig(heldout={"n_starts": 2000, "r_low": 0.10, "r_high": 0.25})
    off = cfg.heldout_offsets()
    assert off.shape == (2000, 3)
    assert np.all(off[:, 2] == 0.0)
    r = np.hypot(off[:, 0], off[:, 1])
    assert r.min() >= 0.10 and r.max() <= 0.25
    # uniform: every eighth of the circle and every third of the ring is visited evenly
    a = np.arctan2(off[:, 1], off[:, 0]) % (2 * np.pi)
    counts = np.histogram(a, bins=8, range=(0, 2 * np.pi))[0]
    assert counts.min() > 200 and counts.max() < 300
    thirds = np.histogram(r, bins=3, range=(0.10, 0.25))[0]
    assert thirds.min() > 600


def test_heldout_offsets_are_seeded_and_apart_from_the_training_starts() -> None:
    cfg = FrameworkConfig(seed=3)
    off = cfg.heldout_offsets()
    assert off.shape == (32, 3)
    assert np.array_equal(off, FrameworkConfig(seed=3).heldout_offsets())
    assert not np.allclose(off, FrameworkConfig(seed=4).heldout_offsets())
    # the same positions whatever the training parameters (their own stream)...
    other = cfg.with_({"starts.n_starts": 12, "max_iterations": 3, "directed.per_pair": 5})
    assert np.array_equal(other.heldout_offsets(), off)
    # ...and none of them is a training start
    train = cfg.start_offsets()
    d = np.linalg.norm(off[:, None, :2] - train[None, :, :2], axis=2)
    assert d.min() > 1e-3
    # the returned array is a copy: mutating it leaves the config's positions alone
    off[:] = 0.0
    assert not np.allclose(cfg.heldout_offsets(), 0.0)


@pytest.mark.parametrize(("field", "value"), [
    ("n_starts", -1), ("n_starts", 2.5), ("r_low", 0.0),
    ("r_high", float("nan")), ("r_high", float("inf")),
])
def test_heldout_config_names_the_bad_field(field: str, value: object) -> None:
    with pytest.raises(ValueError, match=f"^heldout.{field}:"):
        FrameworkConfig().with_({f"heldout.{field}": value})


def test_heldout_ring_must_not_be_reversed() -> None:
    with pytest.raises(ValueError, match=r"^heldout.r_low, r_high:"):
        FrameworkConfig(heldout={"r_low": 0.3, "r_high": 0.2})


def test_heldout_task_refuses_a_start_out_of_range(tmp_path: Path) -> None:
    from a2l.framework import ValidationTask

    cfg = FrameworkConfig(heldout={"n_starts": 4})
    with pytest.raises(ValueError, match="held-out start 4 out of range"):
        heldout_task(ValidationTask(cfg, str(tmp_path / "none.a2lb"), 4, 0))


@pytest.mark.slow
def test_heldout_rollouts_decide_nothing(tmp_path: Path) -> None:
    """A run with held-out starts and one without give the same training metrics and
    dataset: held-out rollouts take no training draw, accept nothing, stick no pair."""
    base = FrameworkConfig(
        scene="virtual", seed=1, max_iterations=2, discretization={"n_effects": 4}
    )
    with Executor(workers=1) as ex:
        off = run_framework(base.with_({"heldout.n_starts": 0}), tmp_path / "off", ex)
        on = run_framework(base.with_({"heldout.n_starts": 6}), tmp_path / "on", ex)
    strip = [{k: v for k, v in it.items() if k != "wall_s"} for it in off.iterations]
    assert [{k: v for k, v in it.items() if k != "wall_s"} for it in on.iterations] == strip
    assert off.dataset.equals(on.dataset)
    # (the skill is learnt from the dataset alone; the bundles differ in the config they
    # record, heldout_starts)
    assert off.heldout == [] and off.heldout_score is None
    assert [h["iteration"] for h in on.heldout] == [0, 1]
    assert all(0.0 <= h["heldout_score"] <= 100.0 for h in on.heldout)
    kept = max(it["iteration"] for it in on.iterations if it["accepted"])
    assert on.heldout_score == on.heldout[kept]["heldout_score"]
    assert len(on.heldout_validation) == 6 * 4


@pytest.mark.slow
def test_resumed_run_keeps_its_heldout_history(tmp_path: Path) -> None:
    cfg = FrameworkConfig(scene="virtual", seed=1, max_iterations=2,
                          discretization={"n_effects": 4}, heldout={"n_starts": 4})
    with Executor(workers=1) as ex:
        whole = run_framework(cfg, tmp_path / "whole", ex)
        run_framework(cfg.with_(max_iterations=1), tmp_path / "split", ex)
        resumed = run_framework(cfg, tmp_path / "split", ex)
    strip = [{k: v for k, v in h.items() if k != "heldout_wall_s"} for h in whole.heldout]
    assert [{k: v for k, v in h.items() if k != "heldout_wall_s"}
            for h in resumed.heldout] == strip
    assert resumed.heldout_score == whole.heldout_score


class _Ready:
    """Outcomes computed now, behind a submission's ``result()``."""

    def __init__(self, outcomes: list) -> None:
        self.outcomes = outcomes

    def result(self) -> list:
        return self.outcomes


class _Later:
    """Outcomes computed when asked for (the rounds submitted ahead run out of order)."""

    def __init__(self, fn, items: list) -> None:  # noqa: ANN001
        self.fn, self.items = fn, items

    def result(self) -> list:
        return [self.fn(t) for t in self.items]


def _drive_together(strategies: list, evaluate, batch: int, ahead: int = 0) -> None:  # noqa: ANN001
    """The framework's way: candidates (each naming its wanted effect) evaluated in rounds."""
    if ahead == 0:
        submit = lambda pairs: _Ready(evaluate([c for _, c in pairs]))  # noqa: E731
    else:
        submit = lambda pairs: _Later(lambda p: evaluate([p])[0],  # noqa: E731
                                      [c for _, c in pairs])
    drive_ahead(strategies, submit, batch, ahead=ahead)


def test_directed_pairs_driven_together_find_what_they_find_one_by_one() -> None:
    cfg = FrameworkConfig(scene="virtual", seed=2, directed={"per_pair": 3})
    pairs = [(4, 2), (0, 1), (6, 3)]

    def strategies() -> list[EffectDirected]:
        return [EffectDirected(cfg, s, e, lambda i, j=j: phase_seed(cfg, 1, 2 + j, i),
                               want=5, cap=70) for j, (s, e) in enumerate(pairs)]

    calls: list[int] = []

    def evaluate(tasks: list) -> list:
        calls.append(len(tasks))
        return [directed_task(t) for t in tasks]

    alone = strategies()
    for s in alone:
        drive(s, evaluate, batch=8)
    n_alone = len(calls)
    calls.clear()
    together = strategies()
    _drive_together(together, evaluate, batch=8)
    for a, t in zip(alone, together, strict=True):
        assert a.tried == t.tried
        assert [r.moves for r in a.found] == [r.moves for r in t.found]
        assert [r.effect for r in t.found] == [t.effect] * len(t.found)
    assert len(calls) < n_alone
    assert len(calls) == max(-(-s.tried // 8) for s in alone)
    # the light outcomes (an effect index for every trajectory not kept) keep the same
    light = strategies()
    sent: list = []

    def evaluate_light(pairs: list) -> list:
        out = [directed_outcome_task(p) for p in pairs]
        sent.extend(out)
        return out

    _drive_together(light, evaluate_light, batch=8)
    for a, t in zip(alone, light, strict=True):
        assert a.tried == t.tried
        assert [r.moves for r in a.found] == [r.moves for r in t.found]
    kept = sum(len(t.found) for t in light)
    assert sum(not isinstance(o, Missed) for o in sent) >= kept
    assert sum(isinstance(o, Missed) for o in sent) > kept  # most come back light


@pytest.mark.parametrize("ahead", [1, 3])
def test_rounds_asked_ahead_end_as_rounds_one_by_one(ahead: int) -> None:
    """Rounds submitted before the previous ones are told (as on workers) are dropped past
    the point where a strategy is done: every strategy ends as driven one round at a time,
    whatever the number of rounds in advance."""
    cfg = FrameworkConfig(scene="virtual", seed=2, directed={"per_pair": 3})
    pairs = [(4, 2), (0, 1), (6, 3), (2, 0)]

    def strategies() -> list[EffectDirected]:
        return [EffectDirected(cfg, s, e, lambda i, j=j: phase_seed(cfg, 1, 2 + j, i),
                               want=w, cap=70) for j, ((s, e), w) in
                enumerate(zip(pairs, (5, 1, 3, 200), strict=True))]

    def evaluate(pairs_: list) -> list:
        return [directed_outcome_task(p) for p in pairs_]

    one_by_one = strategies()
    _drive_together(one_by_one, evaluate, batch=8)
    ahead_ = strategies()
    _drive_together(ahead_, evaluate, batch=8, ahead=ahead)
    for a, b in zip(one_by_one, ahead_, strict=True):
        assert (a.tried, a.done) == (b.tried, b.done)
        assert [r.moves for r in a.found] == [r.moves for r in b.found]
        assert b.asked >= b.tried  # asked ahead, dropped when done
    assert ahead_[3].tried == 70 and len(ahead_[3].found) < 200  # one ran into its cap
    assert any(b.asked > b.tried for b in ahead_)


def test_drive_ahead_refuses_a_strategy_that_cannot_be_asked_ahead() -> None:
    class Plain:
        done = False

    with pytest.raises(TypeError, match="cannot be asked ahead"):
        drive_ahead([Plain()], lambda pairs: _Ready([]), batch=4)


def test_make_env_sets_the_scene_to_the_source_it_reads() -> None:
    env = make_env("virtual", seed=0)
    assert env.scene.config.context_source == env.source == "perceived"  # the camera
    env.close()
    env = make_env("virtual", seed=0, context_source="ground_truth")
    assert env.source == "ground_truth"
    env.close()
    with pytest.raises(ValueError, match="contradicts"):
        make_env("virtual", source="ground_truth", context_source="perceived")
    with pytest.raises(ValueError, match="source"):
        make_env("virtual", source="oracle")


def test_baxter_env_renders_no_camera_frame_per_movement() -> None:
    """The Baxter scene of a ground-truth env records no perceived observation: nothing
    renders a camera frame at each movement's start."""
    env = make_env("bullet", seed=0, source="ground_truth")
    try:
        assert env.scene.config.context_source == "ground_truth"
        env.begin(np.array([0.2, 0.0, 0.0]))
        env.execute((-1, 0, 0))
        assert "perceived" not in env.scene._step_start
        assert "perceived" not in env.scene._episode_start
    finally:
        env.close()


def test_an_unreachable_heldout_start_is_redrawn_the_same_way_everywhere() -> None:
    """Baxter, seed 1: held-out start 23 lies 0.249 m beyond the box along +x, where the arm
    cannot hold the gripper down (the run crashed there before the redraw); it is replaced by
    its first reachable redraw, from the same ring, and every call gives the same one. A
    reachable start is kept as drawn."""
    from a2l.errors import UnreachableError
    from a2l.framework.validation import reachable_heldout
    from a2l.rollout.env import scene_env

    cfg = FrameworkConfig(scene="bullet", seed=1, discretization={"n_effects": 4})
    raw = cfg.heldout_offsets()
    env = scene_env(cfg)
    with pytest.raises(UnreachableError, match="unreachable"):
        env.begin(raw[23])
    got = reachable_heldout(cfg, 23)
    assert not np.array_equal(got, raw[23])
    assert 0.10 <= np.hypot(got[0], got[1]) <= 0.25 and got[2] == 0.0
    assert any(np.array_equal(got, cfg.heldout_redraw(23, k)) for k in range(1, 21))
    env.begin(got)  # reachable
    assert np.array_equal(reachable_heldout(cfg, 23), got)
    assert np.array_equal(reachable_heldout(cfg, 0), raw[0])
    with pytest.raises(ValueError, match="attempt"):
        cfg.heldout_redraw(23, 0)


def test_the_framework_reads_the_context_from_the_camera_by_default() -> None:
    """Every rollout's env (babbling, extension, validation, held-out: all through
    scene_env) reads the camera unless the config says ground truth; one frame per
    movement of the main camera on Baxter."""
    from a2l.rollout.env import scene_env

    cfg = FrameworkConfig(scene="bullet", seed=3)
    assert cfg.context_source == "perceived"
    env = scene_env(cfg)
    assert env.source == env.scene.config.context_source == "perceived"
    renders = []  # frames of the main camera (the side ones render when the arm hides the box)
    cam = env.scene.cameras[0]
    cam.render = (lambda f: lambda: renders.append(1) or f())(cam.render)
    env.begin(np.array([0.2, 0.0, 0.0]))
    for _ in range(3):
        env.object()
        env.execute((-1, 0, 0))
    env.object()
    assert len(renders) == 4  # the start, then one frame after each movement
    assert "perceived" in env.scene._step_start
    truth = scene_env(FrameworkConfig(scene="bullet", seed=3, context_source="ground_truth"))
    assert truth.source == "ground_truth" and truth is not env
    old = scene_env(FrameworkConfig(scene="bullet", seed=3,
                                    scene_config={"source": "ground_truth"}))
    assert old.source == "ground_truth"
    with pytest.raises(ConfigError, match="context_source"):
        FrameworkConfig(context_source="camera").validate()


def test_rounds_given_up_on_workers_change_nothing() -> None:
    """On worker processes the parts of the rounds in flight that belong to strategies done
    meanwhile are given up (:meth:`a2l.parallel.Pending.drop`): every strategy ends as
    driven one round at a time."""
    cfg = FrameworkConfig(scene="virtual", seed=2, directed={"per_pair": 3})
    pairs = [(4, 2), (0, 1), (6, 3), (2, 0)]

    def strategies() -> list[EffectDirected]:
        return [EffectDirected(cfg, s, e, lambda i, j=j: phase_seed(cfg, 1, 2 + j, i),
                               want=4, cap=60) for j, (s, e) in enumerate(pairs)]

    alone = strategies()
    for s in alone:
        drive(s, lambda tasks: [directed_task(t) for t in tasks], batch=4)
    together = strategies()
    with Executor(workers=2) as ex:
        drive_ahead(together, lambda got: ex.submit(
            directed_outcome_task, [c for _, c in got], batches=2 * len(got)),
            batch=4, ahead=2)
    for a, t in zip(alone, together, strict=True):
        assert a.tried == t.tried
        assert [r.moves for r in a.found] == [r.moves for r in t.found]
