"""Effect tests: did a run, or the scene's episode so far, produce the wanted effect?

The tests and their constants are the C++ core's (``cpp/include/a2l/effects.hpp``:
``a2l::push_test``, ``a2l::stayed_away``, ``kPushDistance``, ``kAwayRadius``, ...), which
``a2l-run`` calls too; this module reads them from ``a2l._core`` and holds the one registry
of effect tests, :data:`EFFECT_TESTS`.

- A push (``left``, ``right``, ``close``, ``far``, :func:`push_test`): done when the
  displacement the movements produced reaches :data:`PUSH_DISTANCE` along the push direction
  (success when that axis dominates) or across it (failure).
- ``grasped``: the block is at least ``lift_threshold`` (5 cm in the grasp scenes) above
  where it was at the episode's start, in the closed gripper (the scene's detector,
  :meth:`a2l.sim.Scene.observe_effect`).
- ``pressed``: the button toggled the light since the episode's start.
- ``away`` (the light-on behaviour of ``grasp_light``, a "hot stove"): the end-effector
  waits within :data:`AWAY_RADIUS` of ``block + RETREAT`` (back and up, 20 cm from the
  block), the block having moved less than :data:`AWAY_TOLERANCE`.

A run's test (:data:`EffectTest`) looks at its :class:`Progress` after each movement and
answers ``(done, success)``; the scene's outcome (:func:`scene_outcome`, ``f(scene) ->
bool``) reads the ground truth of the episode so far. Other skills register their tests
with :func:`register_effect_test`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from a2l import _core
from a2l.errors import A2LValueError
from a2l.rollout.protocol import SceneProtocol
from a2l.skills.effects import AXIS_EFFECTS

__all__ = ["AWAY_RADIUS", "AWAY_TOLERANCE", "EFFECT_TESTS", "PUSH_DISTANCE", "RETREAT",
           "SCENE_OUTCOMES", "EffectTest", "Progress", "away_test", "effect_test_of",
           "light_test", "push_test", "register_effect_test", "scene_outcome", "scene_test",
           "stayed_away"]

#: A push skill succeeds when the object moved at least this far (m) the right way.
PUSH_DISTANCE: float = _core.PUSH_DISTANCE
#: Where the light-on behaviour waits, relative to the block (m): back and up.
RETREAT: NDArray[np.float64] = np.asarray(_core.retreat_offset(), dtype=float)
RETREAT.setflags(write=False)
#: How close to the retreat pose the end-effector must be (m).
AWAY_RADIUS: float = _core.AWAY_RADIUS
#: How far the block may have moved for ``away`` (m).
AWAY_TOLERANCE: float = _core.AWAY_TOLERANCE


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
    true_obj : ndarray, shape (3,), optional
        The object's true position now (None: `obj` is the truth, or it is unknown). With
        the context read from the camera, `obj` is what the skill saw; a test judges the
        outcome on this one.
    """

    effect: str
    produced: np.ndarray
    start_object: np.ndarray
    obj: np.ndarray
    eef: np.ndarray
    start_states: dict[str, str]
    states: dict[str, str]
    scene: SceneProtocol
    true_obj: np.ndarray | None = None


#: An effect test: ``progress -> (done, success)``.
EffectTest = Callable[[Progress], tuple[bool, bool]]


def stayed_away(scene: SceneProtocol, obj: str | None = None) -> bool:
    """The scene's ``away`` outcome: the end-effector at the retreat pose of object `obj`
    (default: the scene's primary object), which has not moved since the episode's start
    (ground truth; ``a2l::stayed_away``)."""
    name = obj or scene.primary_object
    start = scene.episode_start()["objects"].get(name)
    now = scene.ground_truth()["objects"].get(name)
    if start is None or now is None:
        return False
    now = np.asarray(now, dtype=float)
    return bool(_core.stayed_away(scene.eef_position(), now,
                                  now - np.asarray(start, dtype=float)))


def _effect_named(effect: str) -> Callable[[SceneProtocol], bool]:
    def test(scene: SceneProtocol) -> bool:
        return bool(scene.observe_effect(since="episode", source="ground_truth") == effect)

    test.__name__ = effect
    return test


_SCENE_OUTCOMES: dict[str, Callable[[SceneProtocol], bool]] = {
    "grasped": _effect_named("grasped"),
    "pressed": _effect_named("pressed"),
    "away": stayed_away,
}
#: The effects the scene itself tells from its episode so far (:func:`scene_outcome`).
SCENE_OUTCOMES: tuple[str, ...] = tuple(_SCENE_OUTCOMES)


def scene_outcome(effect: str) -> Callable[[SceneProtocol], bool]:
    """The scene's test ``f(scene) -> bool`` of `effect` over the episode so far (ground
    truth); a clear error for an effect not in :data:`SCENE_OUTCOMES`."""
    if effect not in _SCENE_OUTCOMES:
        raise A2LValueError(f"no effect test for '{effect}'; known: {sorted(_SCENE_OUTCOMES)}")
    return _SCENE_OUTCOMES[effect]


def scene_test(fn: Callable[[SceneProtocol], bool]) -> EffectTest:
    """An effect test from a test of the scene's episode so far (``f(scene) -> bool``, such
    as :func:`scene_outcome`'s): done (and successful) once it holds."""

    def test(pr: Progress) -> tuple[bool, bool]:
        ok = bool(fn(pr.scene))
        return ok, ok

    return test


def push_test(effect: str, distance: float = PUSH_DISTANCE) -> EffectTest:
    """The effect test of a push (``a2l::push_test``): done when the produced displacement
    reaches `distance` along the push direction (success when that axis dominates: the
    4-effect class is `effect`) or `distance` across it (failure)."""
    if effect not in AXIS_EFFECTS:
        raise ValueError(f"unknown push effect {effect!r}; known: {sorted(AXIS_EFFECTS)}")
    index = AXIS_EFFECTS.index(effect)

    def test(pr: Progress) -> tuple[bool, bool]:
        done, success = _core.push_test(np.asarray(pr.produced[:2], dtype=float), index,
                                        distance)
        return bool(done), bool(success)

    return test


def away_test(pr: Progress) -> tuple[bool, bool]:
    """Effect test of ``away`` (the light-on behaviour of ``grasp_light``), ``(done,
    success)``: done and successful once the end-effector is within :data:`AWAY_RADIUS` of
    the retreat pose relative to the block where it is now, the movements having moved the
    block less than :data:`AWAY_TOLERANCE` (a perturbation that moves it is not the skill's
    doing); done and failed if the block was grasped. The block is its true position
    (``pr.true_obj``) when the progress has it, as every other test judges on the truth: with
    the context from the camera, the block the skill saw may be a few millimetres off."""
    if pr.scene.observe_effect(since="episode", source="ground_truth") == "grasped":
        return True, False
    obj = pr.obj if pr.true_obj is None else pr.true_obj
    ok = bool(_core.stayed_away(np.asarray(pr.eef, dtype=float), np.asarray(obj, dtype=float),
                                np.asarray(pr.produced, dtype=float)))
    return ok, ok


#: Effect name -> effect test: the pushes, the scene's grasped and pressed, away.
EFFECT_TESTS: dict[str, EffectTest] = {
    **{e: push_test(e) for e in AXIS_EFFECTS},
    "grasped": scene_test(_SCENE_OUTCOMES["grasped"]),
    "pressed": scene_test(_SCENE_OUTCOMES["pressed"]),
    "away": away_test,
}


def effect_test_of(effect: str) -> EffectTest | None:
    """The registered test of `effect` (:data:`EFFECT_TESTS`), or None."""
    return EFFECT_TESTS.get(effect)


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
