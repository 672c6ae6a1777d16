"""The vocabulary the C++ core owns (``cpp/include/a2l/effects.hpp``,
``movement_repertoire.hpp``) is what Python reads: the movement repertoire's default order and
labels, the effect names, the effect tests and their constants. Python keeps no copy of them:
each value here is read from ``a2l._core`` and checked against the definition."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from a2l import _core
from a2l.acquisition.trajectory import follow_waypoints
from a2l.lfd.demonstrators import PUSH_DIRECTIONS
from a2l.planning.repertoire import DIRECTIONS as PLANNING_DIRECTIONS
from a2l.rollout import effect_tests as et
from a2l.sim.object_configs import GraspConfig
from a2l.skills.effects import (
    AXIS_EFFECTS,
    DIAGONAL_EFFECTS,
    EFFECT_DIRECTIONS,
    EFFECT_NAMES,
    EffectDiscretizer,
)
from a2l.skills.repertoire import MovementRepertoire, default_directions, direction_label


def test_effect_names_are_the_cores() -> None:
    assert EFFECT_NAMES == tuple(_core.effect_names(8)) == (
        "left", "right", "close", "far", "close_left", "close_right", "far_left", "far_right")
    assert AXIS_EFFECTS == tuple(_core.effect_names(4)) == EFFECT_NAMES[:4]
    assert DIAGONAL_EFFECTS == EFFECT_NAMES[4:]
    assert EffectDiscretizer(8).values == EFFECT_NAMES
    assert [_core.effect_index(n) for n in EFFECT_NAMES] == list(range(8))
    assert _core.effect_name(-1) == "none"


def test_effect_directions_are_the_cores() -> None:
    assert EFFECT_DIRECTIONS == {n: tuple(_core.effect_direction(i))
                                 for i, n in enumerate(EFFECT_NAMES)}
    assert EFFECT_DIRECTIONS["far"] == (1.0, 0.0) and EFFECT_DIRECTIONS["left"] == (0.0, 1.0)
    assert EFFECT_DIRECTIONS["close_right"] == (-1.0, -1.0)
    assert PUSH_DIRECTIONS == {n: EFFECT_DIRECTIONS[n] for n in AXIS_EFFECTS}
    assert PLANNING_DIRECTIONS == {n: (int(x), int(y)) for n, (x, y) in EFFECT_DIRECTIONS.items()}


def test_effect_constants_are_the_cores() -> None:
    assert et.PUSH_DISTANCE == _core.PUSH_DISTANCE == 0.05
    assert et.AWAY_RADIUS == _core.AWAY_RADIUS == 0.04
    assert et.AWAY_TOLERANCE == _core.AWAY_TOLERANCE == 0.01
    assert et.RETREAT.tolist() == list(_core.retreat_offset()) == [-0.12, 0.0, 0.16]
    assert not et.RETREAT.flags.writeable
    d = EffectDiscretizer()
    assert (d.threshold, d.ratio) == (_core.EFFECT_THRESHOLD, _core.EFFECT_RATIO) == (0.01, 3.0)
    assert GraspConfig().lift_threshold == _core.LIFT_THRESHOLD == 0.05


def test_default_directions_are_the_cores() -> None:
    for planar in (False, True):
        dirs = default_directions(planar)
        assert dirs.dtype == np.int64 and dirs.flags.c_contiguous and not dirs.flags.writeable
        assert np.array_equal(dirs, _core.default_directions(planar))
        assert np.array_equal(MovementRepertoire(planar=planar).directions, dirs)
        labels = MovementRepertoire(planar=planar).labels
        assert labels == tuple(_core.direction_label(d) for d in dirs)
    assert MovementRepertoire(planar=True).labels == (
        "+x", "-x", "+y", "-y", "+x+y", "+x-y", "-x+y", "-x-y")
    dirs = default_directions()
    assert len(dirs) == 26
    assert [direction_label(d) for d in dirs[:6]] == ["+x", "-x", "+y", "-y", "+z", "-z"]
    # the table order: fewer non-zero signs first; then the zero pattern; then + before -
    def key(d: tuple[int, ...]) -> tuple[int, ...]:
        return (sum(1 for s in d if s), *(s == 0 for s in d), *(-s for s in d))

    every = [d for d in itertools.product((1, -1, 0), repeat=3) if any(d)]
    assert [tuple(d) for d in dirs.tolist()] == sorted(every, key=key)


def test_waypoints_choose_the_same_sign_vectors_in_any_order() -> None:
    """play_and_look's movements are indices into the core's order (NovEB's rollouts map them
    to the framework's repertoire by sign vector): the order of the candidates changes the
    index, never the movement chosen (no tie between two directions)."""
    rng = np.random.default_rng(0)
    lexicographic = np.array([d for d in itertools.product((-1, 0, 1), repeat=3) if any(d)])
    chosen = []
    for dirs in (default_directions(), lexicographic):
        moved: list[tuple[int, int, int]] = []

        def execute(d: tuple[int, int, int], moved: list = moved) -> bool:
            moved.append(d)
            return True

        for k in range(200):
            points = rng.uniform(-0.3, 0.3, (3, 3)) if k % 2 else np.c_[
                rng.uniform(-0.3, 0.3, (3, 2)), np.zeros(3)]
            out, _ = follow_waypoints(execute, lambda: np.zeros(3),
                                      dirs, 0.05, np.zeros(3), points, 40)
            assert [tuple(int(s) for s in dirs[m]) for m in out] == moved[-len(out):]
        chosen.append(moved)
        rng = np.random.default_rng(0)
    assert chosen[0] == chosen[1]


def test_push_test_is_the_cores() -> None:
    """The push test against its definition (along / across the push direction)."""
    rng = np.random.default_rng(1)
    directions = {"far": (1.0, 0.0), "close": (-1.0, 0.0), "left": (0.0, 1.0),
                  "right": (0.0, -1.0)}
    for effect, d in directions.items():
        assert np.array_equal(_core.effect_direction(AXIS_EFFECTS.index(effect)), d)
        test = et.EFFECT_TESTS[effect]
        n = np.array([-d[1], d[0]])
        for xy in rng.normal(0, 0.05, (500, 2)):
            along, across = float(xy @ np.asarray(d)), abs(float(xy @ n))
            want = (True, along > across) if along >= 0.05 else (across >= 0.05, False)
            progress = et.Progress(effect, np.r_[xy, 0.0], *(np.zeros(3),) * 3, {}, {}, None)
            assert test(progress) == want
    with pytest.raises(ValueError):
        et.push_test("far_left")


def test_away_is_the_cores() -> None:
    """a2l::stayed_away against its definition, on random poses."""
    rng = np.random.default_rng(2)
    for _ in range(2000):
        obj = rng.normal(0, 0.3, 3)
        eef = obj + et.RETREAT + rng.normal(0, 0.03, 3)
        moved = rng.normal(0, 0.008, 3)
        want = (np.linalg.norm(eef - obj - et.RETREAT) <= et.AWAY_RADIUS
                and np.linalg.norm(moved) < et.AWAY_TOLERANCE)
        assert _core.stayed_away(eef, obj, moved) == want
    assert not _core.stayed_away(np.full(3, np.nan), np.zeros(3), np.zeros(3))


def test_away_judges_the_true_block_not_the_one_the_camera_saw() -> None:
    """grasp_light, trial seed 1000 with the camera at 256 x 192: the block read 4.1 mm off,
    the gripper 3.8 cm from the retreat pose of the true block but 4.0 cm from that of the
    seen one; the outcome is the true block's."""

    class Scene:
        def observe_effect(self, since: str, source: str) -> str:
            return "none"

    block = np.array([0.607, -0.277, -0.17])
    seen = block + [0.0037, -0.0018, 0.0]
    eef = np.array([0.487, -0.241, 0.003])
    assert np.linalg.norm(eef - block - et.RETREAT) < et.AWAY_RADIUS
    assert np.linalg.norm(eef - seen - et.RETREAT) > et.AWAY_RADIUS
    pr = et.Progress("away", np.zeros(3), seen, seen, eef, {}, {}, Scene())
    assert et.away_test(pr) == (False, False)  # the seen block alone
    pr.true_obj = block
    assert et.away_test(pr) == (True, True)


def test_one_registry_of_effect_tests() -> None:
    assert set(et.EFFECT_TESTS) >= {*AXIS_EFFECTS, "grasped", "pressed", "away"}
    assert set(et.SCENE_OUTCOMES) == {"grasped", "pressed", "away"}
    assert et.effect_test_of("away") is et.away_test
    assert et.effect_test_of("flown") is None
