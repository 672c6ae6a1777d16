"""Effect tests of the manipulation skills: did the episode produce what was wanted?

- ``grasped``: the block is at least ``lift_threshold`` (5 cm in the grasp scenes) above
  where it was at the episode's start, in the closed gripper (the scene's detector,
  :meth:`a2l.sim.Scene.observe_effect`).
- ``pressed``: the button toggled the light since the episode's start.
- ``away`` (the light-on behaviour of ``grasp_light``, a "hot stove"): the end-effector
  waits at the retreat pose, within :data:`AWAY_RADIUS` of ``block + RETREAT`` (back and
  up, 20 cm from the block), and the block has not moved (< 1 cm) since the episode's start.

Every test reads the ground truth (the true state of the world, not the camera's).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l.errors import A2LValueError

__all__ = ["AWAY_RADIUS", "EFFECT_TESTS", "RETREAT", "effect_test", "stayed_away"]

#: Where the light-on behaviour waits, relative to the block (m): back and up.
RETREAT: NDArray[np.float64] = np.array([-0.12, 0.0, 0.16])
#: How close to the retreat pose the end-effector must be (m).
AWAY_RADIUS = 0.04


def stayed_away(scene: Any, obj: str | None = None, offset: ArrayLike = RETREAT,
                radius: float = AWAY_RADIUS, tolerance: float = 0.01) -> bool:
    """The light-on behaviour: at the retreat pose, the object left where it was.

    Parameters
    ----------
    scene : a2l.sim.Scene
    obj : str, optional
        Default: the scene's primary object.
    offset : array_like, shape (3,)
        The retreat pose relative to the object (m).
    radius : float
        Largest distance (m) of the end-effector from ``object + offset``.
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
    off = float(np.linalg.norm(scene.eef_position() - now - np.asarray(offset, dtype=float)))
    return off <= radius and moved < tolerance


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
