"""The movements outside a skill that bring the gripper to a push (in
:func:`a2l.rollout.goal.reach_goal`'s runs): the descent from above to the object's height
(:func:`descent`) and the transit over the object to a point behind the face a push needs
(:func:`behind`, :func:`transit`, :class:`Transit`). Each is one of the scene's movements; a
run records it as :data:`DESCENT` or :data:`TRANSIT`, not as an effect's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["DESCENT", "TRANSIT", "Transit", "behind", "descent", "transit"]

#: What a goal-reaching run records for a movement of its descent (no effect's).
DESCENT = "descent"
#: What a goal-reaching run records for a movement of its transit (no effect's).
TRANSIT = "transit"


def descent(eef: ArrayLike, obj: ArrayLike, step: float, air: float = 0.02,
            clear_radius: float = 0.06) -> NDArray[np.float64] | None:
    """The next movement of the descent to the object's height, or None once there.

    Parameters
    ----------
    eef, obj : array_like, shape (3,)
        End-effector and object centre (m).
    step : float
        A movement's length (m).
    air : float
        Higher than this above the object's centre, the end-effector descends (m).
    clear_radius : float
        At least this far from the object in the plane it goes straight down (at most
        `step`, not below the object's centre); nearer, straight away from it (m).

    Returns
    -------
    ndarray, shape (3,), or None
        The displacement (m).
    """
    e, o = np.asarray(eef, dtype=float), np.asarray(obj, dtype=float)
    if e[2] <= o[2] + air:
        return None
    away = e[:2] - o[:2]
    dist = float(np.linalg.norm(away))
    if dist >= clear_radius:
        return np.array([0.0, 0.0, -min(step, float(e[2] - o[2]))])
    unit = away / dist if dist > 1e-9 else np.array([-1.0, 0.0])
    return np.array([unit[0], unit[1], 0.0]) * step


def behind(obj: ArrayLike, direction: ArrayLike, distance: float) -> NDArray[np.float64]:
    """The point `distance` behind the object's centre for a push along `direction`.

    Parameters
    ----------
    obj : array_like, shape (3,)
        The object's centre (m).
    direction : array_like, shape (2,)
        The planar unit direction the object is to move.
    distance : float
        From the object's centre (m).

    Returns
    -------
    ndarray, shape (3,)
        At the object's height (m).
    """
    o = np.asarray(obj, dtype=float)
    u = np.asarray(direction, dtype=float)
    return np.array([o[0] - u[0] * distance, o[1] - u[1] * distance, o[2]])


def _crosses(e: NDArray[np.float64], t: NDArray[np.float64], o: NDArray[np.float64],
             lift: float, clear: float) -> bool:
    """Whether the straight way from `e` to `t` (3,) passes within `clear` of the object's
    centre `o` (3,) in the plane lower than `lift` above it."""
    for s in np.linspace(0.0, 1.0, 21):
        p = e + s * (t - e)
        if p[2] < o[2] + lift and float(np.hypot(*(p[:2] - o[:2]))) < clear:
            return True
    return False


def transit(eef: ArrayLike, obj: ArrayLike, target: ArrayLike, step: float,
            lift: float = 0.07, clear: float = 0.05, gain: float = 1.5,
            tolerance: float = 0.01) -> NDArray[np.float64] | None:
    """The next displacement of a transit to `target` that goes over the object, or None
    once there.

    Straight towards the target where that way stays clear of the object (nowhere within
    `clear` of its centre in the plane lower than `lift` above it); else, low and within
    ``clear + step`` of the object in the plane, straight up to `lift` above its centre;
    else towards the point above the target at the end-effector's height (at least `lift`
    above the object), without descending until the way down is clear.

    Parameters
    ----------
    eef, obj, target : array_like, shape (3,)
        End-effector, object centre and target (m); the target clear of the object.
    step : float
        Most displacement along each axis (m).
    lift : float
        Height above the object's centre over which the transit crosses it (m).
    clear : float
        The way passes the object's centre at least this far in the plane, or over it (m).
    gain : float
        The displacement is `gain` times the way left to the point aimed at (the arm
        carries out part of it), clipped to `step` along each axis.
    tolerance : float
        Arrived within this of the target in the plane and in height (m).

    Returns
    -------
    ndarray, shape (3,), or None
        The displacement (m).
    """
    e, o, t = (np.asarray(v, dtype=float).reshape(3) for v in (eef, obj, target))
    left = t - e
    if float(np.hypot(left[0], left[1])) <= tolerance and abs(float(left[2])) <= tolerance:
        return None
    aim = t.copy()
    if _crosses(e, t, o, lift, clear):
        aim[2] = max(float(e[2]), float(o[2]) + lift)
        if e[2] < o[2] + lift - tolerance and float(np.hypot(*(e[:2] - o[:2]))) < clear + step:
            aim[:2] = e[:2]
    return np.clip(gain * (aim - e), -step, step)


@dataclass(frozen=True)
class Transit:
    """How the arm gets behind the face it pushes next, outside the skill: over the object.

    When the controller switches to an effect (the first one included) with the
    end-effector not already behind the object for it (:meth:`in_place`), it moves to the
    point `behind` the object's centre opposite the effect's direction, at the object's
    height (:func:`behind`, recomputed as the object moves), by :func:`transit`'s
    displacements: over the object where the way there crosses it. The C++ step of the
    skill chooses every movement from there.

    Attributes
    ----------
    behind : float
        Distance of the point from the object's centre (m).
    lift, clear, gain, tolerance : float
        As :func:`transit`.
    lateral : float
        In place: the end-effector within this of the effect's line through the object's
        centre (m), and within ``behind + tolerance`` behind the centre along it.
    max_steps : int
        Most movements of one transit (an unreachable point ends it there).
    """

    behind: float = 0.06
    lift: float = 0.07
    clear: float = 0.05
    gain: float = 1.5
    tolerance: float = 0.01
    lateral: float = 0.02
    max_steps: int = 12

    def target(self, obj: ArrayLike, direction: ArrayLike) -> NDArray[np.float64]:
        """The point the transit goes to for a push along `direction` (2,), shape (3,)."""
        return behind(obj, direction, self.behind)

    def in_place(self, eef: ArrayLike, obj: ArrayLike, direction: ArrayLike,
                 air: float = 0.02) -> bool:
        """The end-effector (3,) is at the object's (3,) height (within `air`) and behind
        it for a push along `direction` (2,): no transit needed."""
        e, o = np.asarray(eef, dtype=float), np.asarray(obj, dtype=float)
        u = np.asarray(direction, dtype=float)
        rel = o[:2] - e[:2]
        along = float(rel @ u)
        lateral = abs(float(rel[0] * u[1] - rel[1] * u[0]))
        return bool(e[2] <= o[2] + air and 0.0 < along <= self.behind + self.tolerance
                    and lateral <= self.lateral)

    def next(self, eef: ArrayLike, obj: ArrayLike, direction: ArrayLike,
             step: float) -> NDArray[np.float64] | None:
        """The next displacement (3,) of the transit, or None once there (m)."""
        return transit(eef, obj, self.target(obj, direction), step, self.lift,
                       self.clear, self.gain, self.tolerance)
