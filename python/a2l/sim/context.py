"""The context reader's data: low-level states (object relative to the end-effector) and
high-level states, as skills consume them (the words of ``docs/method.md``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["Context", "ObjectContext", "low_level_state"]


@dataclass(frozen=True)
class ObjectContext:
    """Low-level state of one object relative to the end-effector.

    Attributes
    ----------
    position : ndarray, shape (3,)
        Object centre in the world frame (m).
    vector : ndarray, shape (3,)
        ``position - eef`` (m): the object seen from the end-effector.
    distance : float
        ``||eef - position||`` (m).
    orientation : float
        ``atan2`` of ``(eef - position)`` in the table plane, in (-pi, pi] (rad).
    inclination : float
        Angle of ``(eef - position)`` from the vertical (+z), in [0, pi] (rad).
    """

    position: NDArray[np.float64]
    vector: NDArray[np.float64]
    distance: float
    orientation: float
    inclination: float


def low_level_state(eef: ArrayLike, position: ArrayLike) -> ObjectContext:
    """Low-level state of an object at `position` (3,) seen from an end-effector at `eef` (3,)."""
    e = np.asarray(eef, dtype=float).reshape(3)
    p = np.asarray(position, dtype=float).reshape(3)
    rel = e - p
    dist = float(np.linalg.norm(rel))
    # the formulas of a2l.skills.discretizer and the C++ Discretizer (math.atan2: the C
    # library's, as the runtime calls it)
    incl = math.atan2(math.hypot(float(rel[0]), float(rel[1])), float(rel[2]))
    return ObjectContext(
        position=p.copy(), vector=p - e, distance=dist,
        orientation=math.atan2(float(rel[1]), float(rel[0])), inclination=incl,
    )


@dataclass(frozen=True)
class Context:
    """Everything about the robot-object interaction at one instant.

    Attributes
    ----------
    eef : ndarray, shape (3,)
        End-effector point in the world frame (m), from the joint encoders (FK).
    objects : dict of str to ObjectContext
        One entry per object that is present (and, when perceived, visible).
    states : dict of str to str
        High-level states, e.g. ``{"gripper": "open", "light": "off"}``.
    source : str
        ``"perceived"`` or ``"ground_truth"``.
    """

    eef: NDArray[np.float64]
    objects: dict[str, ObjectContext] = field(default_factory=dict)
    states: dict[str, str] = field(default_factory=dict)
    source: str = "ground_truth"
