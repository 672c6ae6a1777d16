"""Effect tests of the manipulation skills: did the episode produce what was wanted?

- ``grasped``: the block is at least ``lift_threshold`` (5 cm in the grasp scenes) above
  where it was at the episode's start, in the closed gripper (the scene's detector,
  :meth:`a2l.sim.Scene.observe_effect`).
- ``pressed``: the button toggled the light since the episode's start.
- ``away`` (the light-on behaviour of ``grasp_light``, a "hot stove"): the end-effector is
  at least :data:`AWAY` from the block, the block has not moved (< 1 cm) and is not held.

Every test reads the ground truth (the true state of the world, not the camera's).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from a2l.errors import A2LValueError

__all__ = ["AWAY", "EFFECT_TESTS", "effect_test", "stayed_away"]

#: Distance (m) from the block beyond which the end-effector is "away" from it.
AWAY = 0.15


def stayed_away(scene: Any, obj: str | None = None, distance: float = AWAY,
                tolerance: float = 0.01) -> bool:
    """The light-on behaviour: away from the object, which was left where it was.

    Parameters
    ----------
    scene : a2l.sim.Scene
    obj : str, optional
        Default: the scene's primary object.
    distance : float
        Smallest end-effector-object distance (m).
    tolerance : float
        Largest displacement (m) of the object since the episode's start.
    """
    name = obj or scene.primary_object
    start = scene._episode_start["ground_truth"].objects.get(name)
    now = scene.ground_truth()["objects"].get(name)
    if start is None or now is None:
        return False
    now = np.asarray(now, dtype=float)
    moved = float(np.linalg.norm(now - np.asarray(start, dtype=float)))
    far = float(np.linalg.norm(scene.eef_position() - now))
    return far >= distance and moved < tolerance


def _effect_named(effect: str) -> Any:
    def test(scene: Any) -> bool:
        return bool(scene.observe_effect(since="episode", source="ground_truth") == effect)

    test.__name__ = effect
    return test


#: Effect name -> test ``f(scene) -> bool`` of the episode so far.
EFFECT_TESTS: dict[str, Any] = {
    "grasped": _effect_named("grasped"),
    "pressed": _effect_named("pressed"),
    "away": stayed_away,
}


def effect_test(effect: str) -> Any:
    """The test of an effect name (:data:`EFFECT_TESTS`); a clear error for an unknown one."""
    if effect not in EFFECT_TESTS:
        raise A2LValueError(f"no effect test for '{effect}'; known: {sorted(EFFECT_TESTS)}")
    return EFFECT_TESTS[effect]
