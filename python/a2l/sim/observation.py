"""What a scene observes at one instant, and the effect between two such observations."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from a2l.skills.effects import effect_name

__all__ = ["Observation", "observed_effect"]


@dataclass
class Observation:
    """Object positions and high-level states at one instant (perceived or true)."""

    objects: dict[str, tuple[float, float, float]] = field(default_factory=dict)
    states: dict[str, str] = field(default_factory=dict)
    eef: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    gripper_closed: bool = False

    def as_dict(self) -> dict[str, dict[str, Any]]:
        return {"objects": dict(self.objects), "states": dict(self.states)}


def observed_effect(before: Observation, after: Observation, movable: Iterable[str],
                    cfg: Any) -> str:
    """Name the effect between two observations of a scene.

    Parameters
    ----------
    before, after : Observation
        The earlier and the later observation.
    movable : iterable of str
        Names of the objects whose displacement counts (a pressed button does not).
    cfg : scene config
        Reads ``n_push_effects``, ``effect_threshold``, ``effect_ratio`` and, if it has
        one, ``lift_threshold``.

    Returns
    -------
    str
        ``"pressed"`` (the light toggled), ``"grasped"`` (an object lifted in the closed
        gripper, within 8 cm of the end-effector), the push effect of the object that moved
        most (:func:`a2l.skills.effects.effect_name`) or ``"none"``.
    """
    if "light" in before.states and before.states.get("light") != after.states.get("light"):
        return "pressed"
    best, best_d = None, -1.0
    for name in movable:
        if name not in before.objects or name not in after.objects:
            continue
        b = np.asarray(before.objects[name])
        a = np.asarray(after.objects[name])
        if (a[2] - b[2] > getattr(cfg, "lift_threshold", np.inf) and after.gripper_closed
                and np.linalg.norm(a - after.eef) < 0.08):
            return "grasped"
        dist = float(np.hypot(*(a - b)[:2]))
        if dist > best_d:
            best, best_d = a - b, dist
    if best is None:
        return "none"
    return effect_name(best, cfg.n_push_effects, cfg.effect_threshold, cfg.effect_ratio)
