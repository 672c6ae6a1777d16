"""Effect tests of the demonstrated skills: did a run produce its effect?

An effect test looks at the run's :class:`Progress` after each movement and answers
``(done, success)``. The push tests (:func:`push_test`) are registered here; other skills
register theirs with :func:`register_effect_test`; an effect without one falls back on the
scene outcome of that name (:mod:`a2l.sim.outcomes`: ``grasped``, ``pressed``, ``away``),
done once it holds (:func:`effect_test_of`). :func:`a2l.lfd.execute.run_skill` runs them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from a2l.lfd.demonstrators import PUSH_DIRECTIONS

__all__ = ["EFFECT_TESTS", "PUSH_DISTANCE", "EffectTest", "Progress", "effect_test_of",
           "light_test", "push_test", "register_effect_test", "scene_test"]

#: A push skill succeeds when the object moved at least this far (m) the right way.
PUSH_DISTANCE = 0.05

@dataclass
class Progress:
    """What an effect test looks at, after each movement.

    Attributes
    ----------
    effect : str
        The wanted effect.
    produced : ndarray, shape (3,)
        Object displacement the executed movements produced (perturbations excluded).
    start_object, obj, eef : ndarray, shape (3,)
        Object at the start, object and end-effector now (NaN: not seen).
    start_states, states : dict of str to str
        High-level states at the start and now.
    scene : a2l.sim.Scene
        The scene (for tests that need more, e.g. whether the gripper holds the object).
    """

    effect: str
    produced: np.ndarray
    start_object: np.ndarray
    obj: np.ndarray
    eef: np.ndarray
    start_states: dict[str, str]
    states: dict[str, str]
    scene: Any


#: An effect test: ``progress -> (done, success)``.
EffectTest = Callable[[Progress], tuple[bool, bool]]


def push_test(effect: str, distance: float = PUSH_DISTANCE) -> EffectTest:
    """The effect test of a push: done when the produced displacement reaches `distance`
    along the push direction (success when that axis dominates: the 4-effect class is
    `effect`) or `distance` across it (failure)."""
    d = np.asarray(PUSH_DIRECTIONS[effect])
    n = np.array([-d[1], d[0]])

    def test(pr: Progress) -> tuple[bool, bool]:
        xy = pr.produced[:2]
        along, across = float(xy @ d), abs(float(xy @ n))
        if along >= distance:
            return True, along > across
        return across >= distance, False

    return test


#: Effect name -> effect test.
EFFECT_TESTS: dict[str, EffectTest] = {e: push_test(e) for e in PUSH_DIRECTIONS}


def scene_test(fn: Callable[[Any], bool]) -> EffectTest:
    """An effect test from a test of the scene's episode so far (``f(scene) -> bool``, such
    as :data:`a2l.sim.outcomes.EFFECT_TESTS`): done (and successful) once it holds."""

    def test(pr: Progress) -> tuple[bool, bool]:
        ok = bool(fn(pr.scene))
        return ok, ok

    return test


def effect_test_of(effect: str) -> EffectTest | None:
    """The registered test of `effect`, else the scene outcome of that name, else None."""
    if effect in EFFECT_TESTS:
        return EFFECT_TESTS[effect]
    from a2l.sim import outcomes

    fn = outcomes.EFFECT_TESTS.get(effect)
    return None if fn is None else scene_test(fn)


def light_test(effect_by_light: dict[str, str]) -> EffectTest:
    """The effect test of a skill whose wanted outcome depends on the light: the test of
    ``effect_by_light[light]`` for the light the step sees (``"off"`` when none)."""
    tests = {}
    for light, effect in effect_by_light.items():
        test = effect_test_of(effect)
        if test is None:
            raise ValueError(f"no effect test for effect {effect!r} (light {light!r})")
        tests[light] = test
    return lambda pr: tests[pr.states.get("light", "off")](pr)


def register_effect_test(effect: str, test: EffectTest) -> None:
    """Register (or replace) the effect test of `effect`."""
    if not callable(test):
        raise TypeError(f"the effect test of {effect!r} must be callable")
    EFFECT_TESTS[str(effect)] = test
