"""The framework's small parts: score, configuration errors, start positions, loop erasure,
random waypoint trajectories, the effect-directed budget of stuck pairs, and the
``a2l experiment`` command's argument errors (exit code 2, no traceback)."""

from __future__ import annotations

import dataclasses
import json
import re
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from a2l.acquisition.interactions import (
    Rollout,
    erase_loops,
    play,
    rollouts_from_table,
    rollouts_table,
)
from a2l.cli import main
from a2l.errors import ConfigError
from a2l.framework import (
    FAIL,
    FALSE_POSITIVE,
    SUCCESS,
    BabbleTask,
    DirectedTask,
    FrameworkConfig,
    babble_task,
    directed_task,
    extend,
    heading_chooser,
    random_waypoints,
    score_of,
)
from a2l.framework.scoring import miss_counts, outcome_of, success_of
from a2l.parallel import Executor
from a2l.rollout.env import SceneEnv, make_env


def _rollouts(outcomes: list[str]) -> list[Rollout]:
    """Validation rollouts with the given outcomes (positions do not enter the score)."""
    z = np.zeros((1, 3))
    return [Rollout(start=i, moves=[], eef=z, obj=z, outcome=o) for i, o in enumerate(outcomes)]


# --- score ------------------------------------------------------------------------------

@pytest.mark.parametrize(("outcomes", "n_effects", "n_starts", "expected"), [
    # 4 effects x 2 starts = 8 rollouts, 32 points at most.
    ([SUCCESS] * 8, 4, 2, 100.0),
    ([FAIL] * 8, 4, 2, 0.0),
    ([FALSE_POSITIVE] * 8, 4, 2, 25.0),                        # 8 / 32
    ([SUCCESS] * 3 + [FALSE_POSITIVE] * 2 + [FAIL] * 3, 4, 2, 43.75),  # (12 + 2) / 32
    # 8 effects x 8 starts = 64 rollouts, 256 points: 60 successes and 3 false positives.
    ([SUCCESS] * 60 + [FALSE_POSITIVE] * 3 + [FAIL], 8, 8, 100.0 * 243 / 256),
    # 4 effects x 8 starts: a single success.
    ([SUCCESS] + [FAIL] * 31, 4, 8, 100.0 * 4 / 128),
])
def test_score_of_hand_values(outcomes: list[str], n_effects: int, n_starts: int,
                              expected: float) -> None:
    assert score_of(_rollouts(outcomes), n_effects, n_starts) == pytest.approx(expected,
                                                                                abs=1e-12)


def test_success_rate_counts_a_false_positive_as_a_failure() -> None:
    """The headline: 3 successes of 8 is 37.5 % whatever the 2 false positives; the score
    counts them as points (43.75); the misses are told apart by how they ended."""
    rs = _rollouts([SUCCESS] * 3 + [FALSE_POSITIVE] * 2 + [FAIL] * 3)
    rs[5].stop, rs[6].stop, rs[7].stop = "unknown_context", "step_cap", "unknown_context"
    rs[6].fallbacks = 2
    assert success_of(rs) == pytest.approx(3 / 8)
    assert score_of(rs, 4, 2) == pytest.approx(43.75)
    assert miss_counts(rs) == {"false_positive": 2, "unknown_context": 2, "step_cap": 1,
                               "with_fallback": 1}
    assert np.isnan(success_of([]))


def test_score_of_babbling_rollouts_count_nothing() -> None:
    # Babbling rollouts have no outcome: no points.
    assert score_of(_rollouts(["", "", SUCCESS]), 4, 1) == pytest.approx(25.0)


# --- configuration ----------------------------------------------------------------------

@pytest.mark.parametrize(("field", "value"), [
    ("scene", "kitchen"),
    ("discretization.n_effects", 6),
    ("starts.n_starts", 0),
    ("babbling.max_steps", -1),
    ("babbling.try_cap", 2.5),
    ("max_iterations", 0),
    ("skill.step_cap", 0),
    ("discretization.n_orient", 0),
    ("discretization.n_dist", 0),
    ("extension.max_extensions", 0),
    ("directed.per_pair", 0),
    ("directed.try_cap", 0),
    ("directed.steps", 0),
    ("directed.stuck_after", 0),
    ("directed.growth", 0),
    ("starts.radius", 0.0),
    ("discretization.step", -0.05),
    ("discretization.effect_threshold", float("nan")),
    ("starts.radius", float("inf")),
    ("discretization.n_incl", -1),
    ("extension.cut", 0),
    ("learning.structure", "random-forest"),
    ("directed.mode", "spiral"),
    ("directed.waypoints_max", -1),
    ("directed.waypoints_max", 1.5),
    ("directed.waypoint_aim", 0.0),
    ("directed.waypoint_aim", float("nan")),
    ("discretization.n_offset", 2),
    ("discretization.n_offset", -1),
    ("discretization.offset_half_x", 0.0),
    ("discretization.offset_half_y", float("inf")),
    ("learning.fixed_parents", "distance"),
    ("learning.fixed_parents", [1]),
    ("learning.fixed_parents", ("distance", "light")),
    ("learning.fixed_parents", ("offset_x",)),
    ("starts.layout", "spiral"),
    ("starts.r_low", 0.0),
    ("starts.r_high", float("nan")),
    ("skill.fallback", "guess"),
    ("skill.train_fallback", "nearer"),
])
def test_a_bad_field_is_refused_naming_it(field: str, value: object) -> None:
    """Every part checks its fields when it is made; the error names the field by its dotted
    name (the command line's option)."""
    with pytest.raises(ValueError, match=rf"^{re.escape(field)}:"):
        FrameworkConfig().with_({field: value})
    # from_dict checks too, with the same message.
    head, _, rest = field.partition(".")
    d = FrameworkConfig().to_dict()
    if rest:
        d[head] = {**d[head], rest: value}
    else:
        d[head] = value
    with pytest.raises(ValueError, match=rf"^{re.escape(field)}:"):
        FrameworkConfig.from_dict(d)


@pytest.mark.parametrize(("low", "high"), [(0.2, 0.2), (0.3, 0.1)])
def test_validate_distance_range(low: float, high: float) -> None:
    with pytest.raises(ValueError, match=r"^discretization.dist_low, dist_high:"):
        FrameworkConfig(discretization={"dist_low": low, "dist_high": high})
    with pytest.raises(ValueError, match=r"^discretization.dist_low:"):
        FrameworkConfig(discretization={"dist_low": -0.1})


def test_a_misspelt_part_or_field_is_refused_with_the_valid_names() -> None:
    with pytest.raises(ValueError, match=r"^discretization: unknown field\(s\) \['n_orientt'\]"
                       r".*n_orient"):
        FrameworkConfig(discretization={"n_orientt": 24})
    with pytest.raises(ValueError, match=r"discretization has no field 'n_orientt'.*n_orient"):
        FrameworkConfig().with_({"discretization.n_orientt": 24})
    with pytest.raises(ValueError, match=r"no such field \(now discretization.n_orient\)"):
        FrameworkConfig().with_({"n_orient": 24})
    with pytest.raises(ValueError, match=r"no such field.*heldout.n_starts"):
        FrameworkConfig().with_({"held.n_starts": 0})


def test_a_flat_config_of_an_earlier_version_is_converted_naming_each_renamed_field() -> None:
    flat = {"scene": "baxter", "n_effects": 8, "heldout_starts": 4, "directed_per_pair": 9,
            "fixed_parents": ["distance", "orientation"], "seed": 3}
    with pytest.warns(FutureWarning, match=r"n_effects is now discretization.n_effects, "
                      r"heldout_starts is now heldout.n_starts, directed_per_pair is now "
                      r"directed.per_pair, fixed_parents is now learning.fixed_parents"):
        cfg = FrameworkConfig.from_dict(flat)
    assert cfg == FrameworkConfig(scene="bullet", seed=3, discretization={"n_effects": 8},
                                  heldout={"n_starts": 4}, directed={"per_pair": 9},
                                  learning={"fixed_parents": ("distance", "orientation")})


def test_fallback_defaults_by_scene_and_an_explicit_rule_wins() -> None:
    """Baxter heads for the nearest cell with data, the virtual scene stops (as
    measured in ``docs/experiments/push.md``); a rule given explicitly is kept, and a
    config read back from its dict keeps the resolved rule."""
    assert FrameworkConfig(scene="bullet").skill.fallback == "approach"
    assert FrameworkConfig(scene="virtual").skill.fallback == "none"
    assert FrameworkConfig(scene="bullet", skill={"fallback": "none"}).skill.fallback == "none"
    assert FrameworkConfig(scene="virtual",
                           skill={"fallback": "nearest"}).skill.fallback == "nearest"
    cfg = FrameworkConfig(scene="bullet")
    assert FrameworkConfig.from_dict({**cfg.to_dict(), "scene": "virtual"}
                                     ).skill.fallback == "approach"
    with pytest.raises(ConfigError, match="fallback"):
        FrameworkConfig(scene="bullet", skill={"fallback": "guess"})


def test_training_validation_runs_the_training_rule(tmp_path: Path) -> None:
    """The training validation's skill is the learned one with ``train_fallback`` (a copy
    beside it when the rules differ, the same file when they agree); Baxter trains with
    ``nearest`` and runs with ``approach``, the virtual scene uses ``none`` for both."""
    from a2l.framework.rules import training_bundle
    from a2l.skills import Discretizer, MovementRepertoire
    from a2l.skills.bundle import load_bundle, save_bundle
    from a2l.skills.pipeline import compile_policy, learn_network, make_skill_spec
    from a2l.skills.synthetic import push_dataset

    base = FrameworkConfig(scene="bullet")
    assert (base.skill.fallback, base.skill.train_fallback) == ("approach", "nearest")
    virtual = FrameworkConfig(scene="virtual")
    assert (virtual.skill.fallback, virtual.skill.train_fallback) == ("none", "none")
    assert FrameworkConfig(scene="bullet", skill={"train_fallback": "approach"}
                           ).skill.train_fallback == "approach"
    disc = Discretizer(movements=MovementRepertoire(planar=True), inclination=None)
    net = learn_network(disc.discretize(push_dataset(300, seed=1)), "hand-coded")
    spec = make_skill_spec(compile_policy(net, "move", disc.evidence), disc, name="push")
    path = tmp_path / "iter_000.a2lb"
    save_bundle(replace(spec, fallback="approach", clearance=0.10, clearance_ratio=0.25,
                        align=0.05, avoid_revisits=True, step_cap=16), path)
    train = training_bundle(base, path)
    assert train == tmp_path / "iter_000.train.a2lb"
    got, run = load_bundle(train), load_bundle(path)
    assert (got.fallback, run.fallback) == ("nearest", "approach")
    # the exported skill keeps the clearance, alignment and revisit rules; the training
    # validation runs without them
    assert (got.clearance, run.clearance) == (0.0, 0.10)
    assert (got.align, run.align) == (0.0, 0.05)
    assert (got.avoid_revisits, run.avoid_revisits) == (False, True)
    assert run.clearance_ratio == 0.25
    # the exported skill runs longer than the training validation's
    assert (base.skill.step_cap, base.skill.train_step_cap) == (16, 12)
    assert (got.step_cap, run.step_cap) == (12, 16)
    assert np.array_equal(got.posterior, run.posterior) and got.extra == run.extra
    same = base.with_({"skill.train_fallback": "approach", "skill.clearance": 0.0,
                       "skill.align": 0.0, "skill.avoid_revisits": False,
                       "skill.train_step_cap": 16})
    assert training_bundle(same, path) == path
    # a shorter training cap alone still trains on a copy with it
    capped = training_bundle(same.with_({"skill.train_step_cap": 12}), path)
    assert capped != path and load_bundle(capped).step_cap == 12
    # the revisit rule alone still trains on a copy without it
    alone = training_bundle(same.with_({"skill.avoid_revisits": True}), path)
    assert alone != path and not load_bundle(alone).avoid_revisits
    # the alignment rule alone still trains on a copy without it
    aligned = training_bundle(same.with_({"skill.align": 0.05}), path)
    assert aligned != path and load_bundle(aligned).align == 0.0
    # a rule of the same fallback but a clearance still trains on a copy without it
    copy = training_bundle(base.with_({"skill.train_fallback": "approach"}), path)
    assert copy != path and load_bundle(copy).clearance == 0.0


def test_validation_runs_to_the_bundles_step_cap(tmp_path: Path) -> None:
    """A validation rollout ends at the cap of the bundle it runs (the training copy's, the
    exported skill's), not at the configuration's ``skill.step_cap``: from 0.15 m on the
    side `right` pushes toward, the skill needs 4 movements."""
    from a2l.framework.validation import _closed_loop
    from a2l.skills.bundle import save_bundle
    from a2l.skills.pipeline import compile_policy, learn_network, make_skill_spec
    from a2l.skills.synthetic import push_dataset

    cfg = FrameworkConfig(scene="virtual").with_({"skill.step_cap": 2})
    disc = cfg.discretization.discretizer()
    net = learn_network(disc.discretize(push_dataset(300, seed=1)), "hand-coded")
    spec = make_skill_spec(compile_policy(net, "move", disc.evidence), disc, name="push")
    got = {}
    for cap in (2, 12):
        path = tmp_path / f"cap{cap}.a2lb"
        save_bundle(replace(spec, step_cap=cap), path)
        r = _closed_loop(cfg, str(path), 0, np.array([0.15, 0.0, 0.0]), 1)
        got[cap] = (r.executed, r.stop, r.outcome)
    assert got[2] == (2, "step_cap", "fail")
    assert got[12] == (4, "moved", "success")


@pytest.mark.parametrize("value", [0.0, 1.5, float("nan"), "0.5", True])
def test_clearance_ratio_must_be_a_share(value: object) -> None:
    with pytest.raises(ValueError, match="^skill.clearance_ratio:"):
        FrameworkConfig().with_({"skill.clearance_ratio": value})
    assert FrameworkConfig().skill.clearance_ratio == 0.25
    assert FrameworkConfig().skill.avoid_revisits
    assert not FrameworkConfig.preset("thesis").skill.avoid_revisits
    assert (FrameworkConfig().skill.align, FrameworkConfig.preset("thesis").skill.align) == (
        0.05, 0.0)


@pytest.mark.parametrize("value", [-0.01, float("nan"), "0.05", True])
def test_align_must_be_a_length(value: object) -> None:
    with pytest.raises(ValueError, match="^skill.align:"):
        FrameworkConfig().with_({"skill.align": value})


@pytest.mark.parametrize("value", [-0.01, float("nan"), "0.1", True])
def test_clearance_must_be_a_length(value: object) -> None:
    with pytest.raises(ValueError, match="^skill.clearance:"):
        FrameworkConfig().with_({"skill.clearance": value})
    assert FrameworkConfig().skill.clearance == 0.10
    assert FrameworkConfig.preset("thesis").skill.clearance == 0.0


def test_default_config_is_valid_and_round_trips() -> None:
    cfg = FrameworkConfig(seed=7, scene="baxter", scene_config={"gui": False},
                          discretization={"n_effects": 8})
    assert FrameworkConfig.from_dict(json.loads(json.dumps(cfg.to_dict()))) == cfg


def test_fixed_parents_keep_distance_in_a_small_dataset(tmp_path: Path) -> None:
    """Iteration 0's dataset is small: hill-climbing + K2 leaves ``distance`` out of
    ``move``'s parents (virtual seed 0, as on every seed of docs/framework.md's sweep);
    ``fixed_parents=("distance",)`` keeps it, and a name that is no context variable is
    refused."""
    from a2l.acquisition.interactions import interaction_rows
    from a2l.framework import acquire, generate_skill
    from a2l.parallel import Executor
    from a2l.skills import load_bundle

    cfg = FrameworkConfig(scene="virtual", seed=0, discretization={"n_effects": 4})
    with Executor(workers=1) as local:
        frame = interaction_rows(acquire(cfg, local, 0).rollouts,
                                 cfg.discretization.discretizer())
    names = {}
    for fixed in ((), ("distance",)):
        bundle = tmp_path / f"fixed-{len(fixed)}.a2lb"
        generate_skill(cfg.with_({"learning.fixed_parents": fixed}), frame, bundle)
        names[fixed] = [v.name for v in load_bundle(bundle).variables]
    assert "distance" not in names[()]
    assert "distance" in names[("distance",)]
    with pytest.raises(ValueError, match=r"^learning.fixed_parents: \['light'\] not context"):
        cfg.with_({"learning.fixed_parents": ("light",)})



def test_from_dict_names_unknown_keys() -> None:
    d = {**FrameworkConfig().to_dict(), "n_startz": 8, "effects": 4}
    with pytest.raises(ValueError, match=r"unknown config key\(s\) \['effects', 'n_startz'\]"):
        FrameworkConfig.from_dict(d)


# --- start positions --------------------------------------------------------------------

def test_start_offsets_evenly_on_the_circle() -> None:
    cfg = FrameworkConfig(starts={"n_starts": 8, "layout": "circle", "radius": 0.2})
    off = cfg.start_offsets()
    assert off.shape == (8, 3)
    np.testing.assert_allclose(np.linalg.norm(off, axis=1), 0.2, atol=1e-12)
    np.testing.assert_allclose(off[:, 2], 0.0, atol=0)
    # First start on +x, then counter-clockwise every 45 degrees.
    np.testing.assert_allclose(off[0], [0.2, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(off[2], [0.0, 0.2, 0.0], atol=1e-12)
    np.testing.assert_allclose(off[4], [-0.2, 0.0, 0.0], atol=1e-12)
    s = 0.2 / np.sqrt(2)
    np.testing.assert_allclose(off[1], [s, s, 0.0], atol=1e-12)
    np.testing.assert_allclose(off[7], [s, -s, 0.0], atol=1e-12)
    # Neighbouring starts are a chord of 2 r sin(pi / n) apart.
    chords = np.linalg.norm(np.diff(np.vstack([off, off[:1]]), axis=0), axis=1)
    np.testing.assert_allclose(chords, 2 * 0.2 * np.sin(np.pi / 8), atol=1e-12)


def test_start_offsets_spread_over_the_ring() -> None:
    """The ring layout: every angle of the circle layout, the radii spread over the ring
    users start from (0.10-0.25 m), each once, neighbouring angles far apart."""
    cfg = FrameworkConfig(starts={"layout": "ring"})
    assert (cfg.starts.r_low, cfg.starts.r_high, cfg.starts.n_starts) == (0.10, 0.25, 8)
    off = cfg.start_offsets()
    circle = FrameworkConfig(starts={"layout": "circle"}).start_offsets()
    angles = np.arctan2(off[:, 1], off[:, 0])
    np.testing.assert_allclose(angles, np.arctan2(circle[:, 1], circle[:, 0]), atol=1e-12)
    r = np.linalg.norm(off, axis=1)
    np.testing.assert_allclose(np.sort(r), np.linspace(0.10, 0.25, 8), atol=1e-12)
    np.testing.assert_allclose(r[:4], [0.10, 0.10 + 0.15 * 4 / 7, 0.10 + 0.15 * 2 / 7,
                                       0.10 + 0.15 * 6 / 7], atol=1e-12)
    assert np.min(np.abs(np.diff(np.append(r, r[0])))) >= 0.15 / 7 - 1e-12
    assert cfg.starts.outer_radius == 0.25
    assert FrameworkConfig(starts={"layout": "circle"}).starts.outer_radius == 0.2
    # any count: each radius of the ring once
    r5 = np.linalg.norm(FrameworkConfig(starts={"n_starts": 5, "layout": "ring"}
                                        ).start_offsets(), axis=1)
    np.testing.assert_allclose(np.sort(r5), np.linspace(0.10, 0.25, 5), atol=1e-12)


def test_start_offsets_other_radius_and_count() -> None:
    off = FrameworkConfig(
        starts={"n_starts": 3, "layout": "circle", "radius": 0.15}
    ).start_offsets()
    angles = np.degrees(np.arctan2(off[:, 1], off[:, 0]))
    np.testing.assert_allclose(angles, [0.0, 120.0, -120.0], atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(off, axis=1), 0.15, atol=1e-12)


def test_start_position_in_the_virtual_scene() -> None:
    """The end-effector begins at the object's home + the offset, the object at home."""
    cfg = FrameworkConfig()
    env = make_env("virtual", seed=0, step=cfg.discretization.step)
    try:
        for offset in cfg.start_offsets():
            env.begin(offset)
            np.testing.assert_allclose(env.object(), env.home, atol=1e-9)
            np.testing.assert_allclose(env.eef(), env.home + offset, atol=1e-9)
            planar = np.linalg.norm((env.eef() - env.object())[:2])
            assert planar == pytest.approx(np.linalg.norm(offset), abs=1e-9)
    finally:
        env.close()


# --- loop erasure -----------------------------------------------------------------------

def test_erase_loops_cuts_a_return_before_contact() -> None:
    p0, p1, p2, p3 = (np.array(v, float) for v in
                      ([0, 0, 0], [0.05, 0, 0], [0, 0.05, 0], [0, 0.10, 0]))
    o0, o1 = np.zeros(3), np.array([0, 0.03, 0])
    r = Rollout(start=2, moves=[0, 1, 2, 2], eef=np.array([p0, p1, p0, p2, p3]),
                obj=np.array([o0, o0, o0, o0, o1]), effect=1, wanted=3, outcome="fail",
                stop="moved", executed=4, fallbacks=2, true_effect=0)
    e = erase_loops(r)
    assert e.moves == [2, 2]               # out and back again: gone
    np.testing.assert_allclose(e.eef, [p0, p2, p3])
    np.testing.assert_allclose(e.obj, [o0, o0, o1])
    # every other field is the rollout's own (none back at its default)
    kept = [f.name for f in dataclasses.fields(Rollout) if f.name not in ("moves", "eef", "obj")]
    assert {n: getattr(e, n) for n in kept} == {n: getattr(r, n) for n in kept}
    assert all(getattr(r, n) != f.default for f in dataclasses.fields(Rollout)
               if (n := f.name) in kept and f.default is not dataclasses.MISSING)


def test_a_rollout_table_reads_back_the_rollouts_it_stored(tmp_path: Path) -> None:
    """A checkpoint's validation table (written as Parquet) gives back every field of its
    rollouts, in order; a table from before ``fallbacks`` and ``true_effect`` reads them as 0
    and the observed effect."""
    rng = np.random.default_rng(5)
    rollouts = [Rollout(i, [int(m) for m in rng.integers(0, 8, 3 + i)],
                        rng.normal(size=(4 + i, 3)), rng.normal(size=(4 + i, 3)),
                        effect=i % 4, wanted=(i + 1) % 4, outcome=("success", "fail")[i % 2],
                        stop="effect", fallbacks=i, true_effect=(i + 2) % 4)
                for i in range(3)]
    path = tmp_path / "validation.parquet"
    rollouts_table(rollouts).to_parquet(path)
    back = rollouts_from_table(pd.read_parquet(path))
    assert len(back) == 3
    for a, b in zip(rollouts, back, strict=True):
        assert (a.start, a.moves, a.effect, a.wanted, a.outcome, a.stop, a.fallbacks,
                a.true_effect) == (b.start, b.moves, b.effect, b.wanted, b.outcome, b.stop,
                                   b.fallbacks, b.true_effect)
        np.testing.assert_array_equal(a.eef, b.eef)
        np.testing.assert_array_equal(a.obj, b.obj)
    old = rollouts_from_table(rollouts_table(rollouts).drop(columns=["fallbacks", "true_effect"]))
    assert [r.fallbacks for r in old] == [0, 0, 0]
    assert [r.true_effect for r in old] == [r.effect for r in rollouts]


def test_erase_loops_keeps_every_other_field() -> None:
    """Only the moves and positions change: the outcome, the counts and the true effect are
    the rollout's (a validation rollout with a fallback step and a camera-only effect)."""
    eef = np.array([[0, 0, 0], [0.05, 0, 0], [0, 0, 0], [0.02, 0, 0]], float)
    obj = np.array([[0, 0, 0], [0, 0, 0], [0, 0, 0], [0.02, 0, 0]], float)
    r = Rollout(start=2, moves=[3, 7, 3], eef=eef, obj=obj, effect=0, wanted=1,
                outcome="false_positive", stop="moved", executed=5, fallbacks=2, true_effect=1)
    e = erase_loops(r)
    assert e.moves == [3]
    kept = ("start", "effect", "wanted", "outcome", "stop", "executed", "fallbacks",
            "true_effect")
    assert [getattr(e, k) for k in kept] == [getattr(r, k) for k in kept]


def test_erase_loops_keeps_a_loop_free_walk() -> None:
    eef = np.array([[0, 0, 0], [0.05, 0, 0], [0.10, 0, 0]], float)
    obj = np.array([[0, 0, 0], [0, 0, 0], [0.02, 0, 0]], float)
    r = Rollout(start=0, moves=[3, 3], eef=eef, obj=obj, effect=0)
    e = erase_loops(r)
    assert e.moves == [3, 3]
    np.testing.assert_array_equal(e.eef, eef)


# --- random waypoint trajectories ---------------------------------------------------------

def test_random_waypoints_lie_where_drawn() -> None:
    home = np.array([0.6, -0.3, 0.8])
    counts = set()
    for seed in range(200):
        pts = random_waypoints(np.random.default_rng(seed), home, 2, 0.05, 0.25, 0.04)
        counts.add(len(pts))
        assert pts.shape[1] == 3 and 1 <= len(pts) <= 3
        np.testing.assert_allclose(pts[:, 2], home[2], atol=0)
        r = np.linalg.norm((pts[:-1] - home)[:, :2], axis=1)
        assert np.all((r >= 0.05) & (r <= 0.25))
        assert np.all(np.abs(pts[-1, :2] - home[:2]) <= 0.04)
    assert counts == {1, 2, 3}          # 0, 1 and 2 via-points all drawn
    # Seeded: the same generator state gives the same points.
    a = random_waypoints(np.random.default_rng(7), home, 2, 0.05, 0.25, 0.04)
    b = random_waypoints(np.random.default_rng(7), home, 2, 0.05, 0.25, 0.04)
    np.testing.assert_array_equal(a, b)


def test_heading_chooser_passes_its_points_in_order() -> None:
    """Following the chooser's movements (exact 0.05 m steps, no scene) passes within 0.7
    steps of each via-point in turn and ends at the last point."""
    disc = FrameworkConfig().discretization.discretizer()
    step = disc.movements.step
    points = np.array([[0.0, 0.2, 0.0], [-0.15, 0.05, 0.0], [0.01, -0.02, 0.0]])
    eef = np.array([0.2, 0.0, 0.0])
    choose = heading_chooser(points, disc, eef)
    visited = [eef]
    for _ in range(40):
        eef = eef + disc.movements.displacement(choose(eef, np.zeros(3)))
        visited.append(eef)
    visited_a = np.array(visited)
    first_near = [int(np.argmax(np.linalg.norm(visited_a - p, axis=1) < 0.7 * step))
                  for p in points[:2]]
    assert all(np.linalg.norm(visited_a[k] - p) < 0.7 * step
               for k, p in zip(first_near, points[:2], strict=True))
    assert 0 < first_near[0] < first_near[1]
    # It then hovers at the last point (within a diagonal step of it).
    assert np.linalg.norm(visited_a[-1] - points[2]) <= np.sqrt(2) * step + 1e-12
    # It plans on nominal positions: measured ones a few mm off give the same movements
    # (a physics scene's noise must not change a seeded trajectory).
    rng = np.random.default_rng(0)
    clean, noisy = heading_chooser(points, disc, visited_a[0]), heading_chooser(points, disc,
                                                                                 visited_a[0])
    for p in visited_a[:-1]:
        assert clean(p, np.zeros(3)) == noisy(p + rng.normal(0, 0.003, 3), np.zeros(3))


def test_directed_task_random_mode_is_babbling() -> None:
    cfg = FrameworkConfig(directed={"mode": "random"})
    for seed in range(5):
        a = directed_task(DirectedTask(cfg, 3, seed, 20))
        b = babble_task(BabbleTask(cfg, 3, (), seed, 20))
        assert a.moves == b.moves and a.effect == b.effect


def test_waypoint_babbling_goes_around_the_object() -> None:
    """Behind the box for ``close`` (start 4, effect 2), a pushing trajectory must go around
    it. Measured on 2,000 tries: random walks of 20 movements 0.6 %, waypoint
    trajectories 11.8 %; here 300 tries of each (measured: 3 and 33), same seeds."""
    cfg = FrameworkConfig(scene="virtual")
    hits = {}
    for mode in ("random", "waypoints"):
        d = FrameworkConfig(scene="virtual", directed={"mode": mode})
        rs = [directed_task(DirectedTask(d, 4, seed, cfg.directed.steps)) for seed in range(300)]
        hits[mode] = sum(r.effect == 2 for r in rs)
        assert all(r.start == 4 and len(r.moves) <= cfg.directed.steps for r in rs)
    assert hits["waypoints"] >= 15
    assert hits["waypoints"] >= 5 * max(hits["random"], 1)


# --- effect-directed babbling for stuck pairs ---------------------------------------------

@pytest.mark.parametrize(("stuck_for", "growth", "expected"), [
    (1, 5, 3),      # stuck since the last iteration: the base budget
    (3, 5, 9),      # three iterations in a row: three times the budget
    (9, 5, 15),     # capped at directed_growth times
    (3, 1, 3),      # directed_growth=1: a fixed budget
])
def test_directed_budget_grows_while_a_pair_stays_stuck(stuck_for: int, growth: int,
                                                        expected: int) -> None:
    cfg = FrameworkConfig(scene="virtual", seed=4, directed={"per_pair": 3, "growth": growth})
    start, effect = 4, 2         # behind the box for "close": the walk must go around it
    out = extend(cfg, Executor(workers=1), 1, [], {(start, effect): stuck_for, (0, 0): 0}
                 ).rollouts
    assert len(out) == expected
    assert all(r.start == start and r.effect == effect and r.moved for r in out)
    # The same seeds: a larger budget keeps what a smaller one found, and adds to it.
    base = extend(cfg, Executor(workers=1), 1, [], {(start, effect): 1}).rollouts
    assert [r.moves for r in out[: len(base)]] == [r.moves for r in base]


# --- the command's argument errors --------------------------------------------------------

def _exit_code(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    with pytest.raises(SystemExit) as info:
        main(argv)
    return int(info.value.code), capsys.readouterr().err


@pytest.mark.parametrize(("argv", "argument"), [
    (["--effects", "5"], "--effects"),
    (["--scene", "kitchen"], "--scene"),
    (["--workers", "0"], "--workers"),
    (["--seed", "-1"], "--seed"),
    (["--iterations", "zero"], "--iterations"),
    (["--starts", "0"], "--starts"),
    (["--heldout.n-starts", "-1"], "--heldout.n-starts"),
])
def test_push_bad_arguments_exit_2(argv: list[str], argument: str,
                                   capsys: pytest.CaptureFixture[str]) -> None:
    code, err = _exit_code(["experiment", "push", *argv], capsys)
    assert code == 2
    assert f"argument {argument}" in err


def test_push_resume_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, err = _exit_code(["experiment", "push", "--resume", str(tmp_path / "nope")], capsys)
    assert code == 2 and "argument --resume" in err and "not a directory" in err
    code, err = _exit_code(["experiment", "push", "--resume", str(tmp_path)], capsys)
    assert code == 2 and "argument --resume" in err and "config.json" in err
    (tmp_path / "config.json").write_text("{}")
    code, err = _exit_code(["experiment", "push", "--resume", str(tmp_path), "--seed", "3"],
                           capsys)
    assert code == 2 and "argument --seed" in err and "--resume" in err


def test_push_refuses_to_overwrite_a_run(tmp_path: Path,
                                         capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "checkpoints" / "iter_000").mkdir(parents=True)
    code, err = _exit_code(["experiment", "push", "--out", str(tmp_path)], capsys)
    assert code == 2 and "argument --out" in err and f"--resume {tmp_path}" in err


@pytest.mark.slow
def test_push_unreachable_cluster(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # Nothing listens on the discard port of the loopback interface.
    code, err = _exit_code(["experiment", "push", "--out", str(tmp_path / "run"),
                            "--cluster", "tcp://127.0.0.1:9", "--quiet"], capsys)
    assert code == 2 and "argument --cluster" in err and "127.0.0.1:9" in err
    assert not (tmp_path / "run").exists()     # nothing started


def test_discretization_bad_arguments(capsys: pytest.CaptureFixture[str]) -> None:
    code, err = _exit_code(["experiment", "discretization"], capsys)
    assert code == 2 and "--out" in err
    code, err = _exit_code(["experiment", "discretization", "--out", "x", "--workers", "-2"],
                           capsys)
    assert code == 2 and "argument --workers" in err


def test_command_reports_user_errors_without_traceback(tmp_path: Path) -> None:
    """The installed command: a missing resume directory is a message and exit code 2."""
    proc = subprocess.run([sys.executable, "-m", "a2l.cli", "experiment", "push", "--resume",
                           str(tmp_path / "missing")], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 2
    assert "argument --resume" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_discretization_command_writes_the_table(tmp_path: Path) -> None:
    """``a2l experiment discretization``: one run per orientation x distance combination,
    a table and the selected default (one iteration each: the table, not the scores, is
    under test here)."""
    out = tmp_path / "study"
    assert main(["experiment", "discretization", "--out", str(out), "--iterations", "1",
                 "--seed", "1", "--quiet"]) == 0
    m = json.loads((out / "metrics.json").read_text())
    combos = [(r["n_orient"], r["n_dist"]) for r in m["rows"]]
    assert combos == [(o, d) for o in (8, 16, 24, 32) for d in (3, 4, 5)]
    for r, (o, d) in zip(m["rows"], combos, strict=True):
        sub = json.loads((out / f"o{o}-d{d}" / "metrics.json").read_text())
        assert sub["seed"] == 1 and len(sub["iterations"]) == r["iterations"] == 1
        assert r["final_score"] == sub["final_score"]
        cfg = json.loads((out / f"o{o}-d{d}" / "config.json").read_text())["framework"]
        assert (cfg["discretization"]["n_orient"], cfg["discretization"]["n_dist"],
                cfg["seed"]) == (o, d, 1)
    best = max(r["final_score"] for r in m["rows"])
    sel = m["selected"]
    chosen = next(r for r in m["rows"] if (r["n_orient"], r["n_dist"]) == (sel["n_orient"],
                                                                             sel["n_dist"]))
    assert chosen["final_score"] == best
    report = (out / "report.md").read_text()
    rows = [line for line in report.splitlines() if line[:3].strip("| ").isdigit()]
    assert len(rows) == 12
    assert report.count("(selected)") == 1


# --- outcomes judged by what happened ----------------------------------------------------


class _MisreadingEnv(SceneEnv):
    """The virtual scene seen through a camera that, after the first reading, places the
    box 6 cm further along x than it is."""

    def __init__(self, env: SceneEnv) -> None:
        super().__init__(env.scene, "perceived")
        self.reads = 0

    def object(self) -> np.ndarray:
        self.reads += 1
        seen = self.true_object()
        return seen if self.reads == 1 else seen + np.array([0.06, 0.0, 0.0])


def test_a_rollout_is_judged_by_the_objects_true_displacement() -> None:
    """The robot sees an effect the box did not make: the rollout stops as `moved` with the
    seen effect, its true effect is none, and the validation outcome is a failure."""
    cfg = FrameworkConfig(scene="virtual")
    disc = cfg.discretization.discretizer()
    base = make_env("virtual", seed=0, step=cfg.discretization.step, source="ground_truth")
    env = _MisreadingEnv(base)
    try:
        away = int(np.argmax(disc.movements.directions[:, 1]))  # +y: away from a box at -y
        r = play(env, disc, 0, np.array([0.0, 0.20, 0.0]), [], lambda e, o: away, 3)
        assert r.stop == "moved" and r.effect >= 0
        assert r.true_effect == -1
        np.testing.assert_allclose(env.true_object(), env.home, atol=1e-9)
        assert outcome_of(r.true_effect, r.effect) == FAIL
        assert outcome_of(r.effect, r.effect) == SUCCESS
        assert outcome_of(r.effect, (r.effect + 1) % 4) == FALSE_POSITIVE
    finally:
        base.close()
